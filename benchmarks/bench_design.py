"""Benchmark of the design optimizer on a shipped spec (default ``designs/ore_pass.toml``).

The model is the spec's own (``DesignModel``): the best catalog combination of the full run
(94 GHz, Gunn oscillator) with the integer pulse count relaxed, from the spec's initial design.

1. Side by side, from the same start on the same model: diffsense's two solvers (SQP,
   ``SolverOptions(method="sqp")``, and the default augmented Lagrangian over BFGS; exact
   gradients through the chain, one jitted program each) against
   ``scipy.optimize.minimize(method="SLSQP")`` with finite-difference gradients (jac=None,
   scipy's 2-point differences) and with the exact JAX gradients, calling the same jitted
   model functions. The methods take turns in rounds (each round runs each method 3 times back
   to back and keeps the best), so that the drifting load of a shared machine weighs on all of
   them alike. Reported: the median over rounds of the time per solve, compile time, the
   optimum's objective, its relative error against the best objective found by any method, the
   largest requirement violation (scaled), and SLSQP-FD's time over each method's (median of
   the per-round ratios).
2. Tolerance sweep: solve time against objective error for tol = 1e-4 … 1e-10, both solvers.
3. Batch throughput: a sweep of the required detection margin over B specs in one call of
   ``make_batch_solver`` (compile excluded), with the specs solved one after another
   (``lockstep=1``, the CPU default; SQP and AL) and all in one vmap (``lockstep=None``, AL).
4. Process cold start: ``diffsense optimize`` of the whole spec (all catalog combinations,
   8 starts, integer rounding) in a fresh process with an empty compilation cache and again
   with the cache it filled.
5. Lanes in lockstep: the design optimiser's first step (every catalog combination from each
   of 8 starts: one lane per pair) as one compiled call, with ``lockstep`` = 1 (lanes in
   sequence, ``lax.map``), the number of combinations (one start's catalog options per vmap)
   and all lanes in one vmap. Compile and warm run time, converged lanes.

Run: python benchmarks/bench_design.py [--spec designs/ore_pass.toml] [--repeats 30] [--skip-cli] [--quick]
(section 1 needs scipy, in the ``bench`` extras).
Times are wall-clock on this machine (2 cores, possibly shared: ratios measured in one run).
``--quick`` prints the same tables for the smaller lidar spec (``designs/lidar_rangefinder.toml``,
unless ``--spec`` is given) with 2 rounds, fewer rows (one tolerance, batches of 4 specs with the
AL solver only, two lane layouts of 2 starts) and no process cold start: a check that the
benchmark works, not a measurement.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import _support
import jax
import jax.numpy as jnp
import numpy as np

import diffsense  # noqa: F401
from diffsense.design.model import DesignModel
from diffsense.design.optimizer import _starts, _thetas, tight_limits
from diffsense.design.problem import design_problem, requirement_problem, variable_scales
from diffsense.design.runner import objective_scale
from diffsense.design.spec import load_spec
from diffsense.optimize import SolverOptions, make_batch_solver, solve
from diffsense.optimize.lanes import lane_program

ROOT = _support.ROOT
_median_time = _support.median_time
TOLERANCES = (1e-4, 1e-6, 1e-8, 1e-10)
#: section 3's layouts: (method, label, lockstep)
BATCH_LAYOUTS = (("sqp", "in sequence (1)", 1), ("al", "in sequence (1)", 1), ("al", "one vmap (None)", None))


def _setup(spec_path):
    model = DesignModel(load_spec(spec_path))
    combo = None
    for c in model.combinations:
        if "94" in " ".join(str(v) for v in c.values.values()) or c.values.get("freq_hz") == 94e9:
            if "Gunn" in " ".join(c.options.values()):
                combo = c.index
    combo = 0 if combo is None else combo
    problem = requirement_problem(model)
    theta = model.solve_inputs(model.inputs(combo), combo, tight_limits(model, 1e-7), objective_scale(model))
    return model, combo, problem, jax.tree_util.tree_map(jnp.asarray, theta)


def _violation(model, x, combo):
    v = np.asarray(model.evaluate_all(x, model.combo_table[combo])[1])
    return float(np.max(np.maximum(model.sign * (v - model.limits) / model.scales, 0.0)))


def _objective(model, x, combo):
    return float(model.evaluate_all(x, model.combo_table[combo])[2])


def _batched(theta, B):
    """θ repeated over a leading axis of B specs."""
    return jax.tree_util.tree_map(lambda a: jnp.broadcast_to(a, (B,) + jnp.shape(a)), theta)


def make_ours(model, problem, theta, options):
    """(compiled solve call, compile seconds) for diffsense's solve with ``options``."""
    fn = jax.jit(lambda x0, th: solve(problem, x0, th, options))
    x0 = jnp.asarray(model.initial)
    t = time.perf_counter()
    jax.block_until_ready(fn(x0, theta))
    t_compile = time.perf_counter() - t

    def once():
        r = jax.block_until_ready(fn(x0, theta))
        return np.asarray(r.x), bool(r.converged)
    return once, t_compile


def run_ours(model, problem, theta, options, repeats):
    once, t_compile = make_ours(model, problem, theta, options)
    t_solve = _median_time(once, repeats)
    x, conv = once()
    return x, conv, t_compile, t_solve


def make_slsqp(model, problem, theta, exact_gradients):
    """A call running ``scipy.optimize.minimize(method="SLSQP")`` on the model, returning
    (x, success, objective evaluations)."""
    from scipy.optimize import minimize

    f = jax.jit(lambda x: problem.f(x, theta))
    g = jax.jit(lambda x: problem.g(x, theta))
    df = jax.jit(jax.grad(lambda x: problem.f(x, theta)))
    dg = jax.jit(jax.jacfwd(lambda x: problem.g(x, theta)))
    # SLSQP works in the physical variables; give it the optimizer's own scaling (log for
    # log-scaled variables, divided by the range otherwise) so that the comparison is fair
    lo, hi = np.asarray(problem.lower, float), np.asarray(problem.upper, float)
    logs = np.asarray(model.log_scale, bool)

    def to_x(z):
        return np.where(logs, np.exp(z), lo + z * (hi - lo))

    def dxdz(z):
        return np.where(logs, np.exp(z), hi - lo)

    zlo = np.where(logs, np.log(lo), 0.0)
    zhi = np.where(logs, np.log(hi), 1.0)
    x0 = np.asarray(model.initial, float)
    z0 = np.where(logs, np.log(x0), (x0 - lo) / (hi - lo))
    cons = [{"type": "ineq", "fun": lambda z: -np.asarray(g(to_x(z)))}]
    if exact_gradients:
        cons[0]["jac"] = lambda z: -np.asarray(dg(to_x(z))) * dxdz(z)[None, :]
    jac = (lambda z: np.asarray(df(to_x(z))) * dxdz(z)) if exact_gradients else None
    nfev = {"n": 0}

    def fun(z):
        nfev["n"] += 1
        return float(f(to_x(z)))

    def once():
        nfev["n"] = 0
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            out = minimize(fun, z0, jac=jac, method="SLSQP", bounds=list(zip(zlo, zhi)), constraints=cons,
                           options={"ftol": 1e-10, "maxiter": 500})
        return to_x(out.x), bool(out.success), nfev["n"]

    once()  # compiles the jitted callables
    return once


def comparison(model, combo, problem, theta, repeats):
    print("\n== 1. one solve on the model, same start: diffsense vs scipy SLSQP ==")
    methods = []
    for label, options in (("diffsense SQP (method='sqp')", SolverOptions(method="sqp")),
                           ("diffsense AL + BFGS (default)", SolverOptions(polish=False))):
        once, tc = make_ours(model, problem, theta, options)
        methods.append((label, once, tc))
    for exact in (False, True):
        label = "scipy SLSQP, " + ("exact JAX gradients" if exact else "finite differences")
        methods.append((label, make_slsqp(model, problem, theta, exact), float("nan")))
    # rounds: every method in every round, so that the load of this shared machine, which
    # drifts over seconds, weighs on all of them alike, and ratios are taken within a round;
    # a method's time in a round is the best of 3 calls back to back (warm: on this VM a call
    # after the process sat idle for a few milliseconds costs ~1 ms more, whatever it runs)
    times = np.zeros((repeats, len(methods)))
    answers = [m[1]() for m in methods]
    for k in range(repeats):
        for i, (_, once, _) in enumerate(methods):
            best = np.inf
            for _ in range(3):
                t = time.perf_counter()
                once()
                best = min(best, time.perf_counter() - t)
            times[k, i] = best
    fd = [i for i, m in enumerate(methods) if m[0].endswith("finite differences")][0]
    feasible = [_objective(model, a[0], combo) for a in answers if _violation(model, a[0], combo) <= 1e-6]
    best = min(feasible)
    print(f"{'method':36s} {'time ms':>9s} {'compile s':>9s} {'objective':>12s} {'rel err':>9s} {'violation':>9s} "
          f"{'SLSQP-FD/this':>13s}  note")
    for i, (label, _, tc) in enumerate(methods):
        x, ok = answers[i][0], answers[i][1]
        obj, viol = _objective(model, x, combo), _violation(model, x, combo)
        speedup = float(np.median(times[:, fd] / times[:, i]))
        note = ("" if ok else "not converged ") + (f"{answers[i][2]} f-evals" if len(answers[i]) > 2 else "")
        print(f"{label:36s} {np.median(times[:, i])*1e3:9.2f} {tc:9.2f} {obj:12.8f} {abs(obj-best)/abs(best):9.1e} "
              f"{viol:9.1e} {speedup:12.1f}x  {note}")
    print(f"time: median over {repeats} rounds of the best of 3 calls back to back (each round runs every method); "
          "SLSQP-FD/this: median over the rounds of SLSQP-FD's time over the method's; rel err: against the best "
          "feasible objective of the four; violation: largest scaled requirement violation")


def tolerance_sweep(model, combo, problem, theta, repeats, tolerances=TOLERANCES):
    print("\n== 2. diffsense: solve time against objective error (tolerance sweep) ==")
    ref_x, _, _, _ = run_ours(model, problem, theta, SolverOptions(polish=False, tol=1e-11, feas_tol=1e-11), 1)
    ref = _objective(model, ref_x, combo)
    print(f"{'method':>6s} {'tol':>8s} {'time ms':>9s} {'rel err':>9s} {'violation':>9s}")
    for method in ("sqp", "al"):
        for tol in tolerances:
            options = SolverOptions(method=method, polish=False, tol=tol, feas_tol=tol)
            x, conv, _, ts = run_ours(model, problem, theta, options, repeats)
            obj = _objective(model, x, combo)
            viol = _violation(model, x, combo)
            print(f"{method:>6s} {tol:8.0e} {ts*1e3:9.2f} {abs(obj-ref)/abs(ref):9.1e} {viol:9.1e}"
                  f"{'' if conv else '  not converged'}")
    print("rel err: against the AL solve at tol = feas_tol = 1e-11; time: median of back-to-back calls")


def batch_throughput(model, combo, problem, theta, sizes, layouts=BATCH_LAYOUTS):
    print("\n== 3. batch: sweep of the first requirement's limit, one compiled call (make_batch_solver) ==")
    print(f"{'method':>6s} {'lockstep':>22s} {'B':>6s} {'compile s':>9s} {'time s':>8s} {'ms/spec':>8s} "
          f"{'converged':>9s}")
    for method, label, lockstep in layouts:
        fn = make_batch_solver(problem, SolverOptions(method=method, polish=False), lockstep=lockstep)
        for B in sizes:
            lims = np.tile(np.asarray(theta.limits), (B, 1))
            lims[:, 0] = lims[:, 0] + model.sign[0] * np.linspace(-3.0, 1.0, B) * model.scales[0]
            x0 = jnp.asarray(np.tile(model.initial, (B, 1)))
            th = _batched(theta, B)._replace(limits=jnp.asarray(lims))
            t = time.perf_counter()
            r = jax.block_until_ready(fn(x0, th))
            tc = time.perf_counter() - t
            t = time.perf_counter()
            r = jax.block_until_ready(fn(x0, th))
            tr = time.perf_counter() - t
            print(f"{method:>6s} {label:>22s} {B:6d} {tc - tr:9.2f} {tr:8.3f} {tr / B * 1e3:8.1f} "
                  f"{int(np.sum(np.asarray(r.converged))):9d}")


def cli_cold_start(spec_path):
    print("\n== 4. process start to answer: `diffsense optimize` (all combinations, 8 starts, rounding) ==")
    exe = Path(sys.executable).with_name("diffsense")
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, DIFFSENSE_CACHE_DIR=cache)
        for label in ("empty compilation cache", "cache filled by the run above"):
            t = time.perf_counter()
            p = subprocess.run([str(exe), "optimize", str(spec_path)], env=env, capture_output=True, text=True)
            print(f"{label:32s} {time.perf_counter() - t:7.1f} s  exit {p.returncode}")


def _lane_arguments(model, starts):
    """The arguments (x0, θ, lower, upper, scale) of the design problem's lane program for
    every (start, combination) lane, start-major, as the optimiser's first step builds them."""
    n_c = len(model.combinations)
    x0 = np.repeat(starts, n_c, axis=0)
    L = x0.shape[0]
    combos = np.tile(np.arange(n_c), starts.shape[0])
    theta = _thetas(model, model.inputs(), combos, tight_limits(model, 1e-7), objective_scale(model))
    zeros = np.zeros((L, 1))
    lower = np.hstack([np.broadcast_to(model.lower, x0.shape), zeros])
    upper = np.hstack([np.broadcast_to(model.upper, x0.shape), zeros])
    scales = np.broadcast_to(variable_scales(model), lower.shape)
    return tuple(jax.tree_util.tree_map(jnp.asarray, a)
                 for a in (np.hstack([x0, zeros]), theta, lower, upper, scales))


def lanes_in_lockstep(model, problem, n_starts=8, layouts=("sequence", "combinations", "all")):
    print("\n== 5. design optimiser's first step: all (start, combination) lanes in one call ==")
    starts = _starts(model, n_starts, 0)
    n_c, n_s = len(model.combinations), starts.shape[0]
    args = _lane_arguments(model, starts)
    problem = design_problem(model)
    print(f"{'lanes per vmap':>24s} {'compile s':>9s} {'run s':>7s} {'converged':>9s}")
    rows = []
    lockstep = {"sequence": ("1 (in sequence)", 1), "combinations": (f"{n_c} (combinations)", n_c),
                "all": (f"{n_s * n_c} (all)", None)}
    for label, k in (lockstep[name] for name in layouts):
        fn = jax.jit(lane_program(problem, SolverOptions(polish=False), k))
        t = time.perf_counter()
        jax.block_until_ready(fn(*args))
        tc = time.perf_counter() - t
        tr = _median_time(lambda: jax.block_until_ready(fn(*args)), 3)
        r = fn(*args)
        rows.append(tr)
        print(f"{label:>24s} {tc - tr:9.2f} {tr:7.3f} {int(np.sum(np.asarray(r.converged))):5d}/{n_s * n_c}")
    print("run time ratios to lanes in sequence: " + ", ".join(f"{r / rows[0]:.1f}x" for r in rows[1:]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spec", help="default designs/ore_pass.toml (designs/lidar_rangefinder.toml with --quick)")
    ap.add_argument("--repeats", type=int, default=30)
    ap.add_argument("--skip-cli", action="store_true")
    ap.add_argument("--quick", action="store_true", help=_support.QUICK_HELP)
    args = ap.parse_args()
    _support.require("bench_design.py", "scipy")
    if args.spec is None:
        args.spec = str(ROOT / "designs" / ("lidar_rangefinder.toml" if args.quick else "ore_pass.toml"))
    model, combo, problem, theta = _setup(args.spec)
    print(f"spec {args.spec}; combination: {model.combinations[combo].options}; variables {model.variable_names}")
    if args.quick:
        comparison(model, combo, problem, theta, 2)
        tolerance_sweep(model, combo, problem, theta, 2, tolerances=(1e-6,))
        batch_throughput(model, combo, problem, theta, (4,), layouts=BATCH_LAYOUTS[1:])
        lanes_in_lockstep(model, problem, n_starts=2, layouts=("sequence", "all"))
        print("\n== 4. process cold start: skipped with --quick ==")
        return
    comparison(model, combo, problem, theta, args.repeats)
    tolerance_sweep(model, combo, problem, theta, args.repeats)
    batch_throughput(model, combo, problem, theta, (16, 256))
    lanes_in_lockstep(model, problem)
    if not args.skip_cli:
        cli_cold_start(args.spec)


if __name__ == "__main__":
    main()
