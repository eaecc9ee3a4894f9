"""FFT weighting windows of an FMCW receiver: noise bandwidth and scalloping loss.

An FMCW radar digitises the beat signal over one sweep, weights it with a window w and takes an
N-point FFT; each bin is a filter of width f_s/N (book §11.12.4.8). The window lowers the range
sidelobes at the price of a wider main lobe and an SNR loss (book §11.10, Table 11.4; the
rectangular window is the matched filter, no loss). Two numbers describe a window here:

* the equivalent noise bandwidth in bins (Harris 1978, eq (11)), for a cosine-sum window
  w(u) = Σ_k a_k cos(2πku), u ∈ [−½, ½], in the continuous (large-N) limit

      ENBW = Σ w² / (Σ w)² · N = (a_0² + ½ Σ_{k≥1} a_k²) / a_0²,

  so that the noise in one bin is k T0 F · ENBW · f_s / N; a signal centred on the bin keeps its
  full power, so the SNR loss of the window (Harris's "processing loss") is 10 log10 ENBW and is
  charged once, through the noise bandwidth;
* the scalloping (straddle) loss, the drop of a signal half a bin off the bin centre,

      L_s = −20 log10( W(½) / W(0) ),  W(δ) = a_0 sinc δ + ½ Σ_{k≥1} a_k [sinc(δ − k) + sinc(δ + k)],

  with sinc x = sin(πx)/(πx), the window's continuous spectrum (an information output; the SNR
  is for a target in the bin centre, as in the book).

Values (Harris 1978, Table 1): rectangular ENBW 1.00 bin, L_s 3.92 dB; Hann 1.50, 1.42 dB;
Hamming (0.54/0.46) 1.36, 1.78 dB (these coefficients give 1.75 dB, the value computed here:
Harris's 1.78 does not follow from them); Blackman (0.42/0.5/0.08) 1.73, 1.10 dB. The book (§11.12.4.8)
widens the bin by 1.3 for its window; option ``window = "given"`` takes such a factor as the
parameter ``window_bandwidth_factor``.

The windows are static structure (a scene option): these numbers are Python floats.

Sources: F. J. Harris, "On the use of windows for harmonic analysis with the discrete Fourier
transform", Proc. IEEE 66(1), 51-83 (1978), eqs (11), Table 1; Brooker §11.10, Table 11.4.
"""

from __future__ import annotations

import math
from typing import Dict, Tuple

__all__ = ["WINDOW_COEFFICIENTS", "WINDOWS", "noise_bandwidth_bins", "scalloping_loss_db"]

#: cosine-sum coefficients (a_0, a_1, ...) of w(u) = Σ a_k cos(2πku), u ∈ [−½, ½] (Harris 1978)
WINDOW_COEFFICIENTS: Dict[str, Tuple[float, ...]] = {
    "rectangular": (1.0,),
    "hann": (0.5, 0.5),
    "hamming": (0.54, 0.46),
    "blackman": (0.42, 0.5, 0.08),
}

#: the values of the scene option ``window``; "given" reads ``window_bandwidth_factor``
WINDOWS = tuple(WINDOW_COEFFICIENTS) + ("given",)


def noise_bandwidth_bins(window: str) -> float:
    """Equivalent noise bandwidth of ``window`` in FFT bins, (a_0² + ½ Σ a_k²)/a_0² (large N).

    Source: Harris (1978) eq (11), Table 1 (Hann 1.50, Hamming 1.36, Blackman 1.73 bins).

    >>> noise_bandwidth_bins("hann"), round(noise_bandwidth_bins("hamming"), 4)
    (1.5, 1.3628)
    """
    a = WINDOW_COEFFICIENTS[window]
    return (a[0] ** 2 + 0.5 * sum(x * x for x in a[1:])) / a[0] ** 2


def _sinc(x: float) -> float:
    return 1.0 if x == 0.0 else math.sin(math.pi * x) / (math.pi * x)


def scalloping_loss_db(window: str) -> float:
    """Loss (dB) of a signal half a bin off the bin centre, −20 log10(W(½)/W(0)) (large N).

    Source: Harris (1978) Table 1 (rectangular 3.92, Hann 1.42, Blackman 1.10 dB; Hamming 1.78 dB
    there, 1.75 dB from the 0.54/0.46 coefficients, returned here).

    >>> round(scalloping_loss_db("rectangular"), 2), round(scalloping_loss_db("hann"), 2)
    (3.92, 1.42)
    """
    a = WINDOW_COEFFICIENTS[window]

    def spectrum(d):
        return a[0] * _sinc(d) + 0.5 * sum(ak * (_sinc(d - k) + _sinc(d + k)) for k, ak in enumerate(a) if k)

    return -20.0 * math.log10(spectrum(0.5) / spectrum(0.0))
