"""The explorer's numbers from the design model's compiled programs: a design's evaluation, its
range sweeps, interval curves and derivatives, all as functions of the input vector.

The input vector is the design model's (:mod:`diffsense.design.layout`) — every design variable,
every catalog parameter and every fixed parameter — so moving a slider, picking a catalog option
or typing a fixed value only changes the numbers fed to the same compiled programs, the ones
``diffsense evaluate``, ``optimize`` and ``report`` use for the same spec
(:mod:`diffsense.design.programs`, kept on disk between runs):

* :meth:`ExplorerProgram.quick` — the *check* program (each case's budget and the outputs the
  requirements and the objective read, the requirements, the objective: the smallest program of
  a spec, compiled first) with the interval requirements' values left NaN ("pending"), so that
  the page shows its numbers before the other programs are compiled;
* :meth:`ExplorerProgram.core` — the interval requirements' worst points by the *search*
  program, then the *outputs* program (every output of every case) at them;
* :meth:`ExplorerProgram.extras` — ``sweeps``: per case with a numeric ``range_m`` input, the
  outputs ``snr_db``, ``required_snr_db``, ``pd`` and the main detection margin
  (:func:`diffsense.report.sweeps.main_margin`) on a grid of ranges (m); ``intervals``: per
  one-parameter interval requirement, its output on :data:`CURVE_POINTS` points of its
  interval; ``jacobian``: d(requirement outputs, objective)/d(inputs) in forward mode (rows:
  the requirements in spec order, then the objective; columns: the inputs) — all by one call of
  the explorer's own *extras* program (only the outputs the curves draw are computed, every
  row in one vmap), compiled in the background after the page is shown and kept on disk.
"""

from __future__ import annotations

import threading
from typing import Dict, List, Optional

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.design.model import DesignModel
from diffsense.design.programs import with_found_points
from diffsense.design.layout import Input
from diffsense.optimize.programs import Program, compile_pool
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
    """The explorer's evaluations of ``model`` at input vectors (module docstring).

    ``sweep_cases``: case -> index of the ``range_m`` input it sweeps; ``grids`` holds one grid
    (m) per distinct index, in the order of :attr:`sweep_inputs`. ``interval_requirements``: the
    indices (spec order) of the one-parameter interval requirements, with their grids in
    :attr:`interval_grids` and the input each one varies in :attr:`interval_inputs`.
    """

    def __init__(self, model: DesignModel, inputs: List[Input]):
        self.model = model
        self.inputs = inputs
        spec = model.spec
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
        self.interval_inputs = {j: model.layout.slot(model.requirements[j].over[0].parameter,
                                                     model.requirements[j].case)
                                for j in self.interval_requirements}
        self.core_ready = False
        self.extras_ready = False
        self._compiling = threading.Lock()
        self._points = None  # the interval slots of the last search (its worst points)
        self._extras = None  # (block sizes, the extras' program)

    def start(self) -> None:
        """Begin compiling the program of the first numbers (:meth:`quick`) in a background
        thread; the others compile on first use (:meth:`core`, :meth:`extras`), which the page
        asks for after it is shown."""
        self.model.programs.start("check")

    def _inputs(self, v, combo_index: int):
        inputs = self.model.inputs(combo_index, values=np.asarray(v, dtype=float))
        if self._points is not None:
            inputs = inputs._replace(points=self._points)
        return inputs

    def _values(self, v, inputs, full: bool = True) -> dict:
        ev, _, req, obj = self.model.programs.values_rows(np.asarray(v, dtype=float)[None, :], inputs, full=full)
        first = lambda tree: jax.tree_util.tree_map(lambda a: np.asarray(a)[0], tree)  # noqa: E731
        return {"evaluations": first(ev), "requirements": np.asarray(req[0], dtype=float),
                "objective": float(np.asarray(obj)[0])}

    def quick(self, v, combo_index: int) -> dict:
        """Evaluations (each case's budget and the outputs the requirements and the objective
        read), requirement values and objective at input vector ``v`` with the interval
        requirements' values NaN (no search)."""
        out = self._values(v, self._inputs(v, combo_index), full=False)
        out["requirements"] = out["requirements"].copy()
        out["requirements"][self.model.intervals.indices] = np.nan
        return out

    def core(self, v, combo_index: int) -> dict:
        """Evaluations, requirement values and objective at input vector ``v`` (NumPy), the
        interval requirements at the worst points a search finds there."""
        def run():
            inputs = self._inputs(v, combo_index)
            if self.model.intervals.indices:
                found = self.model.programs.search_rows(np.asarray(v, dtype=float)[None, :],
                                                        jax.tree_util.tree_map(lambda a: np.asarray(a)[None], inputs))[0]
                inputs = with_found_points(self.model, inputs, found)
                self._points = inputs.points
            return self._values(v, inputs)
        return self._first("core_ready", run)

    def _blocks(self, grids) -> List[tuple]:
        """The row blocks of the extras: per swept range input (its grid from ``grids``, in the
        order of :attr:`sweep_inputs`), then per one-parameter interval requirement,
        ``(kind, key, input index, grid, wanted)`` — the block's rows vary that input over the
        grid, ``wanted`` the outputs the block draws (case -> frozenset; static)."""
        blocks = []
        for k, grid in zip(self.sweep_inputs, grids):
            wanted = {case: frozenset(n for n in SWEEP_OUTPUTS + (self.margin_outputs[case],) if n is not None)
                      for case, kk in self.sweep_cases.items() if kk == k}
            blocks.append(("sweep", k, k, np.asarray(grid, dtype=float), wanted))
        for j in self.interval_requirements:
            r = self.model.requirements[j]
            blocks.append(("interval", j, self.interval_inputs[j], self.interval_grids[j],
                           {r.case: frozenset([r.output])}))
        return blocks

    @staticmethod
    def _rows(v0, blocks) -> np.ndarray:
        """The input vectors of every block (:meth:`_blocks`), stacked."""
        parts = []
        for _, _, k, grid, _ in blocks:
            block = np.repeat(v0[None, :], len(grid), axis=0)
            block[:, k] = grid
            parts.append(block)
        return np.vstack(parts) if parts else np.zeros((0, v0.size))

    def _extras_program(self, blocks) -> Program:
        """``fn(rows, v (n,), θ) -> (curves, jacobian)``: per block (:meth:`_blocks`) the outputs
        it draws at its rows — only those computed, each block's rows in one vmap — and
        d(requirement values, objective)/d(inputs) at ``v`` in forward mode; one program per
        spec structure and block sizes."""
        model = self.model
        wanted = [b[4] for b in blocks]
        sizes = [len(b[3]) for b in blocks]

        def outputs(w):
            def at(v):
                ev = model.evaluate(v, w)
                return {case: {n: ev[case].values[n] for n in sorted(names) if n in ev[case].values}
                        for case, names in w.items()}
            return at

        def stacked(v, inputs):
            _, _, req, obj = model.evaluation(v, inputs, False)
            return jnp.concatenate([jnp.atleast_1d(req), jnp.atleast_1d(obj)])

        def fn(rows, v, inputs):
            curves, start = [], 0
            for w, size in zip(wanted, sizes):
                curves.append(jax.vmap(outputs(w))(rows[start:start + size]))
                start += size
            return curves, jax.jacfwd(stacked)(v, inputs)

        n = len(model.layout)
        key = model.programs.structure + repr(([sorted((c, sorted(x)) for c, x in w.items()) for w in wanted], sizes))
        example = (np.zeros((sum(sizes), n)), np.zeros(n), model.programs.example_inputs)
        return Program("explorer", fn, example, key, preset="optimized", pool=compile_pool())

    def extras(self, v, combo_index: int, grids) -> dict:
        """Sweeps, interval curves and Jacobian at ``v`` (NumPy) by one call of the extras'
        program (:meth:`_extras_program`); compiles on first use."""
        def run():
            v0 = np.asarray(v, dtype=float)
            blocks = self._blocks(grids)
            sizes = tuple(len(b[3]) for b in blocks)
            if self._extras is None or self._extras[0] != sizes:
                self._extras = (sizes, self._extras_program(blocks))
            curves, jac = jax.device_get(self._extras[1](self._rows(v0, blocks), v0, self._inputs(v0, combo_index)))
            out = {"sweeps": {}, "intervals": {}, "jacobian": np.asarray(jac)}
            for (kind, key, _, _, wanted), curve in zip(blocks, curves):
                if kind == "sweep":
                    for case in wanted:
                        out["sweeps"][case] = {n: np.asarray(curve[case][n])
                                               for n in SWEEP_OUTPUTS + (self.margin_outputs[case],) if n in curve[case]}
                else:
                    r = self.model.requirements[key]
                    out["intervals"][key] = np.asarray(curve[r.case][r.output])
            return out
        return self._first("extras_ready", run)

    def _first(self, ready: str, run) -> dict:
        """``run()``; until flag ``ready`` is set, under one lock, so that a program is compiled
        once whichever thread (a slider move, the page's loader) asks first."""
        if getattr(self, ready):
            return run()
        with self._compiling:
            out = run()
            setattr(self, ready, True)
        return out

    def __call__(self, v, combo_index: int, grids) -> dict:
        """Both programs' outputs at ``v``."""
        return {**self.core(v, combo_index), **self.extras(v, combo_index, grids)}


__all__ = ["ExplorerProgram", "range_grid", "interval_grid", "SWEEP_OUTPUTS", "SWEEP_POINTS", "CURVE_POINTS"]
