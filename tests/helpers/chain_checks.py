"""Shared checks for sensor chains: a weighted sum of chosen outputs, compiled once per scene,
whose gradient covers every output at once; jit/vmap agreement; gradient versus central
differences; finite values and gradients over random draws of the documented domain."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from diffsense.scene import complete_parameters, evaluate


class WeightedOutputs:
    """``outputs`` of a chain and ``jit(value_and_grad)`` of ``weights · outputs``, per scene."""

    def __init__(self, outputs, weights):
        self.names = tuple(outputs)
        self.weights = jnp.asarray(weights, dtype=float)
        self._compiled = {}

    def outputs(self, scene, params):
        values = evaluate(scene, params)
        return jnp.stack([values[k] for k in self.names])

    def value_and_grad(self, scene):
        if scene not in self._compiled:
            def weighted(q):
                out = self.outputs(scene, q)
                return jnp.dot(self.weights, out), out

            self._compiled[scene] = jax.jit(jax.value_and_grad(weighted, has_aux=True))
        return self._compiled[scene]

    def assert_jit_and_vmap(self, scene, base, ranges_m):
        """jit equals eager (rel 1e-12); vmap over ``range_m`` equals one jitted call per range."""
        jitted = jax.jit(lambda q: self.outputs(scene, q))
        eager = evaluate(scene, base)
        np.testing.assert_allclose(np.asarray(jitted(base)), [float(eager[k]) for k in self.names], rtol=1e-12)
        ranges = jnp.asarray(ranges_m, dtype=float)
        batched = jax.jit(jax.vmap(lambda r: self.outputs(scene, dict(base, range_m=r))))(ranges)
        for r, row in zip(ranges, batched):
            np.testing.assert_allclose(np.asarray(row), np.asarray(jitted(dict(base, range_m=r))), rtol=1e-12)

    def assert_gradient_matches_fd(self, scene, base, names, rel_step, zero_step=1e-7):
        """Values equal eager evaluation; the gradient of the weighted sum in each named
        parameter equals a central difference (rel 2e-5, plus the difference's rounding)."""
        fn = self.value_and_grad(scene)
        (total, values), grads = fn(base)
        eager = evaluate(scene, base)
        np.testing.assert_allclose(np.asarray(values), [float(eager[k]) for k in self.names], rtol=1e-12)
        for name in names:
            x = float(base[name])
            h = rel_step * abs(x) if x else zero_step
            up, dn = dict(base), dict(base)
            up[name], dn[name] = jnp.asarray(x + h, dtype=float), jnp.asarray(x - h, dtype=float)  # no retrace
            fd = (float(fn(up)[0][0]) - float(fn(dn)[0][0])) / (2 * h)
            assert float(grads[name]) == pytest.approx(fd, rel=2e-5, abs=1e-9 * abs(float(total)) / h), name

    def assert_finite_over(self, scene, params, domains, draws=30, seed=7, extra_points=()):
        """Values and gradients finite at ``draws`` random points of ``domains`` (log-uniform
        where the lower end is positive) and at each of ``extra_points``."""
        fn = self.value_and_grad(scene)
        rng = np.random.default_rng(seed)
        points = [{k: lo * (hi / lo) ** rng.uniform() if lo > 0 else rng.uniform(lo, hi)
                   for k, (lo, hi) in domains.items()} for _ in range(draws)]
        for point in points + list(extra_points):
            (_, vals), g = fn(complete_parameters(scene, dict(params, **point)))
            assert np.all(np.isfinite(np.asarray(vals))), point
            assert all(math.isfinite(float(x)) for x in g.values()), point
