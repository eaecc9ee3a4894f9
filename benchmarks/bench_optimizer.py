"""Benchmark of the constrained optimizer (diffsense.optimize).

1. Side by side with scipy.optimize.minimize(method="SLSQP") using finite-difference
   gradients (jac=None, scipy's 2-point differences) on the same reference problems
   (Hock–Schittkowski with published optima, Brooker's servo bandwidth eq. 14.12): time per
   solve, optimality error |f − f*| / max(1, |f*|), and their ratios. Both run from the
   published start. SLSQP calls the same JAX functions jitted for scalar use, so its
   per-call cost includes JAX dispatch (a few µs); its function-evaluation count is printed.
2. Tolerance sweep: solve time versus optimality error for tol = 1e-4 … 1e-10, with and
   without the Newton polish.
3. Batch throughput: a vmapped θ sweep of the servo problem and of HS071 starts on one
   device, and the same batch sharded over N forced host devices (run in a subprocess with
   XLA_FLAGS=--xla_force_host_platform_device_count=N).

Run: python benchmarks/bench_optimizer.py [--quick] [--json out.json]
Times are wall-clock medians on this machine (compile excluded and reported separately).
``--quick`` runs the same tables on a few problems with 2 repeats, batches of 16 and 8 and one
sharded run: a check that the benchmark works, not a measurement.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import textwrap
import time
import warnings
from pathlib import Path

import _support
import jax
import jax.numpy as jnp
import numpy as np

import diffsense  # noqa: F401
from diffsense.optimize import SolverOptions, make_batch_solver, make_solver
from diffsense.optimize import reference_problems as rp

PROBLEMS = ["hs001", "hs007", "hs021", "hs028", "hs035", "hs039", "hs065", "hs071", "hs076", "hs100",
            "servo_bandwidth"]
QUICK_PROBLEMS = ["hs071", "hs100", "servo_bandwidth"]
TOLERANCES = (1e-4, 1e-6, 1e-8, 1e-10)
SWEEP_PROBLEMS = ["hs071", "hs100", "hs065"]
_median_time = _support.median_time


def _opt_error(f, f_star):
    return abs(float(f) - f_star) / max(1.0, abs(f_star))


def run_ours(P, options, repeats, compile="optimized"):
    solver = make_solver(P.problem, options, compile=compile)
    x0 = jnp.asarray(P.x0)
    t = time.perf_counter()
    r = jax.block_until_ready(solver(x0, P.theta))
    t_compile = time.perf_counter() - t
    t_solve = _median_time(lambda: jax.block_until_ready(solver(x0, P.theta)), repeats)
    return r, t_compile, t_solve


def run_slsqp(P, repeats, tol=1e-10):
    from scipy.optimize import minimize

    prob, th = P.problem, P.theta
    f = jax.jit(lambda x: prob.f(x, th))
    g = jax.jit(lambda x: prob.g(x, th))
    h = jax.jit(lambda x: prob.h(x, th))
    m, p = prob.constraint_sizes(th)
    cons = []
    if m:
        cons.append({"type": "ineq", "fun": lambda x: -np.asarray(g(x))})
    if p:
        cons.append({"type": "eq", "fun": lambda x: np.asarray(h(x))})
    lo, hi = np.asarray(prob.lower), np.asarray(prob.upper)
    bounds = [(None if not np.isfinite(a) else a, None if not np.isfinite(b) else b) for a, b in zip(lo, hi)]
    x0 = np.clip(P.x0, lo, hi)

    def solve():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return minimize(lambda x: float(f(x)), x0, method="SLSQP", jac=None, bounds=bounds, constraints=cons,
                            options={"ftol": tol, "maxiter": 500})

    out = solve()  # warm the jitted callables
    t = _median_time(solve, repeats)
    return out, t


def comparison(repeats, problems=PROBLEMS):
    rows = []
    print("\n== 1. diffsense (AL + BFGS + Newton polish, float64, jitted) vs scipy SLSQP (finite differences) ==")
    print(f"{'problem':17s} {'ours ms':>9s} {'compile s':>9s} {'ours err':>9s} {'SLSQP ms':>9s} {'SLSQP err':>9s} "
          f"{'nfev':>5s} {'time x':>7s}  note")
    for name in problems:
        P = getattr(rp, name)()
        r, tc, ts = run_ours(P, SolverOptions(), repeats)
        out, tsl = run_slsqp(P, repeats)
        e_ours = _opt_error(r.f, P.f_star)
        e_sl = _opt_error(out.fun, P.f_star)
        note = "" if out.success else "SLSQP: " + str(out.message)[:30]
        if not bool(r.converged):
            note += " ours: not converged"
        rows.append(dict(problem=P.name, ours_ms=ts * 1e3, ours_compile_s=tc, ours_err=e_ours, slsqp_ms=tsl * 1e3,
                         slsqp_err=e_sl, slsqp_nfev=int(out.nfev), time_ratio=tsl / ts,
                         ours_converged=bool(r.converged), slsqp_success=bool(out.success)))
        print(f"{P.name:17s} {ts*1e3:9.3f} {tc:9.2f} {e_ours:9.1e} {tsl*1e3:9.3f} {e_sl:9.1e} {int(out.nfev):5d} "
              f"{tsl/ts:7.2f}  {note}")
    print("errors: |f - f*|/max(1,|f*|) against the published f* (HS values carry 7-10 digits, so errors "
          "below ~1e-9 are at the precision of the reference); time x = SLSQP time / ours")
    return rows


def tolerance_sweep(repeats, problems=SWEEP_PROBLEMS, tolerances=TOLERANCES):
    rows = []
    print("\n== 2. tolerance sweep: solve time vs optimality error ==")
    print(f"{'problem':8s} {'tol':>7s} {'polish':>6s} {'ms':>8s} {'f err':>9s} {'stationarity':>12s} {'outer':>5s} "
          f"{'inner':>6s}")
    for name in problems:
        P = getattr(rp, name)()
        for polish in (True, False):
            for tol in tolerances:
                opts = SolverOptions(tol=tol, feas_tol=tol, polish=polish)
                r, _, ts = run_ours(P, opts, repeats, compile="fast")
                e = _opt_error(r.f, P.f_star)
                rows.append(dict(problem=P.name, tol=tol, polish=polish, ms=ts * 1e3, err=e,
                                 stationarity=float(r.kkt.stationarity), outer=int(r.iterations),
                                 inner=int(r.inner_iterations), converged=bool(r.converged)))
                print(f"{P.name:8s} {tol:7.0e} {str(polish):>6s} {ts*1e3:8.3f} {e:9.1e} "
                      f"{float(r.kkt.stationarity):12.1e} {int(r.iterations):5d} {int(r.inner_iterations):6d}")
    return rows


_SHARD_SCRIPT = textwrap.dedent("""
    import json, sys, time
    import jax, jax.numpy as jnp, numpy as np
    sys.path.insert(0, {repo!r})
    import diffsense
    from diffsense.optimize import SolverOptions, make_batch_solver
    from diffsense.optimize import reference_problems as rp
    B = {B}
    P = rp.servo_bandwidth()
    th = {{k: jnp.broadcast_to(v, (B,)) for k, v in P.theta.items()}}
    th["snr"] = jnp.logspace(0.0, 3.0, B)
    th["range_m"] = jnp.linspace(300.0, 30000.0, B)
    fn = make_batch_solver(P.problem, SolverOptions(), shard=True)
    x0 = jnp.array([1.0])
    t = time.perf_counter(); r = jax.block_until_ready(fn(x0, th)); tc = time.perf_counter() - t
    ts = []
    for _ in range(3):
        t = time.perf_counter(); jax.block_until_ready(fn(x0, th)); ts.append(time.perf_counter() - t)
    H = rp.hs071()
    xs = jnp.asarray(np.random.default_rng(0).uniform(1.0, 5.0, ({BH}, 4)))
    fh = make_batch_solver(H.problem, SolverOptions(), shard=True)
    jax.block_until_ready(fh(xs, None))
    th_ = []
    for _ in range(3):
        t = time.perf_counter(); jax.block_until_ready(fh(xs, None)); th_.append(time.perf_counter() - t)
    print(json.dumps({{"devices": jax.device_count(), "servo_s": float(np.median(ts)), "compile_s": tc,
                      "hs071_s": float(np.median(th_)), "converged": float(np.mean(np.asarray(r.converged)))}}))
""")


def batch_throughput(B, BH, device_counts):
    print("\n== 3. batch throughput ==")
    rows = []
    P = rp.servo_bandwidth()
    th = {k: jnp.broadcast_to(v, (B,)) for k, v in P.theta.items()}
    th["snr"] = jnp.logspace(0.0, 3.0, B)
    th["range_m"] = jnp.linspace(300.0, 30000.0, B)
    fn = make_batch_solver(P.problem, SolverOptions(), shard=False)
    x0 = jnp.array([1.0])
    r = jax.block_until_ready(fn(x0, th))
    t_vmap = _median_time(lambda: jax.block_until_ready(fn(x0, th)), 3)
    err = float(np.max(np.abs(np.asarray(r.x[:, 0]) / np.asarray(rp.servo_optimum_hz(th)) - 1)))
    single = make_solver(P.problem, SolverOptions())
    th0 = jax.tree_util.tree_map(lambda a: a[0], th)
    jax.block_until_ready(single(x0, th0))
    t_one = _median_time(lambda: jax.block_until_ready(single(x0, th0)), 20)
    print(f"servo sweep B={B}: vmapped {B / t_vmap:10.0f} solves/s ({t_vmap*1e3:.1f} ms per batch); "
          f"one-by-one jitted calls {1 / t_one:8.0f} solves/s; max rel. error vs eq. 14.12 {err:.1e}")
    rows.append(dict(case="servo_vmap", B=B, solves_per_s=B / t_vmap, single_solves_per_s=1 / t_one, max_rel_err=err))
    H = rp.hs071()
    xs = jnp.asarray(np.random.default_rng(0).uniform(1.0, 5.0, (BH, 4)))
    fh = make_batch_solver(H.problem, SolverOptions(), shard=False)
    rh = jax.block_until_ready(fh(xs, None))
    t_h = _median_time(lambda: jax.block_until_ready(fh(xs, None)), 3)
    ok = np.asarray(rh.converged)
    at_best = np.abs(np.asarray(rh.f) - H.f_star) <= 1e-7 * H.f_star
    print(f"HS071 random starts B={BH}: vmapped {BH / t_h:10.0f} solves/s; converged {ok.mean():.3f}, "
          f"reached f* {at_best.mean():.3f}")
    rows.append(dict(case="hs071_vmap", B=BH, solves_per_s=BH / t_h, converged=float(ok.mean()),
                     reached_fstar=float(at_best.mean())))
    repo = str(Path(__file__).resolve().parents[1])
    for n in device_counts:
        env = dict(os.environ, XLA_FLAGS=f"--xla_force_host_platform_device_count={n}", JAX_PLATFORMS="cpu")
        out = subprocess.run([sys.executable, "-c", _SHARD_SCRIPT.format(repo=repo, B=B, BH=BH)],
                             capture_output=True, text=True, env=env)
        if out.returncode != 0:
            print(f"sharded run with {n} devices failed: {out.stderr[-3000:]}")
            rows.append(dict(case="sharded_failed", devices=n))
            continue
        res = json.loads(out.stdout.strip().splitlines()[-1])
        print(f"sharded over {res['devices']} host devices: servo {B / res['servo_s']:10.0f} solves/s, "
              f"HS071 {BH / res['hs071_s']:10.0f} solves/s (compile {res['compile_s']:.1f} s)")
        rows.append(dict(case="sharded", devices=res["devices"], servo_solves_per_s=B / res["servo_s"],
                         hs071_solves_per_s=BH / res["hs071_s"]))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help=_support.QUICK_HELP)
    ap.add_argument("--json", help="write all numbers to this file")
    args = ap.parse_args()
    _support.require("bench_optimizer.py", "scipy")
    cpus = os.cpu_count() or 1
    print(f"jax {jax.__version__}, devices {jax.devices()}, cpu count {cpus}")
    if args.quick:
        out = {"comparison": comparison(2, QUICK_PROBLEMS),
               "tolerance_sweep": tolerance_sweep(2, SWEEP_PROBLEMS[:1], TOLERANCES[::2]),
               "batch": batch_throughput(16, 8, [cpus])}
    else:
        out = {"comparison": comparison(20), "tolerance_sweep": tolerance_sweep(5),
               "batch": batch_throughput(4096, 1024, [1, cpus])}
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1))
    if any(row["case"] == "sharded_failed" for row in out["batch"]):
        sys.exit("a sharded run failed (see above)")


if __name__ == "__main__":
    main()
