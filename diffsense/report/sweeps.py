"""Data of the report's figures: link budgets, range and false-alarm sweeps, radar coverage.

Every sweep is a batch of input vectors through the report's compiled evaluator
(:class:`~diffsense.report.batch.BatchEvaluator`): one input (``range_m`` of a case, or
``pfa``) varies, every other input keeps its design value, and the chain is evaluated
exactly as for the design itself.
"""

from __future__ import annotations

import math
from typing import List, Optional

import numpy as np

from diffsense.design.model import DesignModel
from diffsense.physics.propagation.refraction import effective_earth_radius_m
from diffsense.report.inputs import Input
from diffsense.scene import chain_for

#: preference order of the output that carries "the" detection margin of a case
MARGIN_OUTPUTS = ("faded_snr_margin_db", "snr_margin_db", "signal_excess_db", "detection_margin_db")


def main_margin(model: DesignModel, case: Optional[str] = None) -> Optional[int]:
    """Index of the requirement on the main detection margin (of ``case`` if given), or None."""
    reqs = [(k, r) for k, r in enumerate(model.requirements) if case is None or r.case == case]
    for name in MARGIN_OUTPUTS:
        for k, r in reqs:
            if r.output == name:
                return k
    for k, r in reqs:
        if "margin" in r.output and r.unit == "dB":
            return k
    return None


def input_index(inputs: List[Input], param: str, case: str) -> Optional[int]:
    """Index of the input that sets ``param`` in ``case`` (None when it is not a numeric input)."""
    for k, inp in enumerate(inputs):
        if inp.param == param and case in inp.cases:
            return k
    return None


def budget_rows(evaluation) -> List[dict]:
    """The budget of one case's evaluation as rows {term, db, running_total_db}."""
    if evaluation.budget is None:
        return []
    total = 0.0
    rows = []
    for name, value in zip(evaluation.budget.names, evaluation.budget.values):
        total += float(np.asarray(value))
        rows.append({"term": name, "db": float(np.asarray(value)), "running_total_db": total})
    return rows


def sweep(batch, inputs: List[Input], k: int, grid) -> tuple:
    """Evaluate with input ``k`` set to each value of ``grid``; returns the batched values."""
    v0 = np.array([i.value for i in inputs], dtype=float)
    V = np.repeat(v0[None, :], len(grid), axis=0)
    V[:, k] = grid
    values, _ = batch(V)
    return values


def range_sweep(batch, model: DesignModel, inputs: List[Input], case: str, n: int = 481) -> dict:
    """SNR, required SNR, Pd and the main margin of ``case`` against range.

    The range grid runs linearly from R/40 to 2 R around the case's range R (stretched to
    cover the interval of ranges the main margin requirement holds over, to 1.25 times its far
    end), or further when the case still detects with Pd ≥ 0.5 at that far end E: then to 1.25
    times the range where Pd first falls below 0.5 on a geometric pre-sweep from E to 32 E (same
    batch shape, so no new compilation), so that the curves show where detection is lost. Clipped to the parameter's
    domain. ``threshold_db`` is the SNR at which the main margin requirement is exactly met:
    snr_db − margin + limit at each range; ``met_to_m`` the range where that requirement is
    last just met (:func:`last_crossing` of its margin), the one crossing both range figures
    mark. When that requirement holds over an interval of ranges (``over.range_m``),
    ``required_range_m`` is that interval (m): the figures shade it instead of marking the
    case's fixed range, which the requirement does not read.

    When the requirement states detection in another condition than the chain's ``snr_db``
    against its ``required_snr_db`` (a target in its deepest fade, ``faded_snr_margin_db``;
    a margin limit other than 0 dB; clutter in the margin), ``condition`` holds that condition:
    ``text`` (:func:`condition_text`), the SNR in it (``snr_db`` less the offset
    ``threshold_db`` − ``required_snr_db``: it meets the required SNR where the margin meets
    its limit) and the Pd in it (:func:`requirement_pd`; None without a ``pd`` output)."""
    k = input_index(inputs, "range_m", case)
    if k is None:
        raise LookupError(f"case '{case}' has no numeric range_m input")
    r0 = inputs[k].value
    lo = max(r0 / 40.0, inputs[k].lo or 0.0)
    r_max = inputs[k].hi or np.inf
    m = main_margin(model, case)
    span = None if m is None else next(((iv.lower, iv.upper) for iv in model.requirements[m].over
                                        if iv.parameter == "range_m"), None)
    if span is not None:
        lo, hi = min(lo, span[0]), min(max(2.0 * r0, 1.25 * span[1]), r_max)
    else:
        hi = min(2.0 * r0, r_max)
    if hi < r_max:
        far = np.geomspace(hi, min(32.0 * hi, r_max), n)
        pd_far = sweep(batch, inputs, k, far)[0][case].values.get("pd")
        if pd_far is not None and float(pd_far[0]) >= 0.5:
            lost = np.flatnonzero(np.isfinite(pd_far) & (np.asarray(pd_far) < 0.5))
            hi = min(1.25 * far[lost[0]], r_max) if lost.size else far[-1]
    grid = np.linspace(lo, hi, n)
    values = sweep(batch, inputs, k, grid)
    ev = values[0][case]
    out = {"range_m": grid, "design_range_m": r0, "outputs": {}}
    for name in ("snr_db", "required_snr_db", "pd"):
        if name in ev.values:
            out["outputs"][name] = np.asarray(ev.values[name])
    if m is not None:
        req = model.requirements[m]
        margin = np.asarray(ev.values[req.output])
        out["margin_requirement"] = {"name": req.name, "output": req.output, "limit": req.limit}
        if span is not None:
            out["required_range_m"] = span
        out["outputs"][req.output] = margin
        out["met_to_m"] = last_crossing(grid, (margin - req.limit) * (1.0 if req.sense == "at_least" else -1.0))
        if "snr_db" in ev.values:
            snr = np.asarray(ev.values["snr_db"])
            out["threshold_db"] = snr - margin + req.limit
            if "required_snr_db" in ev.values:
                offset = out["threshold_db"] - np.asarray(ev.values["required_snr_db"])
                if np.any(np.abs(offset[np.isfinite(offset)]) > 1e-6):
                    condition = {"text": condition_text(inputs, case, req), "snr_db": snr - offset, "pd": None}
                    if "pd" in ev.values:
                        condition["pd"] = requirement_pd(batch, inputs, case, grid, req, margin)
                    out["condition"] = condition
    return out


def last_crossing(grid, margin) -> Optional[float]:
    """The value of ``grid`` where ``margin`` (≥ 0: met) last falls from met to unmet, by linear
    interpolation between the grid points around it; None when it is met everywhere, nowhere,
    or still at the grid's end."""
    m = np.asarray(margin, dtype=float)
    ok = np.isfinite(m) & (m >= 0.0)
    if not ok.any() or ok.all():
        return None
    last = int(np.max(np.flatnonzero(ok)))
    if last + 1 >= m.size or not np.isfinite(m[last + 1]):
        return None
    t = m[last] / (m[last] - m[last + 1])
    return float(grid[last] + t * (grid[last + 1] - grid[last]))


def condition_text(inputs: List[Input], case: str, req) -> str:
    """The condition a margin requirement states the detection in, when it is not the chain's
    plain SNR against the required SNR, as a phrase to follow "SNR" or "Pd": the deepest fade
    of the target (``faded_snr_margin_db``), else the requirement's own margin output; a
    limit other than 0 dB is added."""
    limit = f" with a {req.limit:g} dB margin" if abs(req.limit) > 1e-12 else ""
    if req.output == "faded_snr_margin_db":
        k = input_index(inputs, "rcs_fade_db", case)
        fade = f"faded by {inputs[k].value:g} dB" if k is not None else "in its deepest fade"
        return f"of the target {fade}{limit}"
    return f"as {req.output} counts it{limit}"


def requirement_pd(batch, inputs: List[Input], case: str, grid, req, margin, tol_db: float = 1e-7,
                   steps: int = 8) -> Optional[np.ndarray]:
    """Pd at each range of ``grid`` in the condition the margin requirement ``req`` states
    (e.g. the target in its deepest fade): the required-Pd input ``pd`` at which the margin is
    exactly at its limit, so that it reaches the requirement's Pd exactly where the margin
    reaches its limit. ``margin``: the requirement's output on ``grid`` at the design's Pd.

    The margin falls as the required Pd rises (the required SNR grows), so each range has one
    root, sought on u = logit(pd). The margin at the case's own range against u, tabulated on
    ``len(grid)`` points, gives each range's first estimate and the slope of the steps: exact
    when Pd enters the margin only through the required SNR (m(R, pd) = g(R) − SNR_req(pd)),
    a secant otherwise. Each step evaluates the chain at every range; the rows still more than
    ``tol_db`` from the limit are stepped again (at most ``steps`` times), a row never within
    1e-4 dB is NaN. Pd is sought between 10·Pfa (and 1e-9) and 1 − 1e-9: a range where even the
    least Pd misses the margin gets the least, one where the largest meets it the largest.
    None when the case has no numeric ``pd``, ``pfa`` or ``range_m`` input."""
    kr, kp, kf = (input_index(inputs, name, case) for name in ("range_m", "pd", "pfa"))
    if kp is None or kf is None or kr is None:
        return None
    sign = 1.0 if req.sense == "at_least" else -1.0
    n = len(grid)
    V = np.repeat(np.array([i.value for i in inputs], dtype=float)[None, :], n, axis=0)

    def excess(ranges, p):
        """margin − limit (≥ 0: met) at ``ranges`` and required Pd ``p``."""
        V[:, kr] = ranges
        V[:, kp] = p
        values, _ = batch(V)
        return sign * (np.asarray(values[0][case].values[req.output], dtype=float) - req.limit)

    p_lo, p_hi = max(10.0 * inputs[kf].value, 1e-9), 1.0 - 1e-9
    u_tab = np.linspace(math.log(p_lo / (1.0 - p_lo)), math.log(p_hi / (1.0 - p_hi)), n)
    h = excess(np.full(n, inputs[kr].value), 1.0 / (1.0 + np.exp(-u_tab)))  # falls with u
    ok = np.isfinite(h)
    if ok.sum() < 2:
        return np.full(n, np.nan)
    u_tab, h = u_tab[ok], h[ok]
    slope_tab = np.gradient(h, u_tab)
    h0 = float(np.interp(math.log(inputs[kp].value / (1.0 - inputs[kp].value)), u_tab, h))
    target = h0 - sign * (np.asarray(margin, dtype=float) - req.limit)  # h(u) at the root, Pd apart
    u = np.interp(target, h[::-1], u_tab[::-1])
    pd = np.full(n, np.nan)
    pd[target > h[0]] = p_lo
    pd[target < h[-1]] = p_hi
    open_ = np.isfinite(target) & np.isnan(pd)
    near = np.full(n, np.nan)  # the last Pd within 1e-4 dB of the limit
    for _ in range(steps):
        if not open_.any():
            break
        p = 1.0 / (1.0 + np.exp(-u))
        f = excess(grid, p)
        pd = np.where(open_ & (np.abs(f) <= tol_db), p, pd)
        near = np.where(open_ & (np.abs(f) <= 1e-4), p, near)
        open_ &= ~(np.abs(f) <= tol_db)
        slope = np.interp(u, u_tab, slope_tab)
        step = np.where(open_ & (slope < 0.0) & np.isfinite(f), -f / np.where(slope < 0.0, slope, -1.0), 0.0)
        u = np.clip(u + step, u_tab[0], u_tab[-1])
    pd[open_] = near[open_]
    return pd


def roc_sweep(batch, inputs: List[Input], case: str, pd_levels=(0.9, 0.5, 0.1), n: int = 121) -> dict:
    """Pd of ``case`` against the false-alarm probability, at the design and at longer ranges.

    Pfa runs logarithmically over the chain's domain of ``pfa``; Pd is the chain's own ``pd``
    output (its detector and target statistics). Besides the design (its range and SNR), one
    curve is drawn at each range (searched from R to 100 R on a logarithmic grid) where the
    design's Pd falls to a level of ``pd_levels``, so that a design whose ROC is saturated at
    its own SNR still shows how detection degrades."""
    k = input_index(inputs, "pfa", case)
    if k is None:
        raise LookupError(f"case '{case}' has no numeric pfa input")
    lo = inputs[k].lo if inputs[k].lo and inputs[k].lo > 0 else 1e-15
    hi = inputs[k].hi if inputs[k].hi else 0.5
    grid = np.logspace(math.log10(lo), math.log10(hi), n)
    kr = input_index(inputs, "range_m", case)
    ranges = [inputs[kr].value] if kr is not None else [None]
    if kr is not None:
        r0 = inputs[kr].value
        r = np.geomspace(r0, min(100.0 * r0, inputs[kr].hi or np.inf), 241)
        ev = sweep(batch, inputs, kr, r)[0][case]
        pd_r = np.asarray(ev.values["pd"]) if "pd" in ev.values else np.full(r.shape, np.nan)
        for level in pd_levels:
            if abs(level - pd_r[0]) < 0.05 or level > pd_r[0]:
                continue
            above = np.flatnonzero(np.isfinite(pd_r) & (pd_r >= level))
            if above.size == 0 or above[-1] + 1 >= r.size:
                continue
            i = int(above[-1])
            t = (pd_r[i] - level) / (pd_r[i] - pd_r[i + 1])
            ranges.append(float(math.exp(math.log(r[i]) + t * (math.log(r[i + 1]) - math.log(r[i])))))
    v0 = np.array([i.value for i in inputs], dtype=float)
    V = np.repeat(v0[None, :], len(grid) * len(ranges), axis=0)
    V[:, k] = np.tile(grid, len(ranges))
    if kr is not None:
        V[:, kr] = np.repeat(np.asarray(ranges, dtype=float), len(grid))
    values, _ = batch(V)
    ev = values[0][case]
    if "pd" not in ev.values:
        raise LookupError(f"case '{case}' produces no pd output")
    pd = np.asarray(ev.values["pd"]).reshape(len(ranges), len(grid))
    snr = np.asarray(ev.values["snr_db"]).reshape(len(ranges), len(grid))[:, 0] if "snr_db" in ev.values else None
    curves = [{"range_m": r_, "snr_db": None if snr is None else float(snr[c]), "pd": pd[c]}
              for c, r_ in enumerate(ranges)]
    return {"pfa": grid, "curves": curves, "design_pfa": inputs[k].value}


def gaussian_pattern_db(off_axis_deg, beamwidth_deg):
    """One-way power pattern (dB, ≤ 0) of a Gaussian beam: −12.04 (θ/θ3)².

    G(θ)/G0 = exp(−4 ln 2 θ²/θ3²), i.e. −3.01 dB at θ = θ3/2; a main-lobe approximation
    (no sidelobes), accurate to about 1 dB down to the −10 dB points of a circular aperture
    (D. K. Barton, *Radar System Analysis and Modeling*, Artech House 2005, §3.4)."""
    t = np.asarray(off_axis_deg, dtype=float) / float(beamwidth_deg)
    return -4.0 * math.log(2.0) * 10.0 / math.log(10.0) * t * t


def height_over_effective_earth_m(range_m, elevation_deg, antenna_height_m=0.0, k_factor=4.0 / 3.0):
    """Height (m) of a point at slant range R and elevation θ over a spherical earth of
    effective radius k a (straight rays): h = sqrt(R² + (ka + h0)² + 2 R (ka + h0) sin θ) − ka
    (L. V. Blake, *Radar Range-Performance Analysis*, Artech House 1986, ch. 6, the geometry
    behind the range-height-angle chart)."""
    ae = float(effective_earth_radius_m(k_factor))
    r = np.asarray(range_m, dtype=float)
    a0 = ae + antenna_height_m
    s = np.sin(np.radians(elevation_deg))
    return np.sqrt(r * r + a0 * a0 + 2.0 * r * a0 * s) - ae


def blake_coverage(batch, model: DesignModel, inputs: List[Input], case: str, *, n_range: int = 481,
                   n_angle: int = 181) -> dict:
    """Detection coverage of a radar case in range and height over the 4/3 earth.

    Assumptions (stated in the report): the main margin requirement of the case defines
    detection (margin ≥ its limit); the antenna's elevation pattern is a Gaussian beam of the
    chain's elevation beamwidth with its boresight raised half a beamwidth above the horizon;
    the margin at elevation θ is the chain's margin at range R (all range-dependent terms:
    spreading, attenuation, clutter) plus the two-way pattern loss 2·P(θ − θ_b); antenna
    height 0 unless the case has ``antenna_height_m``; standard refraction k = 4/3."""
    m = main_margin(model, case)
    if m is None:
        raise LookupError(f"case '{case}' has no detection-margin requirement")
    req = model.requirements[m]
    k = input_index(inputs, "range_m", case)
    if k is None:
        raise LookupError(f"case '{case}' has no numeric range_m input")
    r0 = inputs[k].value
    lo = max(r0 / 100.0, inputs[k].lo or 1.0)
    hi = min(r0 * 100.0, inputs[k].hi or 1e7)
    grid = np.geomspace(lo, hi, n_range)
    values = sweep(batch, inputs, k, grid)
    ev = values[0][case]
    margin = np.asarray(ev.values[req.output]) - req.limit
    beam_key = "beamwidth_el_deg" if "beamwidth_el_deg" in ev.values else "beamwidth_deg"
    beamwidth = float(np.asarray(ev.values[beam_key])[0])
    h_index = input_index(inputs, "antenna_height_m", case)
    h0 = inputs[h_index].value if h_index is not None else 0.0
    boresight = 0.5 * beamwidth
    angles = np.linspace(boresight - 2.0 * beamwidth, boresight + 2.0 * beamwidth, n_angle)
    angles = angles[angles >= 0.0] if (angles >= 0.0).sum() > 10 else angles
    pattern = 2.0 * gaussian_pattern_db(angles - boresight, beamwidth)
    ranges = np.full(angles.shape, np.nan)
    for a, loss in enumerate(pattern):
        ok = np.isfinite(margin) & (margin + loss >= 0.0)
        if not ok.any():
            continue
        last = int(np.max(np.flatnonzero(ok)))
        if last + 1 < grid.size and np.isfinite(margin[last + 1]):
            m1, m2 = margin[last] + loss, margin[last + 1] + loss
            t = m1 / (m1 - m2) if m1 != m2 else 0.0
            ranges[a] = math.exp(math.log(grid[last]) + t * (math.log(grid[last + 1]) - math.log(grid[last])))
        else:
            ranges[a] = grid[last]
    return {
        "elevation_deg": angles,
        "range_m": ranges,
        "height_m": height_over_effective_earth_m(np.nan_to_num(ranges), angles, h0),
        "boresight_deg": boresight,
        "beamwidth_deg": beamwidth,
        "antenna_height_m": h0,
        "requirement": req.name,
        "output": req.output,
        "limit": req.limit,
        "design_range_m": r0,
        "range_grid_max_m": float(grid[-1]),
    }


def coverage_applies(scene) -> bool:
    """True when a range-height coverage chart over the 4/3 earth describes the scene, as its chain
    declares (:meth:`diffsense.sensors.chain.Chain.coverage_chart_reason`: a radar looking along
    the earth's surface through the atmosphere, not one looking down a shaft)."""
    return chain_for(scene).coverage_chart_reason(scene) is None


def coverage_skip_reason(scene) -> str:
    """Why the coverage chart is not drawn for ``scene`` (see :func:`coverage_applies`)."""
    return chain_for(scene).coverage_chart_reason(scene) or ""


__all__ = ["coverage_applies", "coverage_skip_reason", "MARGIN_OUTPUTS", "main_margin", "input_index", "budget_rows", "sweep", "range_sweep", "last_crossing",
           "condition_text", "requirement_pd", "roc_sweep",
           "gaussian_pattern_db", "height_over_effective_earth_m", "blake_coverage"]
