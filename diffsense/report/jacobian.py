"""Jacobian of the requirement outputs with respect to every input, elasticities, and a
finite-difference check of the derivatives.

Derivatives come from forward-mode automatic differentiation (``jax.jvp`` along unit
tangents, the columns of ``jax.jacfwd``) through the complete chain evaluation of every case
(:mod:`diffsense.report.batch`).

Elasticity
----------
Each quantity is measured on a logarithmic scale: a dB quantity (unit ``dB``, ``dBm``, ...)
by its value in dB, a positive linear quantity q by 10 log10 q. The elasticity of output y
with respect to input u is

    E = d y_dB / d u_dB,       y_dB = y (dB output) or 10 log10 y,  u_dB likewise,

so for two linear quantities E = (u / y) ∂y/∂u = d ln y / d ln u (% per %), for two dB
quantities E = ∂y/∂u (dB per dB), and mixed pairs are dB per dB of the linear quantity's
10 log10. A power-law relation y ∝ u^a has E = a everywhere. E is not defined (reported as
``None``) where a linear quantity is not positive or has no ratio scale (degrees Celsius).

A probability of detection near 1 is measured by its *miss probability* 1 − Pd in dB,
10 log10(1 − Pd): dB per dB of Pd itself is not meaningful there (Pd 0.95 → 0.96 is 0.05 dB of
Pd but a fifth less missed detections), while halving the miss probability (−3 dB) is the step
an engineer asks about. An input or output named ``pd`` (:data:`MISS_MEASURED`) is measured so,
and the report says so next to it.

Finite-difference check
-----------------------
Each input is stepped in its own measure (ln u for positive ratio inputs, u itself otherwise)
with the fourth-order central stencil

    f'(u) ≈ [f(u − 2h) − 8 f(u − h) + 8 f(u + h) − f(u + 2h)] / (12 h),      h = 1e-3 (ln u)
                                                                             or 1e-3 max(1, |u|),

truncation error h⁴ f⁽⁵⁾/30. An entry is compared (relative difference |FD − AD| / max(|FD|, |AD|))
when the output changes by more than 1e-6 max(1, |y|) over the step (below that, rounding
in the chain — dB terms of 200+ dB cancel to a margin near 0 — dominates the difference).
An entry is flagged *not smooth* when the one-sided slopes (f(u+h) − f(u))/h and
(f(u) − f(u−h))/h differ by more than 2 % (a kink within ±h: a table breakpoint, a clip);
an input whose stencil would leave its documented domain is differenced one-sidedly
(second order) and reported separately.
"""

from __future__ import annotations

import math
from typing import List, Optional

import numpy as np

from diffsense.report.inputs import Input

_LN10_10 = math.log(10.0) / 10.0
_NON_RATIO_UNITS = {"degC", "degF", "celsius", "fahrenheit", "degree_Celsius", "degree_Fahrenheit"}
FD_STEP = 1e-3
RESOLUTION = 1e-6
KINK_TOLERANCE = 2e-2


def is_db_unit(unit: str) -> bool:
    """True for decibel levels and ratios (dB, dBm, dBW, dBsm, dBi), not for dB/m or dB/km."""
    return unit.startswith("dB") and "/" not in unit


def _is_ratio(unit: str, value: float) -> bool:
    return (not is_db_unit(unit)) and unit not in _NON_RATIO_UNITS and np.isfinite(value) and value > 0


#: quantities (base names, without a case prefix) measured by their miss probability 1 − p in dB
MISS_MEASURED = frozenset({"pd"})


def miss_measured(name: Optional[str], value: float) -> bool:
    """True for a probability of detection (``name`` in :data:`MISS_MEASURED`, after any
    ``case.`` prefix) strictly between 0 and 1: measured as 10 log10(1 − p).

    >>> miss_measured("main.pd", 0.95), miss_measured("pfa", 1e-6), miss_measured("pd", 1.0)
    (True, False, False)
    """
    if not name:
        return False
    return name.rsplit(".", 1)[-1] in MISS_MEASURED and np.isfinite(value) and 0.0 < value < 1.0


def measure_factor(unit: str, value: float, name: Optional[str] = None) -> Optional[float]:
    """d(quantity_dB)/d(quantity): 1 for dB units, 10/(ln 10 · q) for positive ratio quantities,
    −10/(ln 10 · (1 − p)) for a probability of detection ``name`` (:func:`miss_measured`),
    ``None`` where no dB measure exists.

    >>> round(measure_factor("1", 0.9, "pd"), 4), round(measure_factor("1", 0.9), 4)
    (-43.4294, 4.8254)
    """
    if miss_measured(name, value):
        return -1.0 / (_LN10_10 * (1.0 - value))
    if is_db_unit(unit):
        return 1.0
    if _is_ratio(unit, value):
        return 1.0 / (_LN10_10 * value)
    return None


def elasticity_matrix(derivative, out_units, out_values, in_units, in_values, out_names=None, in_names=None):
    """Elasticities E[i, j] = d y_i,dB / d u_j,dB (module docstring); NaN where undefined.
    ``out_names``/``in_names``: the quantities' names, so that a probability of detection is
    measured by its miss probability (:func:`miss_measured`)."""
    d = np.asarray(derivative, dtype=float)
    e = np.full(d.shape, np.nan)
    out_names = out_names or [None] * len(out_units)
    in_names = in_names or [None] * len(in_units)
    for i, (ou, ov, on) in enumerate(zip(out_units, out_values, out_names)):
        fo = measure_factor(ou, ov, on)
        if fo is None:
            continue
        for j, (iu, iv, inn) in enumerate(zip(in_units, in_values, in_names)):
            fi = measure_factor(iu, iv, inn)
            if fi is None:
                continue
            e[i, j] = fo * d[i, j] / fi
    return e


def _step(inp: Input):
    """(log_step, h): step in ln u for positive ratio inputs, else absolute."""
    if _is_ratio(inp.unit, inp.value):
        return True, FD_STEP
    return False, FD_STEP * max(1.0, abs(inp.value))


def _point(inp: Input, log_step: bool, k: float, h: float) -> float:
    return inp.value * math.exp(k * h) if log_step else inp.value + k * h


def _inside(inp: Input, value: float) -> bool:
    return (inp.lo is None or value >= inp.lo) and (inp.hi is None or value <= inp.hi)


def finite_difference_rows(inputs: List[Input]) -> tuple:
    """Input rows of the stencil: row 0 the design, then for input j the points at
    k = −2, −1, +1, +2 steps (rows 1 + 4j ... 4 + 4j). Returns (rows, plan) with plan[j] =
    (log_step, h, mode) and mode "central", "forward" or "backward" (domain edge)."""
    v0 = np.array([i.value for i in inputs], dtype=float)
    rows = [v0]
    plan = []
    for j, inp in enumerate(inputs):
        log_step, h = _step(inp)
        pts = {k: _point(inp, log_step, k, h) for k in (-2, -1, 1, 2)}
        if all(_inside(inp, p) for p in pts.values()):
            mode, ks = "central", (-2, -1, 1, 2)
        elif all(_inside(inp, pts[k]) for k in (1, 2)):
            mode, ks = "forward", (1, 2, 1, 2)
        elif all(_inside(inp, pts[k]) for k in (-1, -2)):
            mode, ks = "backward", (-1, -2, -1, -2)
        else:
            mode, ks = "central", (-2, -1, 1, 2)
        for k in ks:
            r = v0.copy()
            r[j] = _point(inp, log_step, k, h)
            rows.append(r)
        plan.append((log_step, h, mode))
    return np.array(rows), plan


def finite_difference_check(inputs: List[Input], plan, f_rows, derivative, out_values) -> dict:
    """Compare AD ``derivative`` (outputs × inputs) with the stencil values ``f_rows`` (rows × outputs).

    Returns ``fd`` (finite-difference derivative, NaN where not computable), ``rel_diff``
    (NaN where not compared), ``status`` per entry ("compared", "below_resolution",
    "not_smooth", "one_sided", "not_finite") and ``max_rel_diff`` over the compared entries."""
    d = np.asarray(derivative, dtype=float)
    f = np.asarray(f_rows, dtype=float)
    f0 = f[0]
    n_out, n_in = d.shape
    fd = np.full(d.shape, np.nan)
    rel = np.full(d.shape, np.nan)
    status = np.full(d.shape, "compared", dtype=object)
    one_sided_rel = np.full(d.shape, np.nan)
    for j, inp in enumerate(inputs):
        log_step, h, mode = plan[j]
        block = f[1 + 4 * j: 5 + 4 * j]  # k-ordered as built
        du_dv = 1.0 / inp.value if log_step else 1.0
        if mode == "central":
            fm2, fm1, fp1, fp2 = block
            slope_u = (fm2 - 8.0 * fm1 + 8.0 * fp1 - fp2) / (12.0 * h)
            fwd = (fp1 - f0) / h
            bwd = (f0 - fm1) / h
        else:
            s = 1.0 if mode == "forward" else -1.0
            f1, f2 = block[0], block[1]
            slope_u = s * (-3.0 * f0 + 4.0 * f1 - f2) / (2.0 * h)
            fwd = bwd = slope_u
        fd[:, j] = slope_u * du_dv
        for i in range(n_out):
            ad_u = d[i, j] / du_dv
            scale = RESOLUTION * max(1.0, abs(f0[i]))
            values = np.concatenate([block[:, i], [f0[i]]])
            if not (np.all(np.isfinite(values)) and np.isfinite(d[i, j])):
                status[i, j] = "not_finite"
                continue
            if max(abs(slope_u[i]), abs(ad_u)) * h <= scale:
                status[i, j] = "below_resolution"
                continue
            r = abs(slope_u[i] - ad_u) / max(abs(slope_u[i]), abs(ad_u))
            if mode != "central":
                status[i, j] = "one_sided"
                one_sided_rel[i, j] = r
                continue
            if abs(fwd[i] - bwd[i]) > KINK_TOLERANCE * max(abs(fwd[i]), abs(bwd[i])) and abs(fwd[i] - bwd[i]) * h > scale:
                status[i, j] = "not_smooth"
                continue
            rel[i, j] = r
    compared = status == "compared"
    return {
        "fd": fd,
        "rel_diff": rel,
        "status": status,
        "one_sided_rel_diff": one_sided_rel,
        "max_rel_diff": float(np.nanmax(rel)) if compared.any() else None,
        "n_compared": int(compared.sum()),
        "n_below_resolution": int((status == "below_resolution").sum()),
        "not_smooth": [(i, j) for i, j in zip(*np.nonzero(status == "not_smooth"))],
        "one_sided": [(i, j) for i, j in zip(*np.nonzero(status == "one_sided"))],
        "not_finite": [(i, j) for i, j in zip(*np.nonzero(status == "not_finite"))],
        "step": FD_STEP,
        "resolution": RESOLUTION,
    }


def jacobian_section(batch, inputs: List[Input], outputs: List[dict]) -> dict:
    """Derivatives, elasticities and the finite-difference check of the report outputs.

    ``batch``: a :class:`~diffsense.report.batch.BatchEvaluator` over ``inputs``; ``outputs``:
    one dict per requirement (``unit``) followed by one for the objective, in the order of
    ``(requirement_values, objective)``. Returns NumPy arrays (outputs × inputs)."""
    v0 = np.array([i.value for i in inputs], dtype=float)
    n = len(inputs)

    def stacked(values):
        _, req, obj = values
        return np.concatenate([np.asarray(req).reshape(req.shape[0], -1), np.asarray(obj).reshape(-1, 1)], axis=1)

    rows, plan = finite_difference_rows(inputs)
    section = {"autodiff": batch.tangents_available, "autodiff_error": batch.tangents_error}
    if batch.tangents_available:
        values, tangents = batch(np.repeat(v0[None, :], n, axis=0), np.eye(n))
        derivative = stacked(tangents).T  # (outputs, inputs)
    else:
        derivative = None
    f_values, _ = batch(rows)
    f_rows = stacked(f_values)
    out_values = f_rows[0]
    if derivative is None:
        check = finite_difference_check(inputs, plan, f_rows, np.zeros((f_rows.shape[1], n)), out_values)
        derivative = check["fd"]
        check = {"max_rel_diff": None, "n_compared": 0, "status": None, "fd": check["fd"],
                 "reason": "automatic differentiation unavailable; the derivatives shown are finite differences"}
    else:
        check = finite_difference_check(inputs, plan, f_rows, derivative, out_values)
    section.update(
        derivative=derivative,
        values=out_values,
        elasticity=elasticity_matrix(derivative, [o["unit"] for o in outputs], out_values,
                                     [i.unit for i in inputs], [i.value for i in inputs],
                                     [o.get("output") for o in outputs], [i.param for i in inputs]),
        fd_check=check,
    )
    return section


__all__ = ["jacobian_section", "is_db_unit", "measure_factor", "miss_measured", "MISS_MEASURED", "elasticity_matrix", "finite_difference_rows",
           "finite_difference_check", "FD_STEP"]
