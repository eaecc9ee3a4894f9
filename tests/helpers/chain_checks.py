"""Shared checks for sensor chains: a weighted sum of chosen outputs, compiled once per scene,
whose gradient covers every output at once; jit/vmap agreement; gradient versus central
differences; finite values and gradients over random draws of the documented domain. And a
batch of forward-mode derivatives (:class:`BatchedJvp`): every directional derivative and the
central differences that check it in one compiled call."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from diffsense.scene import CHAINS, complete_parameters, evaluate


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


class BatchedJvp:
    """Chain outputs and their directional derivatives in the named parameters, at a base point
    and at the base point ± a step in each parameter, all in one ``jit(vmap(jvp))`` call.

    The batch has 3K rows for K = len(parameters): rows 0 … K−1 are the base point with the unit
    tangent of parameter i, rows K + 2i and K + 2i + 1 the base point with parameter i stepped by
    +h and −h, h = ``rel_step``·|x| (``zero_step`` where that is 0). Each row's values are the
    ``outputs`` followed by the budget residual ``snr_db − budget.total``.
    """

    def __init__(self, kind, scene, outputs, parameters, rel_step=1e-6, zero_step=0.0):
        self.kind, self.scene = kind, scene
        self.outputs, self.parameters = tuple(outputs), tuple(parameters)
        self.rel_step, self.zero_step = rel_step, zero_step
        self._compiled = None

    def _values(self, params):
        ev = CHAINS[self.kind].compute(self.scene, params)
        return jnp.stack([ev.values[o] for o in self.outputs] + [ev.values["snr_db"] - ev.budget.total])

    def _batch(self, base):
        k = len(self.parameters)
        p = complete_parameters(self.scene, base)
        primal = {q: np.full(3 * k, float(v)) for q, v in p.items()}
        tangent = {q: np.zeros(3 * k) for q in p}
        steps = np.zeros(k)
        for i, q in enumerate(self.parameters):
            tangent[q][i] = 1.0
            steps[i] = self.rel_step * abs(float(p[q])) or self.zero_step
            primal[q][k + 2 * i] += steps[i]
            primal[q][k + 2 * i + 1] -= steps[i]
        return primal, tangent, steps

    def run(self, base):
        """``(values, tangents, steps)``: values and tangents of the 3K rows, shape
        (3K, outputs + 1), and the step h of each parameter, shape (K,)."""
        if self._compiled is None:
            self._compiled = jax.jit(jax.vmap(lambda p, t: jax.jvp(self._values, (p,), (t,))))
        primal, tangent, steps = self._batch(base)
        values, tangents = (np.asarray(a) for a in self._compiled(primal, tangent))
        return values, tangents, steps

    def assert_matches_eager_and_differences(self, base, value_atol, derivative_floor):
        """At ``base``: the batched values equal eager evaluation (rel 1e-9, abs ``value_atol``),
        the budget terms sum to snr_db (1e-9 dB) in every row, and each directional derivative
        equals its central difference (rel 1e-5, abs 1e-9·max(``derivative_floor``, |value|)).
        Returns the eager evaluation."""
        values, tangents, steps = self.run(base)
        k = len(self.parameters)
        differences = (values[k::2] - values[k + 1::2]) / (2 * steps[:, None])
        eager = evaluate(self.scene, base)
        for j, o in enumerate(self.outputs):
            assert values[0, j] == pytest.approx(float(eager[o]), rel=1e-9, abs=value_atol), o
        assert np.all(np.abs(values[:, -1]) < 1e-9)
        for i, q in enumerate(self.parameters):
            for j, o in enumerate(self.outputs):
                tol = 1e-9 * max(derivative_floor, abs(values[0, j]))
                assert tangents[i, j] == pytest.approx(differences[i, j], rel=1e-5, abs=tol), (q, o)
        return eager

    def assert_finite_at(self, base, domain, unit_draws):
        """Values and directional derivatives are finite at the point that ``unit_draws`` (one
        u in [0, 1] a parameter) pick from ``domain`` ({name: (lo, hi, log)}: log-uniform where
        ``log``, clipped to [lo, hi]), the other parameters as in ``base``. Returns the values."""
        point = dict(base)
        for q, u in zip(self.parameters, unit_draws):
            lo, hi, log = domain[q]
            x = np.exp(np.log(lo) + u * (np.log(hi) - np.log(lo))) if log else lo + u * (hi - lo)
            point[q] = float(np.clip(x, lo, hi))  # exp(log(x)) may round past a bound
        values, tangents, _ = self.run(point)
        assert np.all(np.isfinite(values)) and np.all(np.isfinite(tangents[:len(self.parameters)]))
        return values
