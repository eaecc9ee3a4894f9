"""The report's view of the evaluation program: values and directional derivatives for batches of inputs.

Every numeric section of a report — the design's own numbers, the Jacobian (unit tangents),
the finite-difference check (perturbed inputs), range and false-alarm sweeps — is a batch of
input vectors ``V`` (rows, the layout of :class:`~diffsense.design.layout.InputLayout`) with
optional tangents ``T``, evaluated by the design model's one evaluation program
(:meth:`~diffsense.design.programs.Programs.evaluation`), so a report compiles the chain once
for all its sections, and the same program serves ``evaluate``, ``trade`` and the explorer.
The interval requirements are evaluated at the worst points a search finds at the design.
"""

from __future__ import annotations

import jax
import numpy as np

from diffsense.design.model import DesignModel


class BatchEvaluator:
    """``evaluator(V, T=None) -> (values, tangents)`` for input rows ``V`` (k, n) and tangents ``T``.

    ``values``/``tangents`` are NumPy pytrees ``(evaluations, requirement_values, objective)``
    with a leading axis of length k; ``tangents`` are the directional derivatives along the
    rows of ``T`` (zeros when ``T`` is omitted). ``objective`` is the spec's own (a maximised
    objective not negated).

    Where forward-mode differentiation of the chain fails (a JAX primitive without a
    derivative rule), the evaluator falls back to values only: ``tangents_available`` is then
    False, ``tangents_error`` holds the reason and the tangents are NaN.
    """

    def __init__(self, model: DesignModel, x, combo_index: int):
        self.model = model
        self.values0, inputs = model.programs.design_inputs(np.asarray(x, dtype=float)[None, :], [combo_index])
        self.values0 = self.values0[0]
        self.inputs = jax.tree_util.tree_map(lambda a: np.asarray(a)[0], inputs)
        self.n = self.values0.size
        self.tangents_error = model.programs.tangents_error
        self.tangents_available = self.tangents_error is None

    def __call__(self, V, T=None):
        V = np.atleast_2d(np.asarray(V, dtype=float))
        programs = self.model.programs
        if self.tangents_available:
            try:
                (ev, _, req, obj), (ev_t, _, req_t, obj_t) = programs.evaluate_rows(V, T, self.inputs)
                return (ev, req, obj), (ev_t, req_t, obj_t)
            except (NotImplementedError, TypeError, ValueError) as exc:
                self.tangents_available = False
                self.tangents_error = f"{type(exc).__name__}: {exc}"
        ev, _, req, obj = programs.values_rows(V, self.inputs, full=True)
        values = (ev, req, obj)
        return values, jax.tree_util.tree_map(lambda a: np.full(np.shape(a), np.nan), values)


def row(tree, i: int):
    """Row ``i`` of a batched pytree (leaves indexed along their first axis)."""
    return jax.tree_util.tree_map(lambda a: a[i], tree)


__all__ = ["BatchEvaluator", "row"]
