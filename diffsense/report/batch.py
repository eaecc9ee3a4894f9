"""One compiled program per report: values and directional derivatives for batches of inputs.

Every numeric section of a report — the design's own numbers, the Jacobian (unit tangents),
the finite-difference check (perturbed inputs), range and false-alarm sweeps — is a batch of
input vectors ``V`` (rows) with optional tangents ``T``. :class:`BatchEvaluator` compiles
``vmap(jvp(fn))`` once for a fixed chunk of rows and pads every request to whole chunks, so a
report compiles the chain once instead of once per section.
"""

from __future__ import annotations

from typing import List

import jax
import jax.numpy as jnp
import numpy as np

from diffsense.design.model import DesignModel
from diffsense.report.inputs import Input, input_evaluator


class BatchEvaluator:
    """``evaluator(V, T=None) -> (values, tangents)`` for input rows ``V`` (k, n) and tangents ``T``.

    ``values``/``tangents`` are NumPy pytrees ``(evaluations, requirement_values, objective)``
    with a leading axis of length k (see :func:`~diffsense.report.inputs.input_evaluator`);
    ``tangents`` are the directional derivatives along the rows of ``T`` (zeros when ``T`` is
    omitted). Rows are evaluated in chunks of ``chunk`` (one compilation).

    Where forward-mode differentiation of the chain fails (a JAX primitive without a
    derivative rule), the evaluator falls back to values only: ``tangents_available`` is then
    False, ``tangents_error`` holds the reason and the tangents are NaN.
    """

    def __init__(self, model: DesignModel, inputs: List[Input], combo_index: int, chunk: int = 32):
        self.inputs = inputs
        self.n = len(inputs)
        self.chunk = int(chunk)
        fn = input_evaluator(model, inputs, combo_index)

        def one(v, t):
            return jax.jvp(fn, (v,), (t,))

        def plain(v, t):
            out = fn(v)
            return out, jax.tree_util.tree_map(lambda a: jnp.full_like(a, jnp.nan), out)

        self._program = jax.jit(jax.vmap(one))
        self._plain = jax.jit(jax.vmap(plain))
        self.tangents_available = True
        self.tangents_error = None

    def _run(self, V, T):
        if self.tangents_available:
            try:
                return self._program(V, T)
            except (NotImplementedError, TypeError, ValueError) as exc:
                self.tangents_available = False
                self.tangents_error = f"{type(exc).__name__}: {exc}"
        return self._plain(V, T)

    def __call__(self, V, T=None):
        V = np.atleast_2d(np.asarray(V, dtype=float))
        k = V.shape[0]
        T = np.zeros_like(V) if T is None else np.atleast_2d(np.asarray(T, dtype=float))
        pad = (-k) % self.chunk
        if pad:
            V = np.vstack([V, np.repeat(V[-1:], pad, axis=0)])
            T = np.vstack([T, np.zeros((pad, self.n))])
        parts = []
        for start in range(0, V.shape[0], self.chunk):
            stop = start + self.chunk
            out = self._run(jnp.asarray(V[start:stop]), jnp.asarray(T[start:stop]))
            parts.append(jax.tree_util.tree_map(np.asarray, out))
        values, tangents = jax.tree_util.tree_map(lambda *a: np.concatenate(a, axis=0)[:k], *parts)
        return values, tangents


def row(tree, i: int):
    """Row ``i`` of a batched pytree (leaves indexed along their first axis)."""
    return jax.tree_util.tree_map(lambda a: a[i], tree)


__all__ = ["BatchEvaluator", "row"]
