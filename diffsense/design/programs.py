"""The compiled programs of a design model: one of each kind per spec structure.

Everything a command does with a spec goes through a few programs, each a pure function
of arrays (the spec's numbers are inputs, :mod:`diffsense.design.inputs`), traced once per
structure and kept on disk (:mod:`diffsense.optimize.programs`):

* ``check`` — each case's budget, the outputs the requirements and the objective read, the
  requirement rows and values and the objective, for :data:`EVAL_ROWS` input vectors at once
  (values only): the optimiser's checks, the load-time check of the spec, ``evaluate`` and
  ``optimize``'s printed record;
* ``outputs`` — the same with every output of every case (``--json``, the explorer's numbers);
* ``evaluation`` — every output with its directional derivatives along given tangents of the
  input vector (``jvp``): reports and the explorer's Jacobian read designs through it (values
  alone are a zero tangent, a Jacobian one row per input);
* ``search`` — the worst points of every interval requirement (:mod:`diffsense.design.intervals`)
  for :data:`SEARCH_ROWS` input vectors at once;
* ``dense`` — every interval requirement on its dense re-check grid, at one design;
* ``lanes`` — solves of the design problem (:mod:`diffsense.design.problem`), a batch of lanes
  per call, every step of the optimiser through it.

Each is compiled on first use, in a background thread (:meth:`Programs.start` begins
compilations early, so that two run on two cores). The host functions here pad every request
to the programs' fixed batch sizes.
"""

from __future__ import annotations

from typing import Dict, List, Optional, Tuple

import jax
import numpy as np

from diffsense.design.inputs import DesignInputs, SolveInputs, Stage
from diffsense.design.intervals import EXTRA_SLOTS, IntervalCheck
from diffsense.optimize.options import SolverOptions
from diffsense.optimize.programs import Program, compile_pool, register_serializable
from diffsense.sensors.chain import Budget, Evaluation

#: input vectors per call of the evaluation program
EVAL_ROWS = 8
#: spec structures whose programs a process keeps
SHARED_STRUCTURES = 8
_SHARED: Dict[str, Dict[tuple, Program]] = {}
#: input vectors per call of the search program
SEARCH_ROWS = 8
#: XLA options of the ``search`` and ``dense`` programs (:func:`diffsense.optimize.compile.compiler_options`):
#: optimisation level 0 compiles them ~1 s faster for ~1 ms more per call, a few tens of calls a
#: job (``benchmarks/bench_xla_options.py``); the other programs keep "optimized"
SEARCH_PRESET = "fast"

for _cls in (DesignInputs, SolveInputs, Stage, Evaluation, Budget):
    register_serializable(_cls)


def over_rows(fn):
    """``fn`` over the leading axis of its arguments, one row after another (``lax.map``): the
    rows are independent designs, and mapping them in sequence spares tracing the batched form
    of the chain (a vmap's batching rule processes the chain's whole program)."""
    def mapped(*args):
        return jax.lax.map(lambda a: fn(*a), args)
    return mapped


def stack(trees):
    """The pytrees ``trees`` stacked along a new leading axis (NumPy)."""
    return jax.tree_util.tree_map(lambda *a: np.stack([np.asarray(x) for x in a]), *trees)


def rows_of(tree, rows):
    """Rows ``rows`` of every leaf (NumPy)."""
    return jax.tree_util.tree_map(lambda a: np.asarray(a)[rows], tree)


def _padded(n: int, size: int):
    """Row indices of calls of ``size`` rows covering ``n`` rows (the last call repeats its last row)."""
    for start in range(0, n, size):
        rows = np.arange(start, min(start + size, n))
        yield rows, np.concatenate([rows, np.full(size - rows.size, rows[-1])])


class Programs:
    """The compiled programs of one :class:`~diffsense.design.model.DesignModel` (module
    docstring) and the host functions that feed them."""

    def __init__(self, model):
        self.model = model
        self.structure = repr(model.structure())
        # programs are shared by every model of this structure in the process (a spec read
        # again, the explorer's optimise and report buttons): the last few structures are kept
        self._programs: Dict[tuple, Program] = _SHARED.pop(self.structure, {})
        _SHARED[self.structure] = self._programs
        while len(_SHARED) > SHARED_STRUCTURES:
            _SHARED.pop(next(iter(_SHARED)))
        self._example = model.inputs()
        #: why the evaluation program (derivatives) cannot be built, when it cannot
        self.tangents_error: Optional[str] = None

    @property
    def example_inputs(self) -> DesignInputs:
        """The model's θ at the spec's numbers (:meth:`DesignModel.inputs`): the shapes every
        program is traced for."""
        return self._example

    # --- definitions -------------------------------------------------------------------------
    def _get(self, key: tuple, build) -> Program:
        if key not in self._programs:
            self._programs[key] = build()
        return self._programs[key]

    def evaluation(self) -> Program:
        """``fn(V (k, n), T (k, n), inputs (k, …)) -> (values, tangents)``: the model's
        :meth:`~diffsense.design.model.DesignModel.evaluation` (every output of every case) and
        the derivative of its requirement values and objective along each row of ``T``, k =
        :data:`EVAL_ROWS`. The evaluations' own tangents are zeros: the report differentiates
        only the requirements and the objective, so the tangents of the other outputs are dead
        code that XLA removes before optimising (a smaller program to compile)."""
        model = self.model

        def build():
            def differentiated(vv, inputs):
                evaluations, rows, req, obj = model.evaluation(vv, inputs)
                return jax.lax.stop_gradient(evaluations), jax.lax.stop_gradient(rows), req, obj

            def one(v, t, inputs):
                return jax.jvp(lambda vv: differentiated(vv, inputs), (v,), (t,))

            fn = over_rows(one)
            V = np.zeros((EVAL_ROWS, len(model.layout)))
            return Program("evaluation", fn, (V, V, stack([self._example] * EVAL_ROWS)), self.structure,
                           preset="optimized", pool=compile_pool(), packed=True)
        return self._get(("evaluation",), build)

    def check(self, full: bool = False) -> Program:
        """``fn(V (k, n), inputs (k, …)) -> (evaluations, rows, requirement values, objective)``:
        values without derivatives, k = :data:`EVAL_ROWS`; each case's budget and the outputs
        the requirements and objective read ("check"), or with ``full`` every output of every
        case ("outputs", what :meth:`evaluation` computes)."""
        model = self.model
        name = "outputs" if full else "check"

        def build():
            V = np.zeros((EVAL_ROWS, len(model.layout)))
            fn = over_rows(lambda v, inputs: model.evaluation(v, inputs, full))
            return Program(name, fn, (V, stack([self._example] * EVAL_ROWS)), self.structure, preset="optimized",
                           pool=compile_pool(), packed=True)
        return self._get((name,), build)

    def search(self) -> Program:
        """``fn(V (k, n), inputs (k, …)) -> per interval requirement (values (k, w), points
        (k, w, d))``, k = :data:`SEARCH_ROWS` (:meth:`IntervalRequirements.search`)."""
        model = self.model

        def build():
            def one(v, inputs):
                found = model.intervals.search(model.parameters(v), inputs)
                return tuple(found[j] for j in model.intervals.indices)

            V = np.zeros((SEARCH_ROWS, len(model.layout)))
            return Program("search", over_rows(one), (V, stack([self._example] * SEARCH_ROWS)), self.structure,
                           preset=SEARCH_PRESET, pool=compile_pool())
        return self._get(("search",), build)

    def dense(self) -> Program:
        """``fn(v (n,), inputs) -> per interval requirement (points (P, d), values (P,))``."""
        model = self.model

        def build():
            def fn(v, inputs):
                found = model.intervals.dense(model.parameters(v), inputs)
                return tuple(found[j] for j in model.intervals.indices)

            return Program("dense", fn, (np.zeros(len(model.layout)), self._example), self.structure,
                           preset=SEARCH_PRESET, pool=compile_pool())
        return self._get(("dense",), build)

    def lanes(self, batch: int, options: SolverOptions, lockstep) -> Program:
        """``fn(x0, θ, lower, upper, scale) -> Result`` for ``batch`` lanes of the design problem
        (:func:`diffsense.design.problem.design_problem`), θ a batch of :class:`SolveInputs`."""
        from diffsense.design.problem import design_problem
        from diffsense.optimize.lanes import lane_program

        model = self.model

        def build():
            program = lane_program(design_problem(model), options, lockstep)
            n = len(model.variable_names) + 1
            X = np.zeros((batch, n))
            theta = stack([model.solve_inputs(self._example, 0, model.limits, 1.0)] * batch)
            return Program("lanes", program, (X, theta, X, X, np.ones((batch, n))),
                           self.structure + repr((options, lockstep)), preset="optimized", pool=compile_pool())
        return self._get(("lanes", batch, options, lockstep), build)

    def start(self, *names: str) -> None:
        """Begin exporting and compiling the named programs (those the model has)."""
        for name in names:
            if name in ("search", "dense") and not self.model.intervals.indices:
                continue
            try:
                (self.check(True) if name == "outputs" else getattr(self, name)()).start()
            except NotImplementedError as exc:  # a derivative JAX lacks: values only (BatchEvaluator)
                if name != "evaluation":
                    raise
                self.tangents_error = f"{type(exc).__name__}: {exc}"

    # --- evaluation --------------------------------------------------------------------------
    def values_rows(self, V, inputs: Optional[DesignInputs] = None, per_row_inputs=None, full: bool = False):
        """``(evaluations, rows, requirement values, objective)`` (NumPy, leading axis: the rows
        of ``V``) at input vectors ``V`` by the check program (``full``: the outputs program)."""
        V = np.atleast_2d(np.asarray(V, dtype=float))
        base = self._example if inputs is None else inputs
        return self._rows(self.check(full), V, None, base, per_row_inputs)

    def evaluate_rows(self, V, T=None, inputs: Optional[DesignInputs] = None, per_row_inputs=None):
        """``(values, tangents)`` (NumPy, leading axis: the rows of ``V``) of the evaluation
        program at input vectors ``V`` (k, n) along tangents ``T`` (zeros when omitted), every
        row with ``inputs`` (default: the model's, :meth:`DesignModel.inputs`) or its own
        (``per_row_inputs``, a batch of k)."""
        V = np.atleast_2d(np.asarray(V, dtype=float))
        T = np.zeros_like(V) if T is None else np.atleast_2d(np.asarray(T, dtype=float))
        base = self._example if inputs is None else inputs
        return self._rows(self.evaluation(), V, T, base, per_row_inputs)

    @staticmethod
    def _rows(program, V, T, base, per_row_inputs):
        """``program`` over the rows of ``V`` (and ``T``) in calls of :data:`EVAL_ROWS` rows, all
        dispatched before any result is copied to the host; results concatenated (NumPy)."""
        shared = stack([base] * EVAL_ROWS) if per_row_inputs is None else None
        parts = []
        for _, padded in _padded(V.shape[0], EVAL_ROWS):
            th = shared if per_row_inputs is None else rows_of(per_row_inputs, padded)
            parts.append(program(V[padded], th) if T is None else program(V[padded], T[padded], th))
        # the programs here are packed and every output leads with the row axis; padding rows come last
        joined = program.unpack_calls(np.stack(jax.device_get(parts)))
        return jax.tree_util.tree_map(lambda a: a[:V.shape[0]], joined)

    def search_rows(self, V, per_row_inputs):
        """Per row of ``V`` and per interval requirement, the search's ``(values (w,), points
        (w, d))`` (NumPy): a list over rows of dicts keyed by requirement index."""
        V = np.atleast_2d(np.asarray(V, dtype=float))
        program = self.search()
        idx = self.model.intervals.indices
        out: List[dict] = []
        for rows, padded in _padded(V.shape[0], SEARCH_ROWS):
            res = program(V[padded], rows_of(per_row_inputs, padded))
            res = jax.tree_util.tree_map(np.asarray, res)
            for i in range(rows.size):
                out.append({j: (res[a][0][i], res[a][1][i]) for a, j in enumerate(idx)})
        return out

    def searched(self, values, inputs: DesignInputs) -> Tuple[DesignInputs, dict]:
        """``inputs`` with every interval requirement's slots set by a search at input vector
        ``values`` (:func:`merge_slots`), and the search's result."""
        if not self.model.intervals.indices:
            return inputs, {}
        found = self.search_rows(np.asarray(values)[None, :], stack([inputs]))[0]
        return with_found_points(self.model, inputs, found), found

    def evaluate_design(self, x, combo, full: bool = True):
        """``(evaluations, requirement values, raw objective, row values, inputs)`` at design
        ``x`` with catalog row ``combo`` (its values, then its cost): interval requirements at the
        worst points a search finds there; the objective in its minimised form (the spec's value
        times its sign); every output of every case (``full``) or those the requirements and
        objective read. NumPy results; ``inputs``: the θ used."""
        model = self.model
        values = np.asarray(model.layout.values, dtype=float).copy()
        values[model.layout.variable_slots] = np.asarray(x, dtype=float)
        values[model.layout.catalog_slots] = np.asarray(combo, dtype=float)[:-1]
        inputs = model.inputs(values=values)._replace(cost=np.asarray(float(np.asarray(combo)[-1])))
        inputs, _ = self.searched(values, inputs)
        ev, rows, req, obj = self.values_rows(values[None, :], inputs=inputs, full=full)
        first = lambda tree: jax.tree_util.tree_map(lambda a: a[0], tree)  # noqa: E731
        return first(ev), req[0], float(obj[0]) * model.spec.objective.sign, rows[0], inputs

    def dense_checks(self, values, inputs: DesignInputs, search_values) -> Dict[int, IntervalCheck]:
        """The dense re-check of every interval requirement at input vector ``values`` (its own
        grid, :meth:`IntervalRequirements.check`), against the search's worst ``search_values``
        (spec order)."""
        model = self.model
        if not model.intervals.indices:
            return {}
        res = jax.tree_util.tree_map(np.asarray, self.dense()(np.asarray(values, dtype=float), inputs))
        return {j: model.intervals.check(j, res[a][0], res[a][1], float(search_values[j]))
                for a, j in enumerate(model.intervals.indices)}

    def design_inputs(self, xs, combos) -> Tuple[np.ndarray, DesignInputs]:
        """Input vectors (k, n) of designs ``xs`` (k, n_var) with catalog combinations ``combos``
        (k,), and their θ (a batch) with every interval requirement's slots set by a search there."""
        model = self.model
        combos = np.asarray(combos, dtype=int)
        V = np.stack([model.design_values(x, int(c)) for x, c in zip(np.atleast_2d(xs), combos)])
        inputs = stack([model.inputs(int(c), values=v) for v, c in zip(V, combos)])
        if model.intervals.indices:
            found = self.search_rows(V, inputs)
            inputs = stack([with_found_points(model, rows_of(inputs, i), f) for i, f in enumerate(found)])
        return V, inputs

    def assess(self, xs, combos, tol: float = 1e-9, full: bool = False) -> List[Tuple[dict, List[dict], float]]:
        """Per design ``xs`` (k, n_var) with catalog combination ``combos`` (k,): ``(evaluations,
        requirement report, objective)`` — every case's evaluation (NumPy; its budget and the
        outputs the requirements and objective read, or every output with ``full``), the
        requirement rows (:meth:`DesignModel.requirement_rows`, interval requirements at the
        search's worst points and re-checked densely) and the objective as the spec states it."""
        V, inputs = self.design_inputs(xs, combos)
        ev, _, req, obj = self.values_rows(V, per_row_inputs=inputs, full=full)
        req = np.asarray(req)
        out = []
        for i in range(V.shape[0]):
            rows = self.model.requirement_rows(req[i], tol, self.dense_checks(V[i], rows_of(inputs, i), req[i]))
            out.append((jax.tree_util.tree_map(lambda a, i=i: np.asarray(a)[i], ev), rows, float(np.asarray(obj)[i])))
        return out

    def reports(self, xs, combos, tol: float = 1e-9) -> List[List[dict]]:
        """The requirement report of each design (:meth:`assess`)."""
        return [rows for _, rows, _ in self.assess(xs, combos, tol)]

    def checked_values(self, x, combo):
        """``(requirement values, dense checks)`` at design ``x`` with catalog row ``combo``."""
        _, req, _, _, inputs = self.evaluate_design(x, combo, full=False)
        values = np.asarray(inputs.values)
        return req, self.dense_checks(values, inputs, req)


def merge_slots(model, j: int, old, found) -> np.ndarray:
    """Requirement j's new slots: the search's worst points ``found`` (w, d) first, then the
    extra slots holding the old search points the search left (when they differ from every new
    one by more than 1e-9 of the box in u), most recent first, then the old extra slots (FIFO of
    :data:`EXTRA_SLOTS`)."""
    old = np.asarray(old, dtype=float)
    found = np.asarray(found, dtype=float)
    w = found.shape[0]
    lo, hi, log = model.intervals.box_data(j)
    to_u = lambda p: np.where(log, np.log(np.where(log, p, 1.0)), p)  # noqa: E731
    span = np.where(to_u(hi) > to_u(lo), to_u(hi) - to_u(lo), 1.0)
    new_u = to_u(found) / span
    left = [p for p in old[:w] if np.min(np.max(np.abs(new_u - to_u(p) / span), axis=-1)) > 1e-9]
    extras = (left + list(old[w:]))[:EXTRA_SLOTS]
    while len(extras) < EXTRA_SLOTS:
        extras.append(found[0])
    return np.vstack([found] + [np.asarray(e)[None, :] for e in extras])


def with_found_points(model, inputs: DesignInputs, found: dict) -> DesignInputs:
    """``inputs`` with the slots of each interval requirement in ``found`` (j -> (values,
    points), from a search) merged by :func:`merge_slots`."""
    pts = list(inputs.points)
    for a, j in enumerate(model.intervals.indices):
        if j in found:
            pts[a] = merge_slots(model, j, pts[a], found[j][1])
    return inputs._replace(points=tuple(pts))


def with_extra_point(model, inputs: DesignInputs, j: int, point) -> DesignInputs:
    """``inputs`` with ``point`` (d,) put first in requirement j's extra slots (the exchange step:
    a point the dense re-check found worse than the search's)."""
    a = model.intervals.indices.index(j)
    w = model.requirements[j].over_worst
    old = np.asarray(inputs.points[a], dtype=float)
    extras = [np.asarray(point, dtype=float)] + list(old[w:])
    pts = list(inputs.points)
    pts[a] = np.vstack([old[:w]] + [e[None, :] for e in extras[:EXTRA_SLOTS]])
    return inputs._replace(points=tuple(pts))


__all__ = ["Programs", "EVAL_ROWS", "SEARCH_ROWS", "stack", "rows_of", "merge_slots", "with_found_points",
           "with_extra_point"]

