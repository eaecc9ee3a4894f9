"""The radar chain's detection stage: the required SNR (option ``detectability``), the detection
margin that combines noise, jamming and clutter, Pd, the book's pulse count, and the bracket of
the detection-range search.

Detectability (static option ``detectability``):

* ``"exact"`` — :func:`diffsense.detection.required_snr_db` (exact Swerling 0-4, real N).
  Noncoherent: required per-pulse SNR for N pulses; coherent: single-pulse value − 10 log10 N.
  The ``"linear"`` detector is evaluated with the square-law statistics: the two differ by
  less than 0.2 dB for all N (Marcum 1960; Skolnik 3rd ed. §2.6); the exact linear-law
  statistics are not in :mod:`diffsense.detection`.
* ``"book"`` — single-pulse exact value minus the book's postdetection integration gain
  8 log10 N (N^0.8 rule); the linear (SDLA) detector needs 7 more pulses for the same gain
  (8 log10 max(N − 7, 1)), book §8.16.13. Coherent integration: gain 10 log10 N.
  ``pd`` is then Pd(SNR + gain, Pfa, 1 pulse), consistent with the requirement.
* ``"given"`` — the per-pulse requirement is the parameter ``detectability_db`` (read from the
  book's charts, e.g. 15.2 + 8 − 15 = 8.2 dB in §9.9.1.1); no Pd model, so ``pd`` and the
  integration outputs are not produced.
* ``"shnidman"``, ``"albersheim"``, ``"barton"``, ``"chebyshev"`` — as ``"exact"``, with the requirement from the
  closed-form approximation ``required_snr_db(..., method=...)`` (Shnidman 2002: Swerling 0-4,
  0.1 ≤ Pd ≤ 0.99, 1e-9 ≤ Pfa ≤ 1e-3, N ≤ 100; Albersheim 1981: Swerling 0 only, 0.1 ≤ Pd ≤ 0.9,
  1e-7 ≤ Pfa ≤ 1e-3; Barton 2005: Swerling 0-4, 0.1 ≤ Pd ≤ 0.999, 1e-12 ≤ Pfa ≤ 1e-2, N ≤ 100;
  Chebyshev: an interpolant of the exact values within 0.005 dB, Swerling 0-4, 0.05 ≤ Pd ≤
  1 − 1e-6, 1e-15 ≤ Pfa ≤ 1e-2, N ≤ 1e4, what ``[options] fidelity = "fast"`` picks; NaN outside, and Albersheim with a fluctuating target is refused). Their errors against the
  exact value are in :mod:`diffsense.detection.required_snr` and :mod:`diffsense.detection.barton`.
  ``pd`` stays the exact Pd for N pulses: only the requirement is approximated.

Integration (static option ``integration``): ``"noncoherent"`` (square-law sum of N pulses),
``"coherent"`` (single-pulse requirement − 10 log10 N) or ``"binary"``: M-of-N binary integration,
each of the N = ``n_pulses`` pulses (at most 100) compared with its own threshold and a detection
declared when at least M = ``binary_m`` cross (:func:`diffsense.detection.required_snr_binary_db`
and :func:`diffsense.detection.pd_binary`: exact for Swerling 0-4, Swerling 1 and 3 one RCS draw
for the dwell; with ``detectability = "exact"`` only). A relaxed N or M is interpolated linearly
between the integers around it (bilinear), exact at integers.

Detection margin (dB): detection needs ``S/(N + J) ≥ SNR_req`` and ``S/C ≥ SCR_req``; the
smooth combined criterion

    m(R) = −10 log10( 10^((SNR_req − SJNR(R))/10) + 10^((SCR_req − SCR(R))/10) )

is S ≥ SNR_req (N + J) + SCR_req C: never optimistic, at most 3 dB pessimistic where both
limits coincide.
"""

from __future__ import annotations

from typing import NamedTuple, Optional

import jax.numpy as jnp
import numpy as np

from diffsense import detection as _det
from diffsense.errors import DomainError
from diffsense.numerics.checks import is_concrete
from diffsense.numerics.db import db10, power_sum_db
from diffsense.physics.propagation.refraction import radar_horizon_m
from diffsense.sensors.chain import needs
from diffsense.sensors.radar import equation as eq
from diffsense.sensors.radar.integer_counts import between_integer_counts
from diffsense.sensors.radar.structure import option

__all__ = ["check_binary_counts", "USES_REQUIRED_SNR", "Requirement", "required_snr", "detection_margin_db", "requirement_outputs",
           "pd_at", "pd_outputs", "range_bracket"]

#: outputs that depend on the required per-pulse SNR (an exact detectability solve)
USES_REQUIRED_SNR = ("required_snr_db", "snr_margin_db", "faded_snr_margin_db", "detection_margin_db",
                     "detection_range_m", "detection_range_found", "burn_through_range_m")
#: domain of diffsense.detection.pd (dB); Pd is 0 or 1 to float64 outside
_PD_SNR_DB = (-50.0, 80.0)
#: values of option ``detectability`` that solve the requirement for N pulses directly, each with
#: ``diffsense.detection.required_snr_db(..., method=value)``
SOLVED_METHODS = ("exact", "shnidman", "albersheim", "barton", "chebyshev")


class Requirement(NamedTuple):
    """What detection asks of the echo (dB); each entry ``None`` when no wanted output needs it."""

    per_pulse_db: Optional[jnp.ndarray]  # required per-pulse SNR
    integration_gain_db: Optional[jnp.ndarray]  # reduction of the requirement from 1 to N pulses
    single_pulse_db: Optional[jnp.ndarray]  # requirement for one pulse


def required_snr(scene, p, wanted=None) -> Requirement:
    """The :class:`Requirement` of option ``detectability`` (``wanted`` None: every output).

    The per-pulse requirement serves :data:`USES_REQUIRED_SNR`; the gain ``integration_gain_db``,
    ``integrated_snr_db`` and, outside exact noncoherent detectability, ``pd``; the single-pulse
    requirement ``pulses_needed``, and it enters the per-pulse one (book and coherent:
    req1 − gain) or the gain (exact noncoherent: req1 − req_N).
    """
    if option(scene, "detectability") == "given":
        return Requirement(p["detectability_db"], None, None)
    swerling = option(scene, "swerling")
    coherent = option(scene, "integration") == "coherent"
    n = p["n_pulses"]
    need_req = needs(wanted, *USES_REQUIRED_SNR)
    need_gain = needs(wanted, "integration_gain_db", "integrated_snr_db")
    method = option(scene, "detectability") if option(scene, "detectability") in SOLVED_METHODS else "exact"
    single = lambda: _det.required_snr_db(p["pd"], p["pfa"], jnp.ones_like(n), swerling, method=method)
    if option(scene, "integration") == "binary":
        reqn = _at_binary_counts(p, lambda nn, m: _det.required_snr_binary_db(p["pd"], p["pfa"], nn, m, swerling)) \
            if need_req or need_gain else None
        req1 = single() if need_gain else None
        return Requirement(reqn, req1 - reqn if need_gain else None, req1)
    if coherent or option(scene, "detectability") == "book":
        if coherent:
            gain = db10(n)
        else:
            n_eff = n - _det.BOOK_SDLA_EXTRA_PULSES if option(scene, "detector") == "linear" else n
            gain = _det.book_integration_gain_db(jnp.maximum(n_eff, 1.0))
        req1 = single() if need_req or needs(wanted, "pulses_needed") else None
        return Requirement(req1 - gain if need_req else None, gain, req1)
    # exact (or an approximation of it), noncoherent: the requirement for N pulses directly
    reqn = _det.required_snr_db(p["pd"], p["pfa"], n, swerling, method=method) if need_req or need_gain else None
    req1 = single() if need_gain else None
    return Requirement(reqn, req1 - reqn if need_gain else None, req1)


def check_binary_counts(scene, p):
    """With M-of-N integration, concrete ``binary_m`` and ``n_pulses`` must satisfy M ≤ N
    (DomainError naming both): at least M of N pulses cannot cross when fewer than M are sent."""
    if option(scene, "integration") != "binary":
        return
    m, n = p["binary_m"], p["n_pulses"]
    if not (is_concrete(m) and is_concrete(n)):
        return
    m_max, n_min = float(np.max(np.asarray(m))), float(np.min(np.asarray(n)))
    if m_max > n_min:
        raise DomainError(f"radar chain, integration='binary': binary_m = {m_max:g} exceeds n_pulses = {n_min:g}; "
                          "M-of-N detection needs M <= N (at least M of the N pulses must cross)")


def _at_binary_counts(p, value_at):
    """``value_at(N, M)`` of M-of-N binary integration at N = ``n_pulses`` and M = ``binary_m``,
    each interpolated linearly between the integers around it (bilinear in a relaxed N and M;
    exact at integers, :func:`between_integer_counts`)."""
    return between_integer_counts(
        lambda nn: between_integer_counts(lambda m: value_at(nn, m), p["binary_m"]), p["n_pulses"])


def detection_margin_db(required_snr_db, sjnr_db, required_scr_db=None, scr_db=None):
    """The combined detection margin m (dB) of the module docstring; without clutter
    (``scr_db`` None) it is SJNR − SNR_req."""
    if scr_db is None:
        return sjnr_db - required_snr_db
    return -power_sum_db(required_snr_db - sjnr_db, required_scr_db - scr_db)


def requirement_outputs(p, snr_db, required_snr_db, margin_at_range_db):
    """The required SNR and the margins at ``range_m`` (dB); the detection margin (which may need
    the clutter) when it was computed (``margin_at_range_db`` not None)."""
    values = {
        "required_snr_db": required_snr_db,
        "snr_margin_db": snr_db - required_snr_db,
        "faded_snr_margin_db": snr_db - p["rcs_fade_db"] - required_snr_db,
    }
    if margin_at_range_db is not None:
        values["detection_margin_db"] = margin_at_range_db
    return values


def pd_at(scene, p, sjnr_db, req: Requirement):
    """Pd for the per-pulse S/(N + J) ``sjnr_db`` (dB, any shape): the exact noncoherent series
    over ``n_pulses``, or the single-pulse Pd of the integrated SNR (SNR clipped to [-50, 80] dB,
    where Pd is 0 or 1 to float64)."""
    swerling = option(scene, "swerling")
    n = p["n_pulses"]
    if option(scene, "integration") == "binary":
        snr = jnp.clip(sjnr_db, *_PD_SNR_DB)
        return _at_binary_counts(p, lambda nn, m: _det.pd_binary(snr, p["pfa"], nn, m, swerling))
    if option(scene, "detectability") in SOLVED_METHODS and option(scene, "integration") == "noncoherent":
        return _det.pd(jnp.clip(sjnr_db, *_PD_SNR_DB), p["pfa"], n, swerling)
    return _det.pd(jnp.clip(sjnr_db + req.integration_gain_db, *_PD_SNR_DB), p["pfa"], jnp.ones_like(n), swerling)


def pd_outputs(scene, p, wanted, snr_db, sjnr_db, req: Requirement):
    """Pd against noise and jamming, the integration gain and, for the book's rule, the pulses
    needed in the deepest RCS fade designed for (``rcs_fade_db``); nothing for ``"given"``.
    ``sjnr_db`` is S/(N + J) at ``range_m`` (dB), needed only when ``pd`` is wanted."""
    values = {}
    if option(scene, "detectability") == "given":
        return values
    if needs(wanted, "pd"):
        values["pd"] = pd_at(scene, p, sjnr_db, req)
    if req.integration_gain_db is not None:
        values["integration_gain_db"] = req.integration_gain_db
        values["integrated_snr_db"] = snr_db + req.integration_gain_db
    book_noncoherent = option(scene, "detectability") == "book" and option(scene, "integration") == "noncoherent"
    if book_noncoherent and req.single_pulse_db is not None:
        needed = jnp.maximum(req.single_pulse_db - (snr_db - p["rcs_fade_db"]), 0.0)
        extra = _det.BOOK_SDLA_EXTRA_PULSES if option(scene, "detector") == "linear" else 0.0
        values["pulses_needed"] = 10.0 ** (needed / 8.0) + extra
    return values


def range_bracket(scene, p):
    """Bracket (m) of the detection-range search: [1 m, 10,000 km], above the antenna with sea
    clutter, and inside 0.99 × the radar horizon with multipath."""
    lo = jnp.asarray(eq.RANGE_SEARCH_M[0])
    hi = jnp.asarray(eq.RANGE_SEARCH_M[1])
    if scene.has("sea_clutter"):
        lo = jnp.maximum(lo, 1.0 + p["antenna_height_m"])
    if scene.has("multipath"):
        lo = jnp.maximum(lo, 1.0 + jnp.abs(p["antenna_height_m"] - p["target_height_m"]))
        hi = jnp.minimum(hi, 0.99 * radar_horizon_m(p["antenna_height_m"], p["target_height_m"]))
    return lo, hi
