"""Benchmark of the design optimizer on a shipped spec (default ``designs/ore_pass.toml``).

The model is the spec's own (``DesignModel``): the best catalog combination of the full run
(94 GHz, Gunn oscillator) with the integer pulse count relaxed, from the spec's initial design.

1. Side by side, from the same start on the same model: diffsense's solve (augmented
   Lagrangian over BFGS, exact gradients through the chain, one jitted program; and its SQP
   method, ``SolverOptions(method="sqp")``) against
   ``scipy.optimize.minimize(method="SLSQP")`` with finite-difference gradients (jac=None,
   scipy's 2-point differences) and with the exact JAX gradients, calling the same jitted
   model functions. Reported: warm time per solve (median), compile time, the optimum's
   objective, its relative error against the best objective found by any method, the largest
   requirement violation (scaled), and time ratios.
2. Tolerance sweep: diffsense solve time against objective error for tol = 1e-4 … 1e-10.
3. Batch throughput: a sweep of the required detection margin over B specs in one call of
   ``make_batch_solver`` (compile excluded), with the specs solved one after another
   (``lockstep=1``, the CPU default) and all in one vmap (``lockstep=None``).
4. Process cold start: ``diffsense optimize`` of the whole spec (all catalog combinations,
   8 starts, integer rounding) in a fresh process with an empty compilation cache and again
   with the cache it filled.
5. Lanes in lockstep: the design optimiser's first step (every catalog combination from each
   of 8 starts: one lane per pair) as one compiled call, with ``lockstep`` = 1 (lanes in
   sequence, ``lax.map``), the number of combinations (one start's catalog options per vmap)
   and all lanes in one vmap. Compile and warm run time, converged lanes.

Run: python benchmarks/bench_design.py [--spec designs/ore_pass.toml] [--repeats 10] [--skip-cli]
Times are wall-clock on this machine (2 cores, possibly shared: ratios measured in one run).
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

import jax
import jax.numpy as jnp
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import diffsense  # noqa: E402,F401
from diffsense.design import DesignModel  # noqa: E402
from diffsense.design_optimizer import _tight_limits, build_problem  # noqa: E402
from diffsense.optimize import SolverOptions, solve  # noqa: E402
from diffsense.spec import load_spec  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_optimizer import _median_time  # noqa: E402


def _setup(spec_path):
    model = DesignModel(load_spec(spec_path))
    combo = None
    for c in model.combinations:
        if "94" in " ".join(str(v) for v in c.values.values()) or c.values.get("freq_hz") == 94e9:
            if "Gunn" in " ".join(c.options.values()):
                combo = c.index
    combo = 0 if combo is None else combo
    problem = build_problem(model)
    limits = _tight_limits(model, 1e-7)
    theta = (jnp.asarray(model.combo_table[combo]), jnp.asarray(limits), jnp.asarray(model.initial),
             jnp.zeros(len(model.initial), dtype=bool))
    return model, combo, problem, theta


def _violation(model, x, combo):
    v = np.asarray(model.evaluate_all(x, model.combo_table[combo])[1])
    return float(np.max(np.maximum(model.sign * (v - model.limits) / model.scales, 0.0)))


def _objective(model, x, combo):
    return float(model.evaluate_all(x, model.combo_table[combo])[2])


def run_ours(model, problem, theta, options, repeats):
    fn = jax.jit(lambda x0, th: solve(problem, x0, th, options))
    x0 = jnp.asarray(model.initial)
    t = time.perf_counter()
    r = jax.block_until_ready(fn(x0, theta))
    t_compile = time.perf_counter() - t
    t_solve = _median_time(lambda: jax.block_until_ready(fn(x0, theta)), repeats)
    return np.asarray(r.x), bool(r.converged), t_compile, t_solve


def run_slsqp(model, problem, theta, exact_gradients, repeats):
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
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return minimize(fun, z0, jac=jac, method="SLSQP", bounds=list(zip(zlo, zhi)), constraints=cons,
                            options={"ftol": 1e-10, "maxiter": 500})

    out = once()  # compiles the jitted callables
    nfev["n"] = 0
    t = _median_time(once, repeats)
    return to_x(out.x), bool(out.success), t, nfev["n"] // repeats


def comparison(model, combo, problem, theta, repeats):
    print("\n== 1. one solve on the model, same start: diffsense vs scipy SLSQP ==")
    rows = []
    x, conv, tc, ts = run_ours(model, problem, theta, SolverOptions(polish=False), repeats)
    rows.append(("diffsense (AL + BFGS, exact gradients)", x, conv, ts, tc, ""))
    x, conv, tc, ts = run_ours(model, problem, theta, SolverOptions(method="sqp"), repeats)
    rows.append(("diffsense (SQP, method='sqp')", x, conv, ts, tc, ""))
    for exact in (False, True):
        x, ok, t, nfev = run_slsqp(model, problem, theta, exact, max(1, repeats // 2))
        label = "scipy SLSQP, " + ("exact JAX gradients" if exact else "finite differences")
        rows.append((label, x, ok, t, float("nan"), f"{nfev} f-evals"))
    best = min(_objective(model, r[1], combo) for r in rows if _violation(model, r[1], combo) <= 1e-6)
    t_ours = rows[0][3]
    print(f"{'method':42s} {'time ms':>9s} {'compile s':>9s} {'objective':>12s} {'rel err':>9s} {'violation':>9s} "
          f"{'time x':>7s}  note")
    for label, x, ok, t, tc, note in rows:
        obj = _objective(model, x, combo)
        viol = _violation(model, x, combo)
        print(f"{label:42s} {t*1e3:9.2f} {tc:9.2f} {obj:12.8f} {abs(obj-best)/abs(best):9.1e} {viol:9.1e} "
              f"{t/t_ours:7.1f}  {'' if ok else 'not converged '}{note}")
    print("rel err: against the best feasible objective of the four; violation: largest scaled requirement "
          "violation; time x = time / diffsense time")


def tolerance_sweep(model, combo, problem, theta, repeats):
    print("\n== 2. diffsense: solve time against objective error (tolerance sweep) ==")
    ref_x, _, _, _ = run_ours(model, problem, theta, SolverOptions(polish=False, tol=1e-11, feas_tol=1e-11), 1)
    ref = _objective(model, ref_x, combo)
    print(f"{'tol':>8s} {'time ms':>9s} {'rel err':>9s} {'violation':>9s}")
    for tol in (1e-4, 1e-6, 1e-8, 1e-10):
        x, conv, _, ts = run_ours(model, problem, theta, SolverOptions(polish=False, tol=tol, feas_tol=tol), repeats)
        obj = _objective(model, x, combo)
        print(f"{tol:8.0e} {ts*1e3:9.2f} {abs(obj-ref)/abs(ref):9.1e} {_violation(model, x, combo):9.1e}"
              f"{'' if conv else '  not converged'}")


def batch_throughput(model, combo, problem, theta, sizes):
    print("\n== 3. batch: sweep of the first requirement's limit, one compiled call (make_batch_solver) ==")
    from diffsense.optimize import make_batch_solver

    print(f"{'lockstep':>22s} {'B':>6s} {'compile s':>9s} {'time s':>8s} {'ms/spec':>8s} {'converged':>9s}")
    for label, lockstep in (("in sequence (1)", 1), ("one vmap (None)", None)):
        fn = make_batch_solver(problem, SolverOptions(polish=False), lockstep=lockstep)
        for B in sizes:
            lims = np.tile(np.asarray(theta[1]), (B, 1))
            lims[:, 0] = lims[:, 0] + np.linspace(-3.0, 1.0, B) * model.scales[0]
            x0 = jnp.asarray(np.tile(model.initial, (B, 1)))
            th = (jnp.broadcast_to(theta[0], (B,) + theta[0].shape), jnp.asarray(lims), x0,
                  jnp.broadcast_to(theta[3], (B,) + theta[3].shape))
            t = time.perf_counter()
            r = jax.block_until_ready(fn(x0, th))
            tc = time.perf_counter() - t
            t = time.perf_counter()
            r = jax.block_until_ready(fn(x0, th))
            tr = time.perf_counter() - t
            print(f"{label:>22s} {B:6d} {tc - tr:9.2f} {tr:8.3f} {tr / B * 1e3:8.1f} "
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


def lanes_in_lockstep(model, problem):
    print("\n== 5. design optimiser's first step: all (start, combination) lanes in one call ==")
    from diffsense.design_optimizer import lane_grid, lane_solver
    from diffsense.optimize.multistart import start_points

    starts = np.vstack([model.initial[None, :], start_points(problem, 7, seed=0, method="lhs")])
    n_c, n_s = len(model.combinations), starts.shape[0]
    args = tuple(jnp.asarray(c) for c in lane_grid(model, starts, _tight_limits(model, 1e-7)))
    print(f"{'lanes per vmap':>24s} {'compile s':>9s} {'run s':>7s} {'converged':>9s}")
    rows = []
    for label, k in (("1 (in sequence)", 1), (f"{n_c} (combinations)", n_c), (f"{n_s * n_c} (all)", None)):
        fn = lane_solver(problem, SolverOptions(polish=False), k)
        t = time.perf_counter()
        jax.block_until_ready(fn(*args))
        tc = time.perf_counter() - t
        tr = _median_time(lambda: jax.block_until_ready(fn(*args)), 3)
        r = fn(*args)
        rows.append(tr)
        print(f"{label:>24s} {tc - tr:9.2f} {tr:7.3f} {int(np.sum(np.asarray(r.converged))):5d}/{n_s * n_c}")
    print(f"run time ratios to lanes in sequence: {rows[1] / rows[0]:.1f}x, {rows[2] / rows[0]:.1f}x")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spec", default=str(ROOT / "designs" / "ore_pass.toml"))
    ap.add_argument("--repeats", type=int, default=10)
    ap.add_argument("--skip-cli", action="store_true")
    args = ap.parse_args()
    model, combo, problem, theta = _setup(args.spec)
    print(f"spec {args.spec}; combination: {model.combinations[combo].options}; variables {model.variable_names}")
    comparison(model, combo, problem, theta, args.repeats)
    tolerance_sweep(model, combo, problem, theta, args.repeats)
    batch_throughput(model, combo, problem, theta, (16, 256))
    lanes_in_lockstep(model, problem)
    if not args.skip_cli:
        cli_cold_start(args.spec)


if __name__ == "__main__":
    main()
