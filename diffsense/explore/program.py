"""The explorer's one compiled program: a design's evaluation, its range sweeps and the
derivatives of its requirement outputs, all as functions of the report's input vector.

The input vector is :func:`diffsense.report.inputs.design_inputs` — every design variable,
every catalog parameter and every fixed parameter — so moving a slider, picking a catalog
option or typing a fixed value only changes the numbers fed to the same compiled program; it
is traced and compiled once per spec (:class:`ExplorerProgram`).

One call returns

* ``evaluations``, ``requirements`` and ``objective`` of
  :func:`diffsense.report.inputs.input_evaluator` (every case with every output; the
  objective as the spec states it, for the catalog combination whose cost it is given);
* ``sweeps``: per case with a numeric ``range_m`` input, the outputs ``snr_db``,
  ``required_snr_db``, ``pd`` and the main detection margin
  (:func:`diffsense.report.sweeps.main_margin`) on a grid of ranges (m);
* ``jacobian``: d(requirement outputs, objective)/d(inputs), forward mode (rows: the
  requirements in spec order, then the objective; columns: the inputs).

The catalog cost enters the objective as ``weight · cost`` (:class:`~diffsense.design.spec.Objective`
term ``cost``); the program is traced for the first catalog combination and the objective of
another combination k is shifted by ``weight · (cost_k − cost_0)``, which is exact because the
cost enters the weighted sum linearly and nothing else.
"""

from __future__ import annotations

from typing import Dict, List, Optional, Tuple

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.design.model import DesignModel
from diffsense.report.inputs import Input, input_evaluator
from diffsense.report.sweeps import input_index, main_margin

#: outputs drawn against range, when the case has them
SWEEP_OUTPUTS = ("snr_db", "required_snr_db", "pd")
#: points of every range sweep
SWEEP_POINTS = 121


def range_grid(range_m: float, lower: Optional[float] = None, upper: Optional[float] = None,
               n: int = SWEEP_POINTS) -> np.ndarray:
    """Ranges (m) from R/40 to 2 R around the design range R, linear, clipped to the
    parameter's domain [lower, upper] (the report's range sweep grid)."""
    lo = max(range_m / 40.0, lower or 0.0)
    hi = min(2.0 * range_m, upper if upper is not None else np.inf)
    return np.linspace(lo, max(hi, lo * (1.0 + 1e-9)), n)


class ExplorerProgram:
    """``program(v, cost_shift, grids) -> dict`` compiled once for ``model`` and ``inputs``.

    ``sweep_cases``: case -> index of the ``range_m`` input it sweeps; ``grids`` holds one grid
    (m) per distinct index, in the order of :attr:`sweep_inputs`.
    """

    def __init__(self, model: DesignModel, inputs: List[Input]):
        self.model = model
        self.inputs = inputs
        fn = input_evaluator(model, inputs, 0)
        self.sweep_cases: Dict[str, int] = {}
        for case in model.spec.scenes:
            k = input_index(inputs, "range_m", case)
            if k is not None:
                self.sweep_cases[case] = k
        self.sweep_inputs: List[int] = sorted(set(self.sweep_cases.values()))
        margins = {case: main_margin(model, case) for case in model.spec.scenes}
        self.margin_outputs: Dict[str, Optional[str]] = {
            case: (model.requirements[m].output if m is not None else None) for case, m in margins.items()}

        def swept(v, k, grid):
            rows = jnp.tile(v, (grid.shape[0], 1)).at[:, k].set(grid)
            evaluations = jax.vmap(fn)(rows)[0]
            out = {}
            for case, kk in self.sweep_cases.items():
                if kk != k:
                    continue
                values = evaluations[case].values
                names = [n for n in SWEEP_OUTPUTS if n in values]
                if self.margin_outputs[case] in values:
                    names.append(self.margin_outputs[case])
                out[case] = {n: values[n] for n in names}
            return out

        def stacked(v):
            _, req, obj = fn(v)
            return jnp.concatenate([jnp.reshape(req, (-1,)), jnp.reshape(obj, (1,))])

        def program(v, cost_shift, grids: Tuple):
            evaluations, req, obj = fn(v)
            sweeps = {}
            for k, grid in zip(self.sweep_inputs, grids):
                sweeps.update(swept(v, k, grid))
            return {"evaluations": evaluations, "requirements": req, "objective": obj + cost_shift,
                    "sweeps": sweeps, "jacobian": jax.jacfwd(stacked)(v)}

        self._program = jax.jit(program)

    def __call__(self, v, cost_shift: float, grids) -> dict:
        """The program's outputs at input vector ``v`` as NumPy arrays (blocks until done)."""
        out = self._program(jnp.asarray(v, dtype=float), jnp.asarray(cost_shift, dtype=float),
                            tuple(jnp.asarray(g, dtype=float) for g in grids))
        return jax.tree_util.tree_map(np.asarray, out)


__all__ = ["ExplorerProgram", "range_grid", "SWEEP_OUTPUTS", "SWEEP_POINTS"]
