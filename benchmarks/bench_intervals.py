"""Benchmark of requirements over intervals (semi-infinite constraints) on the spec
``tests/design/interval_specs/multipath_null.toml``: a radar whose detection must hold at every
range from 10 to 20 km, the worst point being a multipath null inside the interval.

1. Cost per solve: the same design problem (minimise peak power) with the requirement stated
   (a) at the one range of the null (a point requirement, the answer known in advance) and (b)
   over the interval (the exchange method finds the null: a search — grid of 129 points, the
   worst points refined — sets the requirement's slots, the solver solves with them, and the
   search and solve repeat until the slots hold the answer's worst points). Each is one lane of
   the design optimiser's compiled programs (:class:`diffsense.design.runner.Runner`, default
   augmented Lagrangian, from the spec's start); the time of (b) includes its searches. Compile
   time of the first call, and the median over rounds of the warm time per design.
2. Accuracy of the worst case: at the optimum of (b), the smallest margin found by (i) the
   solver's grid alone (no refinement), (ii) the solver's refined search, and (iii) the dense
   re-check on 10,001 points of its own grid, each against a reference minimum (the dense
   minimum polished by bisection on the derivative to 1e-12 m). The error of (ii) is what the
   requirement's residual is wrong by; (i) shows what the refinement buys.

Run: python benchmarks/bench_intervals.py [--rounds 15] [--quick]
Times are wall-clock on this machine (2 cores, possibly shared: ratios measured in one run).
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import _support  # noqa: F401  (repository root on sys.path)
import jax
import jax.numpy as jnp
import numpy as np

from diffsense import DesignModel, load_spec
from diffsense.design.optimizer import _thetas
from diffsense.design.runner import Lanes, Runner, objective_scale
from diffsense.optimize import SolverOptions

SPEC = _support.ROOT / "tests" / "design" / "interval_specs" / "multipath_null.toml"


def _solver(model):
    """(call solving the spec's design from its start -> x, compile + first-run seconds, x):
    one lane of the optimiser's lane program; with interval requirements, search and solve
    repeat until the slots hold the answer's worst points (:meth:`Runner.settle`)."""
    run = Runner(model, SolverOptions(polish=False), 1, 1)
    theta = _thetas(model, model.inputs(), [0], model.limits, objective_scale(model))
    lower, upper = run.boxes(n=1)
    x0 = model.initial[None, :]
    combo = np.zeros(1, dtype=int)

    def once():
        th, _ = run.search_points(x0, theta, combo)
        _, res = run.settle(Lanes(x0, th, lower, upper, combo))
        return res.x[0]

    t = time.perf_counter()
    x = once()
    return once, time.perf_counter() - t, x


def _point_model(model, null_range_m):
    """The same spec with the interval requirement replaced by one at ``null_range_m``."""
    spec = model.spec
    req = dataclasses.replace(spec.requirements[0], over=())
    fixed = {case: dict(v, range_m=float(null_range_m)) for case, v in spec.fixed.items()}
    return DesignModel(dataclasses.replace(spec, requirements=[req], fixed=fixed))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--quick", action="store_true", help=_support.QUICK_HELP + " (2 rounds)")
    args = ap.parse_args()
    rounds = 2 if args.quick else args.rounds

    interval = DesignModel(load_spec(SPEC))
    fn_i, compile_i, x_opt = _solver(interval)
    combo0 = interval.combo_table[0]
    values, checks = interval.programs.checked_values(x_opt, combo0)
    check = checks[0]
    null_r = check.worst_point["range_m"]  # the dense grid's point, within one cell of the null
    point = _point_model(interval, null_r)
    fn_p, compile_p, x_p = _solver(point)

    times_i, times_p = [], []
    for _ in range(rounds):  # alternate, so that the machine's drifting load weighs on both alike
        times_p.append(_support.median_time(fn_p, 3))
        times_i.append(_support.median_time(fn_i, 3))
    tp, ti = float(np.median(times_p)), float(np.median(times_i))
    print("1. Cost of an interval requirement against a point requirement (one design, AL, from the spec's start)")
    print(f"{'requirement':<44}{'compile (s)':>12}{'time/design (ms)':>17}{'ratio':>8}{'peak power (W)':>17}")
    print(f"{'at the null range only (' + format(null_r, '.1f') + ' m)':<44}{compile_p:>12.2f}{tp * 1e3:>17.2f}"
          f"{1.0:>8.1f}{float(x_p[0]):>17.6g}")
    print(f"{'over 10-20 km (129-point grid, exchange)':<44}{compile_i:>12.2f}{ti * 1e3:>17.2f}{ti / tp:>8.1f}"
          f"{float(x_opt[0]):>17.6g}")
    print(f"relative difference of the two optima: {abs(float(x_opt[0]) / float(x_p[0]) - 1):.1e}")
    print("compile: the first design's time (programs exported, compiled or loaded, and run)")

    # 2. accuracy of the worst case at the interval optimum
    req = interval.spec.requirements[0]
    design = interval.design_values(x_opt, 0)
    params = interval.parameters(jnp.asarray(design))[req.case]
    margin = jax.jit(jax.vmap(lambda r: interval.intervals.value_at(0, params, jnp.reshape(r, (1,)))))
    slope = jax.jit(jax.vmap(jax.grad(lambda r: interval.intervals.value_at(0, params, jnp.reshape(r, (1,))))))
    grid = interval.intervals.boxes[0].grid()[:, 0]
    grid_min = float(np.min(np.asarray(margin(jnp.asarray(grid)))))
    search = float(values[0])
    dense = check.worst_value
    a, b = null_r - 50.0, null_r + 50.0  # reference: bisection on the derivative around the null
    for _ in range(80):
        m = 0.5 * (a + b)
        if float(slope(jnp.asarray([m]))[0]) < 0:
            a = m
        else:
            b = m
    ref = float(margin(jnp.asarray([0.5 * (a + b)]))[0])
    print()
    print("2. Worst-case margin at the interval optimum against the reference minimum "
          f"({ref:.9f} dB at {0.5 * (a + b):.6f} m)")
    print(f"{'method':<52}{'points':>8}{'worst margin (dB)':>19}{'error (dB)':>12}")
    print(f"{'solver grid alone (no refinement)':<52}{grid.size:>8}{grid_min:>19.9f}{grid_min - ref:>12.2e}")
    print(f"{'search (grid + value-only zoom)':<52}{grid.size:>8}{search:>19.9f}{search - ref:>12.2e}")
    print(f"{'dense re-check, own grid (then the worse of the two)':<52}{check.n_points:>8}{dense:>19.9f}"
          f"{dense - ref:>12.2e}")


if __name__ == "__main__":
    main()
