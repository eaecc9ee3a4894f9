"""The explorer's compiled programs: a design's evaluation, and its range sweeps, interval
curves and derivatives, all as functions of the report's input vector.

The input vector is :func:`diffsense.report.inputs.design_inputs` — every design variable,
every catalog parameter and every fixed parameter — so moving a slider, picking a catalog
option or typing a fixed value only changes the numbers fed to the same compiled programs; each
is traced and compiled once per spec (:class:`ExplorerProgram`). There are two main ones, so that the
page can show its numbers before the larger one is compiled (and a third, :meth:`ExplorerProgram.quick`,
the core without the interval requirements' searches, whose values it leaves NaN, so that the
page shows the budgets, outputs and point requirements before those searches are compiled):

* :meth:`ExplorerProgram.core` — ``evaluations``, ``requirements`` and ``objective`` of
  :func:`diffsense.report.inputs.input_evaluator` (every case with every output; interval
  requirements at their worst point, found with the value-only polish of
  :func:`diffsense.optimize.semi_infinite.worst_points_shared` — the requirements of one case
  over one box searched together by one batched chain evaluation, without the evaluation that
  carries derivatives — whose program compiles in a fraction of the time of the optimiser's
  Newton polish and agrees with it to round-off at a smooth minimum;
  the objective as the spec states it, for the catalog combination whose cost it is given);
* :meth:`ExplorerProgram.extras` — ``sweeps``: per case with a numeric ``range_m`` input, the
  outputs ``snr_db``, ``required_snr_db``, ``pd`` and the main detection margin
  (:func:`diffsense.report.sweeps.main_margin`) on a grid of ranges (m), from the chain alone
  (only those outputs are computed); ``intervals``: per one-parameter interval requirement, its
  output on :data:`CURVE_POINTS` points of its interval; ``jacobian``: d(requirement outputs,
  objective)/d(inputs), forward mode (rows: the requirements in spec order, then the objective;
  columns: the inputs).

The catalog cost enters the objective as ``weight · cost`` (:class:`~diffsense.design.spec.Objective`
term ``cost``); the programs are traced for the first catalog combination and the objective of
another combination k is shifted by ``weight · (cost_k − cost_0)``, which is exact because the
cost enters the weighted sum linearly and nothing else.
"""

from __future__ import annotations

import threading
from typing import Dict, List, Optional, Tuple

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.design.model import DesignModel
from diffsense.report.inputs import Input, case_parameters, input_evaluator
from diffsense.scene import chain_for
from diffsense.report.sweeps import input_index, main_margin

#: outputs drawn against range, when the case has them
SWEEP_OUTPUTS = ("snr_db", "required_snr_db", "pd")
#: points of every range sweep
SWEEP_POINTS = 121
#: points of every interval requirement's curve
CURVE_POINTS = 121


def range_grid(range_m: float, lower: Optional[float] = None, upper: Optional[float] = None,
               n: int = SWEEP_POINTS) -> np.ndarray:
    """Ranges (m) from R/40 to 2 R around the design range R, linear, clipped to the
    parameter's domain [lower, upper] (the report's range sweep grid)."""
    lo = max(range_m / 40.0, lower or 0.0)
    hi = min(2.0 * range_m, upper if upper is not None else np.inf)
    return np.linspace(lo, max(hi, lo * (1.0 + 1e-9)), n)


def interval_grid(bx, n: int = None) -> np.ndarray:
    """``n`` points (default :data:`CURVE_POINTS`) of a one-parameter box, log-spaced where its
    search grid is."""
    n = n or CURVE_POINTS
    lo, hi = float(bx.lower[0]), float(bx.upper[0])
    return np.geomspace(lo, hi, n) if bool(bx.log[0]) else np.linspace(lo, hi, n)


class ExplorerProgram:
    """The compiled :meth:`core` and :meth:`extras` of ``model`` at ``inputs`` (module docstring).

    ``sweep_cases``: case -> index of the ``range_m`` input it sweeps; ``grids`` holds one grid
    (m) per distinct index, in the order of :attr:`sweep_inputs`. ``interval_requirements``: the
    indices (spec order) of the one-parameter interval requirements, with their grids in
    :attr:`interval_grids`.
    """

    def __init__(self, model: DesignModel, inputs: List[Input]):
        self.model = model
        self.inputs = inputs
        spec = model.spec
        model.intervals.polish = "zoom"
        fn = input_evaluator(model, inputs, 0)
        self.sweep_cases: Dict[str, int] = {}
        for case in spec.scenes:
            k = input_index(inputs, "range_m", case)
            if k is not None:
                self.sweep_cases[case] = k
        self.sweep_inputs: List[int] = sorted(set(self.sweep_cases.values()))
        margins = {case: main_margin(model, case) for case in spec.scenes}
        self.margin_outputs: Dict[str, Optional[str]] = {
            case: (model.requirements[m].output if m is not None else None) for case, m in margins.items()}
        self.interval_requirements: List[int] = [j for j in model.intervals.indices
                                                 if model.intervals.boxes[j].dim == 1]
        self.interval_grids = {j: interval_grid(model.intervals.boxes[j]) for j in self.interval_requirements}
        self.extras_ready = False
        self._compiling = threading.Lock()

        def wanted(case):
            names = {n for n in SWEEP_OUTPUTS}
            if self.margin_outputs[case] is not None:
                names.add(self.margin_outputs[case])
            return frozenset(names)

        def swept(v, k, grid):
            out = {}
            for case, kk in self.sweep_cases.items():
                if kk != k:
                    continue
                scene = spec.scenes[case]

                def at(r, case=case, scene=scene):
                    p = dict(case_parameters(spec, inputs, v)[case], range_m=r)
                    return chain_for(scene).compute(scene, p, wanted=wanted(case)).values
                values = jax.vmap(at)(grid)
                out[case] = {n: values[n] for n in list(SWEEP_OUTPUTS) + [self.margin_outputs[case]]
                             if n is not None and n in values}
            return out

        def curves(v):
            params = case_parameters(spec, inputs, v)
            out = {}
            for j in self.interval_requirements:
                p = params[spec.requirements[j].case]
                grid = jnp.asarray(self.interval_grids[j])
                out[j] = jax.vmap(lambda q, j=j, p=p: model.intervals.value_at(j, p, q[None]))(grid)
            return out

        def stacked(v):
            _, req, obj = fn(v)
            return jnp.concatenate([jnp.reshape(req, (-1,)), jnp.reshape(obj, (1,))])

        def evaluated(v, cost_shift, flag: str, value: bool):
            # a switch of the interval searches, read while tracing (module docstring)
            old = getattr(model.intervals, flag)
            setattr(model.intervals, flag, value)
            try:
                evaluations, req, obj = fn(v)
            finally:
                setattr(model.intervals, flag, old)
            return {"evaluations": evaluations, "requirements": req, "objective": obj + cost_shift}

        # core: no derivatives (the Jacobian is in extras), so the searches skip the evaluation
        # that carries them; quick: the core without the interval searches (values NaN)
        core = lambda v, cost_shift: evaluated(v, cost_shift, "differentiable", False)
        quick = lambda v, cost_shift: evaluated(v, cost_shift, "pending", True)

        def extras(v, grids: Tuple):
            sweeps = {}
            for k, grid in zip(self.sweep_inputs, grids):
                sweeps.update(swept(v, k, grid))
            return {"sweeps": sweeps, "intervals": curves(v), "jacobian": jax.jacfwd(stacked)(v)}

        self._quick = jax.jit(quick)
        self._core = jax.jit(core)
        self._extras = jax.jit(extras)
        self.core_ready = False

    def quick(self, v, cost_shift: float) -> dict:
        """:meth:`core` with the interval requirements' values NaN (no search compiled)."""
        out = self._quick(jnp.asarray(v, dtype=float), jnp.asarray(cost_shift, dtype=float))
        return jax.tree_util.tree_map(np.asarray, out)

    def core(self, v, cost_shift: float) -> dict:
        """Evaluations, requirement values and objective at input vector ``v`` (NumPy arrays)."""
        return self._first_compiled("core_ready", self._core,
                                    (jnp.asarray(v, dtype=float), jnp.asarray(cost_shift, dtype=float)))

    def extras(self, v, grids) -> dict:
        """Sweeps, interval curves and Jacobian at ``v`` (NumPy arrays); compiles on first use."""
        return self._first_compiled("extras_ready", self._extras,
                                    (jnp.asarray(v, dtype=float), tuple(jnp.asarray(g, dtype=float) for g in grids)))

    def _first_compiled(self, ready: str, program, args) -> dict:
        """``program(*args)`` as NumPy arrays; until flag ``ready`` is set, under one lock, so that
        a program is compiled once whichever thread (a slider move, the page's loader) asks first."""
        if getattr(self, ready):
            out = program(*args)
        else:
            with self._compiling:
                out = jax.block_until_ready(program(*args))
                setattr(self, ready, True)
        return jax.tree_util.tree_map(np.asarray, out)

    def __call__(self, v, cost_shift: float, grids) -> dict:
        """Both programs' outputs at ``v``."""
        return {**self.core(v, cost_shift), **self.extras(v, grids)}


__all__ = ["ExplorerProgram", "range_grid", "interval_grid", "SWEEP_OUTPUTS", "SWEEP_POINTS", "CURVE_POINTS"]
