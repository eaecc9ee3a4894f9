"""Shared assertion for solvers on the Hock–Schittkowski reference problems."""

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
