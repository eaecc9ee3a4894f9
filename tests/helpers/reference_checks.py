"""Shared assertions for solvers on the Hock–Schittkowski reference problems."""

import numpy as np

from diffsense.optimize import violation

# problems whose published optimum every solver must reach from the published start
HS_WITH_PUBLISHED_OPTIMUM = ["hs001", "hs007", "hs021", "hs028", "hs035", "hs039", "hs065", "hs071", "hs076",
                             "hs100"]


def assert_published_optimum(P, r, x_atol):
    """Converged, feasible, f* to 1e-7 relative (HS quotes 7–10 significant digits), x* within
    ``x_atol`` (scaled by max(1, |x*|)), inside the bounds."""
    assert bool(r.converged) and bool(r.feasible)
    assert abs(float(r.f) - P.f_star) <= 1e-7 * max(1.0, abs(P.f_star))
    np.testing.assert_allclose(np.asarray(r.x), P.x_star, rtol=0, atol=x_atol * max(1.0, np.max(np.abs(P.x_star))))
    assert float(violation(r)) <= 1e-8
    x = np.asarray(r.x)
    assert np.all(x >= np.asarray(P.problem.lower)) and np.all(x <= np.asarray(P.problem.upper))


def assert_hs071_ipopt_multipliers(r, mu_atol):
    """HS071 multipliers of the Ipopt example: λ = (−0.5522937, 0.1614686) for g ≥ 25 written
    with L = f + λ g, z_L[0] = 1.087871. Our g = 25 − Πx ≤ 0 flips the first multiplier's sign.
    The active bound x₀ = 1 is met exactly; ``mu_atol`` bounds the bound multipliers' error."""
    np.testing.assert_allclose(float(r.lam[0]), 0.5522937, rtol=1e-6)
    np.testing.assert_allclose(float(r.nu[0]), 0.1614686, rtol=1e-6)
    np.testing.assert_allclose(np.asarray(r.mu_lower), [1.087871, 0, 0, 0], atol=mu_atol)
    assert float(r.x[0]) == 1.0
