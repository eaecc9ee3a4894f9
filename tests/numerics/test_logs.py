"""log(1 - p) at full relative accuracy (diffsense.numerics.logs) against 40-digit mpmath."""

import jax
import mpmath as mp
import numpy as np

import diffsense  # noqa: F401  (float64)
from diffsense.numerics.logs import log_one_minus


def test_log_one_minus_is_accurate_where_xla_log1p_is_not():
    p = np.concatenate([np.linspace(0.001, 0.9999, 2000), 10.0 ** np.linspace(-300, -3, 200), [0.40625, 0.25]])
    got = np.asarray(log_one_minus(p))
    with mp.workdps(40):
        want = np.array([float(mp.log1p(-mp.mpf(float(x)))) for x in p])
    rel = np.abs(got / want - 1)
    assert rel.max() <= 4.5e-16, (p[rel.argmax()], rel.max())  # docstring: <= 4.4e-16 measured


def test_log_one_minus_gradient_and_ends():
    g = jax.vmap(jax.grad(log_one_minus))(np.array([0.1, 0.25, 0.4, 0.9]))
    np.testing.assert_allclose(np.asarray(g), -1 / (1 - np.array([0.1, 0.25, 0.4, 0.9])), rtol=1e-15)
    assert float(log_one_minus(1.0)) == -np.inf and float(log_one_minus(0.0)) == 0.0
