"""Benchmark of Pareto fronts: epsilon-constraint continuation (diffsense.optimize.continuation)
against pymoo's NSGA-II on problems with exact fronts.

1. Power-aperture (bi-objective): minimise (P, d) s.t. P d^4 >= K, 1e3 <= P <= 1e7 W,
   1 <= d <= 10 m; the exact front is P d^4 = K.
2. Three objectives: F_k = |x - a_k|^2 for three centres a_k in the plane; the Pareto set is
   their triangle, so a point's distance from the front is its distance from the triangle.

Columns: wall time (ours: a warm call, the step program already compiled for that problem; the
first call, tracing and compilation included, is printed apart), model evaluations (ours:
the solver's inner iterations, each one value and gradient of the objectives and constraints;
NSGA-II: population x generations), hypervolume (pymoo's HV, objectives normalised by the exact
front's ideal-nadir box, reference 1.1 each), and the largest distance of a front point from the
exact front (problem 1: max |P d^4 / K - 1|; problem 2: largest distance from the triangle).

Run: python benchmarks/bench_trade.py [--quick]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from _support import QUICK_HELP, require

K = 2.0e4
CENTRES = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])


def _timed_fronts(prob, objectives, thetas, x0, points):
    """Two calls of trace_front with the same problem and objective function objects: the first
    compiles the step program (traced once, then cached), the second reuses it."""
    from diffsense.optimize.continuation import pareto_mask, trace_front

    t = time.perf_counter()
    trace_front(prob, objectives, thetas, x0, points=points)
    first = time.perf_counter() - t
    t = time.perf_counter()
    f = trace_front(prob, objectives, thetas, x0, points=points)
    warm = time.perf_counter() - t
    ok = f.converged & f.feasible
    keep = pareto_mask(f.objectives[ok])
    return f.objectives[ok][keep], f.x[ok][keep], warm, first, f.trips


def ours_power_aperture(points):
    import jax.numpy as jnp
    import diffsense  # noqa: F401
    from diffsense.optimize import Problem

    prob = Problem(lambda x, th: 0.0 * x[0], [1e3, 1.0], [1e7, 10.0],
                   inequality=lambda x, th: jnp.array([1.0 - x[0] * x[1] ** 4 / th]), log_scale=True)
    return _timed_fronts(prob, lambda x, th: x, np.array([K]), np.array([[1e5, 3.0]]), points)


def ours_three(points):
    import jax.numpy as jnp
    from diffsense.optimize import Problem

    prob = Problem(lambda x, th: 0.0 * x[0], [-3.0, -3.0], [3.0, 3.0])
    obj = lambda x, th: jnp.sum((x[None, :] - jnp.asarray(CENTRES)) ** 2, axis=1)  # noqa: E731
    return _timed_fronts(prob, obj, np.zeros((1, 1)), np.array([[0.5, 0.5]]), points)


def nsga(problem, pop, gens, seed=0):
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.optimize import minimize

    t = time.perf_counter()
    res = minimize(problem, NSGA2(pop_size=pop), ("n_gen", gens), seed=seed, verbose=False)
    return res.F, res.X, time.perf_counter() - t, pop * gens


def pymoo_problems():
    from pymoo.core.problem import ElementwiseProblem

    class PowerAperture(ElementwiseProblem):
        def __init__(self):
            super().__init__(n_var=2, n_obj=2, n_ieq_constr=1, xl=np.array([3.0, 0.0]), xu=np.array([7.0, 1.0]))

        def _evaluate(self, z, out, *args, **kwargs):
            P, d = 10 ** z[0], 10 ** z[1]
            out["F"] = [P, d]
            out["G"] = [1.0 - P * d ** 4 / K]

    class Three(ElementwiseProblem):
        def __init__(self):
            super().__init__(n_var=2, n_obj=3, xl=-3.0, xu=3.0)

        def _evaluate(self, x, out, *args, **kwargs):
            out["F"] = np.sum((x[None, :] - CENTRES) ** 2, axis=1)

    return PowerAperture(), Three()


def hv(F, ideal, nadir):
    from pymoo.indicators.hv import HV

    f = (np.asarray(F) - ideal) / (nadir - ideal)
    return float(HV(ref_point=np.full(f.shape[1], 1.1))(f))


def triangle_distance(x):
    # distance of each point from the triangle x >= 0, y >= 0, x + y <= 2 (0 inside)
    out = []
    for p in np.atleast_2d(x):
        q = np.clip(p, 0.0, None)
        if q.sum() > 2.0:
            q = np.clip(q - (q.sum() - 2.0) / 2.0, 0.0, 2.0)
            q = q * (2.0 / q.sum()) if q.sum() > 2.0 else q
        out.append(np.linalg.norm(p - q))
    return float(np.max(out))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=QUICK_HELP)
    args = parser.parse_args()
    require("bench_trade.py", "pymoo")
    points, pop, gens = (12, 40, 40) if args.quick else (30, 100, 250)
    pa, three = pymoo_problems()
    rows = []
    F, _, run, first, trips = ours_power_aperture(points)
    ideal, nadir = np.array([1e3, 1.0]), np.array([K, (K / 1e3) ** 0.25])
    rows.append(("power-aperture", "continuation", run, trips, len(F), hv(F, ideal, nadir),
                 np.max(np.abs(F[:, 0] * F[:, 1] ** 4 / K - 1.0)), first))
    Fn, _, tn, evals = nsga(pa, pop, gens)
    rows.append(("power-aperture", "NSGA-II", tn, evals, len(Fn), hv(Fn, ideal, nadir),
                 np.max(np.abs(Fn[:, 0] * Fn[:, 1] ** 4 / K - 1.0)), None))
    F3, X3, run3, first3, trips3 = ours_three(points)
    ideal3, nadir3 = np.zeros(3), np.array([8.0, 8.0, 8.0])
    rows.append(("three centres", "continuation", run3, trips3, len(F3), hv(F3, ideal3, nadir3),
                 triangle_distance(X3), first3))
    F3n, X3n, t3n, evals3 = nsga(three, pop, gens)
    rows.append(("three centres", "NSGA-II", t3n, evals3, len(F3n), hv(F3n, ideal3, nadir3),
                 triangle_distance(X3n), None))
    print(f"{'problem':15s} {'method':13s} {'time s':>8s} {'evals':>8s} {'points':>7s} {'HV':>8s} "
          f"{'max dist':>10s}")
    for prob, meth, t, ev, n, h, dist, first in rows:
        print(f"{prob:15s} {meth:13s} {t:8.3f} {ev:8d} {n:7d} {h:8.4f} {dist:10.2e}"
              + (f"   (first call incl. compile {first:.2f} s)" if first else ""))
    print("time s: warm call (continuation: compiled program reused; first call printed apart); "
          "NSGA-II: one run")


if __name__ == "__main__":
    main()
