"""Lanes of a design model's solves: one compiled lane program, and the exchange rounds of the
interval requirements around it.

:class:`Runner` feeds lanes — starts, θ (:class:`~diffsense.design.inputs.SolveInputs`) and boxes
— to the model's lane program (:meth:`~diffsense.design.programs.Programs.lanes`) in calls of a
fixed number of lanes (:func:`lane_batch`, the last call padded by repeating its last lane with
its box pinned at its start, which the solver returns at once), so
every step of :func:`~diffsense.design.optimizer.optimize_design`, the canonical stage and the
linearisations it needs reuse one compilation. :meth:`Runner.settle` is the exchange method of
:mod:`diffsense.design.intervals`: after a solve the search looks for worse points at each
answer, and a lane whose answer misses one is solved again from there with the new slots.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import numpy as np

from diffsense.design.model import DesignModel
from diffsense.design.problem import variable_scales
from diffsense.design.programs import rows_of, stack, with_found_points
from diffsense.optimize import Problem, SolverOptions
from diffsense.optimize.batch import resolve_lockstep
from diffsense.optimize.distributed import solve_across_processes

#: lanes per call of the lane program when lanes run one after another (CPU)
LANE_BATCH = 8
#: solves of a lane after which its worst points are taken as found (exchange rounds)
SEARCH_ROUNDS = 4
#: a search value worse than the slots' by more than this (scaled units) moves the slots
SEARCH_TOL = 1e-9


def bounds_problem(model: DesignModel) -> Problem:
    """A problem with the model's box and scaling only (start points, integer neighbours, the
    on-bound test); it is never solved."""
    return Problem(lambda x, _: x[0], model.lower, model.upper, log_scale=model.log_scale, integer=model.integer,
                   names=list(model.variable_names))


def lane_batch(lockstep, first: int) -> int:
    """Lanes per call of the lane program: :data:`LANE_BATCH` when lanes run one after another
    (``lockstep`` 1, "auto" on CPU), else the first step's count (all in one vmap, or a multiple
    of the lockstep count)."""
    k = resolve_lockstep(lockstep)
    if k == 1:
        return LANE_BATCH
    if k is None:
        return first
    return int(np.ceil(first / k) * k)


class Lanes(NamedTuple):
    """Lanes of a step (NumPy; leading axis the lane): starts ``x`` (L, n), θ (a batch of
    :class:`SolveInputs`), boxes (L, n + 1) including t, and each lane's catalog combination."""

    x: np.ndarray
    theta: object
    lower: np.ndarray
    upper: np.ndarray
    combo: np.ndarray


class Runner:
    """Solves lanes of ``model`` through its lane program (:meth:`solve`) and settles their
    interval requirements' slots by the exchange method (:meth:`settle`)."""

    def __init__(self, model: DesignModel, options: SolverOptions, lockstep, first: int):
        self.model = model
        self.options = options
        self.batch = lane_batch(lockstep, first)
        self.program = model.programs.lanes(self.batch, options, resolve_lockstep(lockstep))
        self.scale = variable_scales(model)
        ineq = np.flatnonzero(~model.row_is_equality)
        #: per interval requirement, its rows' positions in a solve's inequality values g
        self.slot_rows = {j: np.flatnonzero(model.row_owner[ineq] == j) for j in model.intervals.indices}
        self.solves = 0

    def boxes(self, lower=None, upper=None, n: int = 1):
        """Boxes (n, n_var + 1) with t pinned at 0 (the model's box by default)."""
        m = self.model
        lo = np.broadcast_to(m.lower if lower is None else lower, (n, m.lower.size))
        hi = np.broadcast_to(m.upper if upper is None else upper, (n, m.upper.size))
        zeros = np.zeros((n, 1))
        return np.hstack([lo, zeros]), np.hstack([hi, zeros])

    def solve(self, lanes: Lanes, scale=None):
        """The :class:`~diffsense.optimize.Result` of every lane (NumPy; ``x`` without t when the
        lanes' starts have none), in calls of :attr:`batch` lanes; with several processes
        (``jax.distributed``) each solves its share (:func:`~diffsense.optimize.distributed.solve_across_processes`)."""
        n_var = self.model.lower.size
        n = lanes.x.shape[0]
        x0 = np.hstack([lanes.x, np.zeros((n, 1))]) if lanes.x.shape[1] == n_var else lanes.x
        scale = np.broadcast_to(self.scale if scale is None else scale, x0.shape)
        res = solve_across_processes(self.program, self.batch, x0, lanes.theta, lanes.lower, lanes.upper, scale,
                                     pin_padding=True)
        self.solves += n
        return res._replace(x=res.x[:, :-1]) if lanes.x.shape[1] == n_var else res

    def search_points(self, x, theta, combo):
        """θ with each lane's interval slots set by a search at its design ``x`` (L, n), and the
        search's results per lane."""
        m = self.model
        if not m.intervals.indices:
            return theta, [{} for _ in range(x.shape[0])]
        V = np.stack([m.design_values(xi, int(c)) for xi, c in zip(x, combo)])
        found = m.programs.search_rows(V, theta.design)
        designs = [with_found_points(m, rows_of(theta.design, i), f) for i, f in enumerate(found)]
        return theta._replace(design=stack(designs)), found

    def settle(self, lanes: Lanes, res=None):
        """Solve ``lanes`` (unless ``res`` is given) and re-solve each lane whose answer the
        search finds a worse point for than its slots hold, with the new points, from its
        answer, until none moves or :data:`SEARCH_ROUNDS` solves. Returns (lanes with the final
        θ, results)."""
        m = self.model
        if res is None:
            res = self.solve(lanes)
        if not m.intervals.indices:
            return lanes, res
        for _ in range(SEARCH_ROUNDS):
            theta, found = self.search_points(res.x, lanes.theta, lanes.combo)
            moved = np.zeros(res.x.shape[0], dtype=bool)
            limits = np.asarray(lanes.theta.limits)
            for i, f in enumerate(found):
                for j, (vals, _) in f.items():
                    worst = m.sign[j] * (vals[0] - limits[i, j]) / m.scales[j]
                    held = np.max(res.g[i, self.slot_rows[j]]) if self.slot_rows[j].size else -np.inf
                    if worst > held + SEARCH_TOL:
                        moved[i] = True
            lanes = lanes._replace(theta=theta)
            if not moved.any():
                break
            idx = np.flatnonzero(moved)
            again = Lanes(res.x[idx], rows_of(theta, idx), lanes.lower[idx], lanes.upper[idx], lanes.combo[idx])
            sub = self.solve(again)
            res = _replace_rows(res, idx, sub)
        return lanes, res


def _replace_rows(res, idx, sub):
    def put(a, b):
        a = np.array(a, copy=True)
        a[idx] = b
        return a
    return jax.tree_util.tree_map(put, res, sub)


def objective_scale(model: DesignModel) -> float:
    """The objective's normalisation: its magnitude at the spec's initial design with the first
    catalog combination (1 when that is 0 or not finite)."""
    values = model.programs.values_rows(model.design_values(model.initial, 0)[None, :])
    f0 = float(np.asarray(values[3])[0])
    return max(abs(f0), 1e-300) if np.isfinite(f0) and f0 != 0 else 1.0




__all__ = ["Runner", "Lanes", "lane_batch", "bounds_problem", "objective_scale", "LANE_BATCH", "SEARCH_ROUNDS",
           "SEARCH_TOL"]
