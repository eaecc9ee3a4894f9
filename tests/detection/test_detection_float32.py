"""float32 detection probability against the 30-digit mpmath reference (tests/reference).

The float32 values come from a child process with DIFFSENSE_X64=0 (``benchmarks/
float32_accuracy.py``, whose grid and reference computation this test reuses), so the rest of
the suite keeps float64. One child evaluates every point: Swerling 0-4 through the general
kernel and Swerling 0 also through the fast kernel for a single Pfa and N.
"""

import numpy as np

from benchmarks import float32_accuracy as f32

# Low-SNR points where Pd - Pfa is small but not negligible: the recursions start in a far tail
# of K there, and their start value underflowed float32 before (Pd came out as Pfa).
_LOW_SNR = [(sw, n, 1e-3, snr) for sw in (0, 1, 2, 3, 4) for n in (1.0, 10.0) for snr in (-30.0, -20.0, -12.0)]


def test_float32_pd_matches_mpmath_grid_and_low_snr():
    # One test, not several sharing a fixture: pytest-xdist would run the fixture (the child
    # process, most of the time of this file) once per worker.
    sw, n, pfa, snr = f32.grid()
    low = np.array(_LOW_SNR, dtype=float)
    low_sw, low_n, low_pfa, low_snr = low[:, 0].astype(int), low[:, 1], low[:, 2], low[:, 3]
    low_pfa = low_pfa.astype(np.float32).astype(float)
    all_sw = np.concatenate([sw, low_sw])
    args = (all_sw, np.concatenate([n, low_n]), np.concatenate([pfa, low_pfa]), np.concatenate([snr, low_snr]))
    want = f32.reference_pd(*args)
    general, fast = f32.evaluate_float32(*args)
    grid = np.arange(len(all_sw)) < len(sw)

    # Grid (Swerling 0-4, N 1/10/100, Pfa 1e-3/1e-6/1e-10, SNR -5...25 dB), general kernel.
    err = np.abs(general - want)
    mixtures = grid & (all_sw != 2)
    # Swerling 0, 1, 3, 4 (the Poisson / negative-binomial mixtures): measured <= 4e-6.
    assert np.max(err[mixtures]) <= 5e-6, np.max(err[mixtures])
    # Swerling 2 is Q(N, T/(1+S)) from jax.scipy.special.gammaincc, whose own float32 error is
    # 5.8e-6 at N = 100 (against mpmath): measured 7e-6.
    assert np.max(err[grid]) <= 1e-5, np.max(err[grid])

    # Swerling 0 through the fast kernel (one Pfa and N per call): measured 1.4e-6.
    m0 = grid & (all_sw == 0)
    assert np.max(np.abs(fast[m0] - want[m0])) <= 5e-6

    # Low SNR: Pd - Pfa is 6.9e-6 ... 1.8e-3 at these points. Measured relative error of
    # Pd - Pfa: <= 1e-5 for the mixtures, 2.4e-4 for Swerling 2 (gammaincc's float32 error of
    # 1.7e-9 on Pd ~ 1e-3). Before the start points were fitted to float32 the sum underflowed
    # at the mixture points and Pd - Pfa came out as 0 (relative error 1).
    low_pts = ~grid
    excess = want[low_pts] - low_pfa
    assert np.min(excess) > 1e-6
    for got in (general[low_pts], fast[low_pts]):
        ok = np.isfinite(got)  # the fast kernel has values at the Swerling-0 points only
        rel = np.abs((got - low_pfa) - excess)[ok] / excess[ok]
        assert np.max(rel) <= 1e-3, np.max(rel)
