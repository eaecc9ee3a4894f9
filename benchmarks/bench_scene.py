"""Cost of scene structure: a minimal (clear-air) radar scene against a scene with every part.

For each scene it measures
  * the number of primitive equations of one traced evaluation (``count_equations``),
  * the compile time of the jitted, vmapped evaluation of a batch of parameter sets (every
    parameter batched, the range varying) at its first call,
  * the warm run time per evaluation (best of several calls, divided by the batch size),
  * the compile time and warm time of the gradient of the detection range (optional, slow).

The parameter values are those of :data:`BASE`; a required parameter that a newer chain has and
``BASE`` lacks is set to the middle of its documented domain, and the run says which.

Run: ``python benchmarks/bench_scene.py [--batch 256] [--repeats 5] [--grad] [--quick]``.
"""

from __future__ import annotations

import argparse
import math
import time

import _support
import jax
import jax.numpy as jnp

import diffsense  # noqa: F401
from diffsense.scene import Scene, complete_parameters, evaluate, parameter_table
from diffsense.sensors.parts import count_equations, traced_parts
from diffsense.sensors.radar import PARTS

BASE = dict(
    range_m=15e3, peak_power_w=5e4, pulse_width_s=0.5e-6, freq_hz=9.4e9, bandwidth_hz=1.2e6, noise_figure_db=3.0,
    prf_hz=2e3, n_pulses=12.0, antenna_diameter_m=1.5, jammer_power_w=5.0, jammer_gain_db=3.0,
    jammer_bandwidth_hz=50e6, target_height_m=20.0, antenna_height_m=15.0,
    # tracking part: alpha-beta gain, angle-servo noise bandwidth, positioner resonance (book
    # 14.6, Fig. 14.19: 10-30 Hz for a 1.5 m antenna)
    track_alpha=0.5, servo_bandwidth_hz=3.0, positioner_resonance_hz=30.0,
)


def _domain_middle(prm):
    """A value inside the documented domain of ``prm`` (geometric middle when it is positive)."""
    lo = prm.lo if prm.lo is not None else -math.inf
    hi = prm.hi if prm.hi is not None else math.inf
    if 0 < lo and math.isfinite(hi):
        return math.sqrt(lo * hi)
    if math.isfinite(lo) and math.isfinite(hi):
        return 0.5 * (lo + hi)
    return lo + 1.0 if math.isfinite(lo) else (hi - 1.0 if math.isfinite(hi) else 1.0)


def params(scene):
    """Every parameter of ``scene``: BASE where it has a value, stand-ins for required ones it lacks."""
    table = parameter_table(scene)
    given = {k: v for k, v in BASE.items() if k in table}
    stand_ins = {k: _domain_middle(p) for k, p in table.items() if p.default is None and k not in given}
    if stand_ins:
        print(f"note: no benchmark value in BASE for {sorted(stand_ins)}; using the middle of each domain")
    return complete_parameters(scene, {**given, **stand_ins})


def bench(name, scene, batch, repeats, with_grad):
    p = params(scene)
    jx = jax.make_jaxpr(lambda q: evaluate(scene, q).values)(p)
    row = dict(scene=name, parts=len(traced_parts(jx)), equations=count_equations(jx))

    # every parameter is batched (tiled), the ranges vary: each evaluation is computed in full
    batched = {k: jnp.full((batch,), v) for k, v in p.items()}
    batched["range_m"] = jnp.geomspace(1e3, 20e3, batch)
    fn = jax.jit(jax.vmap(lambda q: evaluate(scene, q).values))
    t0 = time.perf_counter()
    jax.block_until_ready(fn(batched))
    row["compile_s"] = time.perf_counter() - t0
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        jax.block_until_ready(fn(batched))
        best = min(best, time.perf_counter() - t0)
    row["warm_us_per_eval"] = best / batch * 1e6

    if with_grad:
        g = jax.jit(jax.grad(lambda q: evaluate(scene, q)["detection_range_m"]))
        t0 = time.perf_counter()
        jax.block_until_ready(g(p))
        row["grad_compile_s"] = time.perf_counter() - t0
        best = float("inf")
        for _ in range(repeats):
            t0 = time.perf_counter()
            jax.block_until_ready(g(p))
            best = min(best, time.perf_counter() - t0)
        row["grad_warm_ms"] = best * 1e3
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--batch", type=int, default=256)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--grad", action="store_true", help="also time the gradient of the detection range")
    ap.add_argument("--detectability", default="exact", choices=("exact", "book", "given"))
    ap.add_argument("--quick", action="store_true", help=_support.QUICK_HELP + " (batch 16, 2 repeats)")
    args = ap.parse_args()
    if args.quick:
        args.batch, args.repeats = 16, 2
    opts = {"swerling": 1, "detectability": args.detectability}
    scenes = [("minimal (clear air)", Scene("radar", [], opts)), ("full (all parts)", Scene("radar", list(PARTS), opts))]
    if args.detectability == "given":
        BASE["detectability_db"] = 12.0
    rows = [bench(name, s, args.batch, args.repeats, args.grad) for name, s in scenes]

    cols = ["scene", "parts", "equations", "compile_s", "warm_us_per_eval"]
    if args.grad:
        cols += ["grad_compile_s", "grad_warm_ms"]
    print(f"radar chain, detectability={args.detectability}, vmapped batch of {args.batch} parameter sets, "
          f"best of {args.repeats} warm runs; backend {jax.default_backend()}")
    print(" | ".join(f"{c:>18s}" for c in cols))
    for r in rows:
        cells = []
        for c in cols:
            v = r[c]
            cells.append(f"{v:>18s}" if isinstance(v, str) else f"{v:>18d}" if isinstance(v, int) else f"{v:>18.3f}")
        print(" | ".join(cells))
    a, b = rows
    print(f"full / minimal: equations x{b['equations'] / a['equations']:.1f}, compile x{b['compile_s'] / a['compile_s']:.1f}, "
          f"warm time x{b['warm_us_per_eval'] / a['warm_us_per_eval']:.1f}")


if __name__ == "__main__":
    main()
