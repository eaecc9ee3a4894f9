"""Requirements over intervals (semi-infinite constraints) for :class:`~diffsense.design.model.DesignModel`.

A requirement with ``over`` (:mod:`diffsense.design.spec.intervals`) holds at every point q of a
box of fixed parameters (every range from 50 m to 12 km, every target height ...). With v(x, q)
its output at design x and point q, and s = −1 for ``at_least`` and +1 for ``at_most``, the
requirement is

    max_q  s·(v(x, q) − b) / scale  ≤ 0.

Its *worst value* is min_q v (``at_least``) or max_q v (``at_most``); the optimiser receives one
constraint row per worst point kept (``over_worst``, default 3: the lowest local minima of the
margin found by :func:`diffsense.optimize.semi_infinite.worst_points`, so that two multipath
nulls of nearly equal depth are both constraints), and derivatives with respect to x follow the
envelope theorem (the worst points are held fixed while differentiating).

After a solve every interval requirement is re-checked on a dense grid of at least 10,001 points
(:func:`diffsense.optimize.semi_infinite.dense_check`) independent of the search grid, its smallest
point polished by the same Newton refinement; the requirement counts as met only if the
re-checked worst value meets it. The margin curve of a one-parameter interval comes with the check.
"""

from __future__ import annotations

from typing import Dict, NamedTuple, Optional

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.design.spec.types import Requirement
from diffsense.optimize.semi_infinite import Box, box, dense_check, worst_points, worst_points_shared
from diffsense.scene import chain_for

#: points of the dense re-check of a requirement over an interval or box
DENSE_POINTS = 10_001
#: points of the margin curve kept in a requirement's row (JSON, report figures)
CURVE_POINTS = 1001


def requirement_box(r: Requirement) -> Box:
    """The search box of an interval requirement (its grid as the spec asks, else the default)."""
    lower = [iv.lower for iv in r.over]
    upper = [iv.upper for iv in r.over]
    log = None
    if any(iv.log is not None for iv in r.over):
        log = [iv.log if iv.log is not None else (iv.lower > 0 and iv.upper >= 10 * iv.lower) for iv in r.over]
    return box(lower, upper, counts=r.over_points, log=log)


class IntervalCheck(NamedTuple):
    """The dense re-check of one interval requirement at one design."""

    worst_value: float  # the requirement output at its worst point (output unit)
    worst_point: Dict[str, float]  # parameter -> value (its unit)
    solver_worst_value: float  # the worst value the solver's own search finds
    n_points: int
    curve: Optional[Dict[str, list]]  # one-parameter intervals: {"parameter": [...], "value": [...]}


class IntervalRequirements:
    """The interval requirements of a model: values at a point of their box, worst values and
    rows for the optimiser, and the dense re-check. ``parameters_of(x, combo)`` is the model's
    per-case parameter function."""

    def __init__(self, spec, parameters_of, sign, scales):
        self.spec = spec
        self.parameters_of = parameters_of
        self.indices = [j for j, r in enumerate(spec.requirements) if r.over]
        self.boxes = {j: requirement_box(spec.requirements[j]) for j in self.indices}
        self.sign = np.asarray(sign, dtype=float)
        self.scales = np.asarray(scales, dtype=float)
        self.extra: Dict[int, np.ndarray] = {}  # per requirement: candidate points found by re-checks
        self._dense = {}
        #: how the worst points are polished (:func:`~diffsense.optimize.semi_infinite.worst_points`):
        #: "newton" for the optimiser; the live explorer sets "zoom" (values only, quicker to compile)
        self.polish = "newton"
        #: with the "zoom" polish, whether worst values carry derivatives with respect to the
        #: design (False: one evaluation fewer per group; read when a function is traced)
        self.differentiable = True
        #: when True, worst values are NaN without a search (the live explorer's first program,
        #: which shows everything else before the searches are compiled; read when tracing)
        self.pending = False

    def value_at(self, j: int, params: dict, q):
        """Requirement j's output with its ``over`` parameters set to ``q`` (d,); ``params``: the
        case's parameter dict."""
        r = self.spec.requirements[j]
        p = dict(params)
        for k, iv in enumerate(r.over):
            p[iv.parameter] = q[k]
        scene = self.spec.scenes[r.case]
        return jnp.asarray(chain_for(scene).compute(scene, p, wanted=frozenset({r.output})).values[r.output],
                           dtype=float)

    def _oriented(self, j: int):
        """``fn((params,), q)`` = −s·v: smaller is worse (its minima are the worst points)."""
        s = self.sign[j]
        return lambda theta, q: -s * self.value_at(j, theta[0], q)

    def worst(self, j: int, params: dict):
        """``(values (over_worst,), points (over_worst, d))`` of requirement j: its output at the
        worst points found, worst first (derivatives by the envelope theorem)."""
        r = self.spec.requirements[j]
        vals, pts = worst_points(self._oriented(j), (params,), self.boxes[j], r.over_worst, extra=self.extra.get(j),
                                 polish=self.polish)
        return -self.sign[j] * vals, pts

    def worst_values(self, x, combo, params_by_case=None) -> Dict[int, jnp.ndarray]:
        """Per interval requirement, its worst value (min for at_least, max for at_most).

        With the "zoom" polish, requirements of one case over the same box are searched together
        (:meth:`_shared_worst`): one batched chain evaluation computes all their outputs."""
        if self.pending:
            return {j: jnp.asarray(jnp.nan) for j in self.indices}
        params = self.parameters_of(x, combo) if params_by_case is None else params_by_case
        if self.polish != "zoom":
            return {j: self.worst(j, params[self.spec.requirements[j].case])[0][0] for j in self.indices}
        out = {}
        for js in self._groups():
            p = params[self.spec.requirements[js[0]].case]
            if js[0] in self.extra:
                out[js[0]] = self.worst(js[0], p)[0][0]
            else:
                out.update(self._shared_worst(js, p))
        return out

    def _groups(self):
        """The interval requirements by (case, box, parameters, over_worst), spec order."""
        groups: Dict[tuple, list] = {}
        for j in self.indices:
            r, bx = self.spec.requirements[j], self.boxes[j]
            key = ("own", j) if j in self.extra else (
                r.case, tuple(iv.parameter for iv in r.over), tuple(bx.lower), tuple(bx.upper), tuple(bx.log),
                bx.counts, r.over_worst)
            groups.setdefault(key, []).append(j)
        return list(groups.values())

    def _values_together(self, js, params: dict, q):
        """The oriented values −s·v (smaller is worse) of requirements ``js`` (one case, one box)
        at point ``q``, from one chain evaluation computing all their outputs."""
        reqs = [self.spec.requirements[j] for j in js]
        p = dict(params)
        for k, iv in enumerate(reqs[0].over):
            p[iv.parameter] = q[k]
        scene = self.spec.scenes[reqs[0].case]
        values = chain_for(scene).compute(scene, p, wanted=frozenset(r.output for r in reqs)).values
        return jnp.stack([-self.sign[j] * jnp.asarray(values[r.output], dtype=float) for j, r in zip(js, reqs)])

    def _shared_worst(self, js, params: dict) -> Dict[int, jnp.ndarray]:
        vals, _ = worst_points_shared(lambda theta, q: self._values_together(js, theta[0], q), (params,),
                                      self.boxes[js[0]], len(js), self.spec.requirements[js[0]].over_worst,
                                      differentiable=self.differentiable)
        return {j: -self.sign[j] * vals[i, 0] for i, j in enumerate(js)}

    def rows(self, x, combo, limits) -> Dict[int, jnp.ndarray]:
        """Per interval requirement, its constraint rows s·(v_k − b)/scale (≤ 0 when met)."""
        params = self.parameters_of(x, combo)
        out = {}
        for j in self.indices:
            vals, _ = self.worst(j, params[self.spec.requirements[j].case])
            out[j] = self.sign[j] * (vals - limits[j]) / self.scales[j]
        return out

    def add_candidates(self, points: Dict[int, np.ndarray]) -> None:
        """Exchange step: add points a dense re-check found worse than the search's worst (per
        requirement, (d,) each) to the search's candidates. Functions traced before this keep
        their old candidates: rebuild the solver (and call :meth:`DesignModel.forget_compiled`)."""
        for j, p in points.items():
            p = np.asarray(p, dtype=float).reshape(1, -1)
            self.extra[j] = p if j not in self.extra else np.vstack([self.extra[j], p])
        self._dense = {}

    # --- after a solve -----------------------------------------------------------------------
    def _dense_fn(self, j: int):
        if j not in self._dense:
            case = self.spec.requirements[j].case

            def run(x, combo, pts):
                params = self.parameters_of(x, combo)[case]
                return jax.vmap(lambda q: self.value_at(j, params, q))(pts)
            self._dense[j] = jax.jit(run)
        return self._dense[j]

    def check(self, x, combo, search_values, n_points: int = DENSE_POINTS) -> Dict[int, IntervalCheck]:
        """The dense re-check of every interval requirement at design ``x``, catalog row ``combo``.
        ``search_values``: the requirement values of :meth:`DesignModel.requirement_values` at the
        same design (the solver's own worst values, spec order). The reported worst value is the
        worse of the dense grid's and the search's (the search refines between grid points); the
        worst point is the dense grid's (to one cell of its grid: 1/10,000 of an interval)."""
        x = jnp.asarray(x, dtype=float)
        combo = jnp.asarray(combo, dtype=float)
        out = {}
        for j in self.indices:
            r = self.spec.requirements[j]
            s = self.sign[j]
            fn = self._dense_fn(j)
            oriented = lambda pts, fn=fn: -s * np.asarray(fn(x, combo, jnp.asarray(pts, dtype=float)))  # noqa: E731
            chk = dense_check(oriented, self.boxes[j], n_points=n_points)
            sv = float(search_values[j])
            worst_v = -s * chk.worst_value
            if -s * sv < -s * worst_v:  # the search's refined minimum lies below the grid's
                worst_v = sv
            curve = None
            if chk.curve_p is not None:  # every k-th point of the dense grid, at most CURVE_POINTS
                step = max(1, -(-chk.curve_p.size // CURVE_POINTS))
                curve = {"parameter": [float(v) for v in chk.curve_p[::step]],
                         "value": [float(v) for v in -s * chk.curve_v[::step]]}
            out[j] = IntervalCheck(float(worst_v), {iv.parameter: float(chk.worst_point[k]) for k, iv in enumerate(r.over)},
                                   sv, chk.n_points, curve)
        return out
