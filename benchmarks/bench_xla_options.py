"""XLA:CPU options against each design program's compile time and run time.

Each program of a shipped spec (:mod:`diffsense.design.programs`: ``lanes``, ``check``,
``evaluation``, ``search``, ``dense``) is traced once (``jax.export``) and compiled with each
option set below, without any cache; its run time is the median of 5 calls after a first one:
the lane program on 8 lanes of the optimiser's first step (the first 8 (start, combination)
pairs, slots from a search at their starts), the others on 8 rows (``dense``: one design) at
the spec's initial design (``evaluation``: each row's tangent along one variable).

Option sets (``compiler_options`` of ``jax.jit``):

* optimized — ``xla_cpu_use_fusion_emitters=False`` (``diffsense.optimize.compile``, "optimized", what
  ``lanes``, ``check``, ``outputs`` and ``evaluation`` ship with);
* XLA default — no option;
* O0 / O1 — optimized plus ``xla_backend_optimization_level`` 0 / 1 (O0 is the "fast" preset,
  what ``search`` and ``dense`` ship with);
* no expensive passes — optimized plus ``xla_llvm_disable_expensive_passes``;
* effort −1 — optimized plus ``exec_time_optimization_effort=-1``.

``--sets`` picks option sets by label (comma separated); ``--rounds R`` compiles every program
with every set R times, the sets interleaved within each round (the machine's speed drifts, so a
comparison is made side by side).

Run: python benchmarks/bench_xla_options.py [--quick] [--spec designs/ore_pass.toml]
     [--programs lanes,check,evaluation,search,dense]
     [--sets "optimized,no expensive passes"] [--rounds 3]
``--quick``: the lidar spec's ``check`` program with the optimized and default sets only.
"""

from __future__ import annotations

import argparse
import time

import _support  # noqa: F401  (puts the repository on sys.path)
import jax
import numpy as np

import diffsense  # noqa: F401
from diffsense.design.model import DesignModel
from diffsense.design.optimizer import _starts, _thetas, tight_limits
from diffsense.design.programs import stack
from diffsense.design.runner import Runner, objective_scale
from diffsense.design.spec import load_spec
from diffsense.optimize import SolverOptions
from diffsense.optimize.programs import _named

SHIPPED = {"xla_cpu_use_fusion_emitters": False}
OPTION_SETS = {
    "optimized": SHIPPED,
    "XLA default": {},
    "O0": {**SHIPPED, "xla_backend_optimization_level": 0},
    "O1": {**SHIPPED, "xla_backend_optimization_level": 1},
    "no expensive passes": {**SHIPPED, "xla_llvm_disable_expensive_passes": True},
    "effort -1": {**SHIPPED, "exec_time_optimization_effort": -1.0},
}


def program_cases(model: DesignModel, names):
    """(program, arguments of one call) per program name."""
    cases = {}
    if "lanes" in names:
        run = Runner(model, SolverOptions(polish=False), "auto", 8)
        C = len(model.combinations)
        starts = _starts(model, 8, 0)
        x0 = np.repeat(starts, C, axis=0)[:8]
        combos = np.tile(np.arange(C), starts.shape[0])[:8]
        theta = _thetas(model, model.inputs(), combos, tight_limits(model, 1e-7), objective_scale(model))
        theta, _ = run.search_points(x0, theta, combos)
        lower, upper = run.boxes(n=8)
        X = np.hstack([x0, np.zeros((8, 1))])
        cases["lanes"] = (run.program, (X, theta, lower, upper, np.broadcast_to(run.scale, X.shape)))
    programs = model.programs
    V = np.stack([model.design_values(model.initial, 0)] * 8)
    rows = stack([model.inputs()] * 8)
    if "check" in names:
        cases["check"] = (programs.check(), (V, rows))
    if "evaluation" in names:
        cases["evaluation"] = (programs.evaluation(), (V, np.eye(V.shape[1])[np.arange(8) % V.shape[1]], rows))
    if model.intervals.indices and "search" in names:
        cases["search"] = (programs.search(), (V, rows))
    if model.intervals.indices and "dense" in names:
        cases["dense"] = (programs.dense(), (V[0], model.inputs()))
    return cases


def measure(program, args, options: dict):
    """(compile seconds, median run seconds) of ``program`` compiled with ``options``."""
    call = _named(program._exported().call, program.name)
    t0 = time.perf_counter()
    compiled = jax.jit(call, compiler_options=options).lower(*program.avals).compile()
    compile_s = time.perf_counter() - t0
    jax.block_until_ready(compiled(*args))
    times = []
    for _ in range(5):
        t = time.perf_counter()
        jax.block_until_ready(compiled(*args))
        times.append(time.perf_counter() - t)
    return compile_s, float(np.median(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=_support.QUICK_HELP)
    parser.add_argument("--spec", default=None, help="spec file (default designs/ore_pass.toml)")
    parser.add_argument("--programs", default="lanes,check,search,dense")
    parser.add_argument("--sets", default=None, help="option sets by label, comma separated (default: all)")
    parser.add_argument("--rounds", type=int, default=1, help="compilations of each program with each set")
    args = parser.parse_args()
    spec = args.spec or str(_support.ROOT / "designs" / ("lidar_rangefinder.toml" if args.quick else "ore_pass.toml"))
    names = ["check"] if args.quick else args.programs.split(",")
    labels = ("optimized", "XLA default") if args.quick else (args.sets.split(",") if args.sets else OPTION_SETS)
    unknown = [k for k in labels if k not in OPTION_SETS]
    if unknown:
        parser.error(f"--sets: unknown option set {unknown[0]!r}; choose from {', '.join(OPTION_SETS)}")
    sets = {k: OPTION_SETS[k] for k in labels}
    jax.config.update("jax_compilation_cache_dir", None)
    model = DesignModel(load_spec(spec))
    print(f"# XLA:CPU options, {spec.split('/')[-1]}: compile s / run ms of one call")
    print(f"{'program':8s} {'options':20s} {'compile s':>10s} {'run ms':>10s}")
    for name, (program, call_args) in program_cases(model, names).items():
        program.pool = None
        for label, options in [(k, v) for _ in range(max(1, args.rounds)) for k, v in sets.items()]:
            try:
                compile_s, run_s = measure(program, call_args, options)
            except Exception as exc:  # noqa: BLE001 - an option this XLA lacks: say so, go on
                print(f"{name:8s} {label:20s} rejected: {str(exc).splitlines()[0][:60]}")
                continue
            print(f"{name:8s} {label:20s} {compile_s:10.2f} {1e3 * run_s:10.2f}", flush=True)


if __name__ == "__main__":
    main()
