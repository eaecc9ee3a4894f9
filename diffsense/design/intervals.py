"""Requirements over intervals (semi-infinite constraints) for :class:`~diffsense.design.model.DesignModel`.

A requirement with ``over`` (:mod:`diffsense.design.spec.intervals`) holds at every point q of a
box of fixed parameters (every range from 50 m to 12 km, every target height ...). With v(x, q)
its output at design x and point q, and s = −1 for ``at_least`` and +1 for ``at_most``, the
requirement is

    max_q  s·(v(x, q) − b) / scale  ≤ 0.

The optimiser sees it by the **exchange method** (Hettich & Kortanek 1993, SIAM Review 35, §7;
Still, *Lectures on semi-infinite programming*, 2018, §4): the requirement holds at a finite set
of points, its *slots* — ``over_worst`` points found by the search at the current design plus
:data:`EXTRA_SLOTS` points found earlier (by earlier searches or by the dense re-check) — each one
constraint row s·(v(x, q_k) − b)/scale ≤ 0. The slots are inputs of the compiled programs
(:class:`~diffsense.design.inputs.DesignInputs`), never constants, so a new slot set reuses the
program. Between solves the search (:meth:`IntervalRequirements.search`) looks for the worst
points at the solver's answer; where it finds a value worse than the slots', those points become
the slots and the answer is solved again from where it stands. At convergence the slots hold the
worst points of the answer, so it meets the requirement at every point of the box; at a slot
that is a local minimiser of the margin the row's derivative is the envelope theorem's
(Danskin 1967), the derivative of the worst value.

The search (:func:`diffsense.optimize.semi_infinite.worst_points_grouped`) ranks the local minima
of the margin on a grid of the box (129 points for an interval, 33 per axis for a box of two,
17 for more; ``over_points`` overrides) together with the current slots, and polishes the
``over_worst`` best by values alone (no derivative of the chain: a small program), locating a
smooth minimiser to ~√ε relative and its value to round-off. Requirements of one case over the
same parameters, grid sizes and ``over_worst`` are searched together, each in its own box: one
batched chain evaluation computes all their outputs at once.

After a solve every interval requirement is re-checked on a dense grid of at least 10,001 points
(:meth:`IntervalRequirements.dense`, the grid of :func:`diffsense.optimize.semi_infinite.dense_points`)
independent of the search grid; the requirement counts as met only if the worse of the dense
grid's and the search's worst values meets it. The margin curve of a one-parameter interval
comes with the check.
"""

from __future__ import annotations

from typing import Dict, List, NamedTuple, Optional, Tuple

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.design.spec.limits import DENSE_POINTS  # the re-check's size, counted in the spec's work limit
from diffsense.design.spec.types import Requirement
from diffsense.optimize.semi_infinite import box, dense_points, worst_points_grouped
from diffsense.scene import compute

#: points of the margin curve kept in a requirement's row (JSON, report figures)
CURVE_POINTS = 1001
#: slots of a requirement beyond its ``over_worst`` search points: worst points found earlier
#: (by the dense re-check, or by a search at an earlier answer), kept as constraints
EXTRA_SLOTS = 1


def requirement_box(r: Requirement):
    """The search box of an interval requirement (its grid as the spec asks, else the default),
    a :class:`~diffsense.optimize.semi_infinite.Box` of NumPy arrays."""
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
    solver_worst_value: float  # the worst value the search finds
    n_points: int
    curve: Optional[Dict[str, list]]  # one-parameter intervals: {"parameter": [...], "value": [...]}


class Group(NamedTuple):
    """Interval requirements searched together: one case, the same parameters, grid sizes and
    number of worst points (static structure; their boxes may differ)."""

    case: str
    parameters: Tuple[str, ...]
    counts: Tuple[int, ...]
    over_worst: int
    members: Tuple[int, ...]


class IntervalRequirements:
    """The interval requirements of a spec: their slots, search and dense re-check as pure
    functions of the case parameters and the inputs θ (module docstring). Holds structure only;
    the boxes and slots are data (:meth:`box_data`, :meth:`initial_points`)."""

    def __init__(self, spec, sign):
        self.spec = spec
        self.sign = np.asarray(sign, dtype=float)
        self.indices: List[int] = [j for j, r in enumerate(spec.requirements) if r.over]
        self.boxes = {j: requirement_box(spec.requirements[j]) for j in self.indices}
        groups: Dict[tuple, List[int]] = {}
        for j in self.indices:
            r = spec.requirements[j]
            key = (r.case, tuple(iv.parameter for iv in r.over), self.boxes[j].counts, r.over_worst)
            groups.setdefault(key, []).append(j)
        self.groups: List[Group] = [Group(*key, tuple(js)) for key, js in groups.items()]
        self._group_of = {j: g for g in self.groups for j in g.members}

    def slots(self, j: int) -> int:
        """Constraint rows (slots) of requirement j."""
        return self.spec.requirements[j].over_worst + EXTRA_SLOTS

    def dim(self, j: int) -> int:
        return len(self.spec.requirements[j].over)

    def box_data(self, j: int):
        """(lower, upper, log) of requirement j's box (NumPy, (d,) each): inputs of the programs."""
        bx = self.boxes[j]
        return np.asarray(bx.lower, float), np.asarray(bx.upper, float), np.asarray(bx.log, bool)

    def initial_points(self, j: int) -> np.ndarray:
        """Slots before any search (K_j, d): the box's far corner (every slot the same point; a
        search replaces them before they are used as constraints)."""
        return np.tile(np.asarray(self.boxes[j].upper, float), (self.slots(j), 1))

    # --- traced -----------------------------------------------------------------------------
    def _at(self, group: Group, params: dict, q):
        """The outputs of the group's requirements (m,) with the ``over`` parameters set to q."""
        reqs = [self.spec.requirements[j] for j in group.members]
        p = dict(params)
        for k, name in enumerate(group.parameters):
            p[name] = q[k]
        values = compute(self.spec.scenes[group.case], p, frozenset(r.output for r in reqs)).values
        return jnp.stack([jnp.asarray(values[r.output], dtype=float) for r in reqs])

    def value_at(self, j: int, params: dict, q):
        """Requirement j's output with its ``over`` parameters set to q (d,); ``params``: the
        case's parameter dict."""
        r = self.spec.requirements[j]
        p = dict(params)
        for k, iv in enumerate(r.over):
            p[iv.parameter] = q[k]
        return jnp.asarray(compute(self.spec.scenes[r.case], p, frozenset({r.output})).values[r.output], dtype=float)

    def slot_values(self, params_by_case: dict, points) -> Dict[int, jnp.ndarray]:
        """Per interval requirement j, its output at each of its slots (K_j,) — ``points``: the
        slots per requirement (spec order of :attr:`indices`); one batched chain evaluation per
        group."""
        out = {}
        for g in self.groups:
            pts = jnp.concatenate([points[self.indices.index(j)] for j in g.members], axis=0)
            vals = jax.vmap(lambda q, g=g: self._at(g, params_by_case[g.case], q))(pts)  # (ΣK, m)
            start = 0
            for i, j in enumerate(g.members):
                k = self.slots(j)
                out[j] = vals[start:start + k, i]
                start += k
        return out

    def _boxes(self, group: Group, inputs):
        pos = [self.indices.index(j) for j in group.members]
        return tuple(jnp.stack([inputs.box[a][i] for i in pos]) for a in range(3))

    def search(self, params_by_case: dict, inputs) -> Dict[int, Tuple[jnp.ndarray, jnp.ndarray]]:
        """Per interval requirement j, ``(values (over_worst,), points (over_worst, d))``: the
        worst local minima of its margin over its box at these parameters, worst first, the
        current slots among the candidates (module docstring); values in the output's unit,
        without derivatives."""
        out = {}
        for g in self.groups:
            lower, upper, log = self._boxes(g, inputs)
            s = jnp.asarray([self.sign[j] for j in g.members])
            extra = jnp.stack([inputs.points[self.indices.index(j)] for j in g.members])

            def oriented(theta, q, g=g, s=s):
                return -s * self._at(g, theta, q)

            vals, pts = worst_points_grouped(oriented, params_by_case[g.case], lower, upper, log, g.counts,
                                             g.over_worst, extra=extra)
            for i, j in enumerate(g.members):
                out[j] = (-self.sign[j] * vals[i], pts[i])
        return out

    def dense(self, params_by_case: dict, inputs, n_points: int = DENSE_POINTS) -> Dict[int, Tuple[jnp.ndarray, jnp.ndarray]]:
        """Per interval requirement j, ``(points (P, d), values (P,))``: its output on the dense
        re-check grid of its box (module docstring)."""
        out = {}
        for g in self.groups:
            lower, upper, log = self._boxes(g, inputs)
            pts = jax.vmap(lambda lo, hi, lg: dense_points(lo, hi, lg, n_points))(lower, upper, log)  # (m, P, d)
            m, n, d = pts.shape
            vals = jax.vmap(lambda q, g=g: self._at(g, params_by_case[g.case], q))(pts.reshape(-1, d)).reshape(m, n, m)
            for i, j in enumerate(g.members):
                out[j] = (pts[i], vals[i, :, i])
        return out

    # --- host side --------------------------------------------------------------------------
    def check(self, j: int, points, values, search_value: float) -> IntervalCheck:
        """The dense re-check of requirement j from its dense grid ``points``/``values`` (NumPy,
        from :meth:`dense`) and the search's worst value at the same design: the reported worst
        value is the worse of the dense grid's and the search's (the search refines between grid
        points); the worst point is the dense grid's (to one cell of its grid: 1/10,000 of an
        interval)."""
        r = self.spec.requirements[j]
        s = self.sign[j]
        points = np.asarray(points, dtype=float)
        oriented = -s * np.asarray(values, dtype=float)
        bad = ~np.isfinite(oriented)
        k = int(np.argmax(bad)) if bad.any() else int(np.argmin(oriented))
        worst_v = float(-s * oriented[k])
        sv = float(search_value)
        if -s * sv < -s * worst_v:  # the search's refined minimum lies below the grid's
            worst_v = sv
        curve = None
        if points.shape[1] == 1:  # every k-th point of the dense grid, at most CURVE_POINTS
            step = max(1, -(-points.shape[0] // CURVE_POINTS))
            curve = {"parameter": [float(v) for v in points[::step, 0]],
                     "value": [float(v) for v in np.asarray(values, dtype=float)[::step]]}
        return IntervalCheck(worst_v, {iv.parameter: float(points[k, i]) for i, iv in enumerate(r.over)}, sv,
                             int(points.shape[0]), curve)


__all__ = ["IntervalRequirements", "IntervalCheck", "Group", "requirement_box", "DENSE_POINTS", "CURVE_POINTS",
           "EXTRA_SLOTS"]
