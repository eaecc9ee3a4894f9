"""``[options] fidelity = "fast"`` on the shipped designs: how far the fast answer is from the exact
one, and how much sooner it comes.

For each design in ``designs/`` the spec as shipped (exact) and its fast twin: ``fidelity = "fast"``
with every option the spec sets to its chain's default removed (an explicit default is what the
fast choices replace; ``detectability = "exact"`` in the ore pass, say). A design whose fast twin
switches nothing (its sensor has no atlas-approved fast choice, or its spec sets the option to a
non-default value, like ``detectability = "given"``) gets one line saying so. Otherwise both are
optimised in this process (``optimize_design``, 8 starts): the first call (tracing, compiling
and solving) and the median of ``--repeats`` warm calls, and the fast answer is re-evaluated with
the exact models (:func:`diffsense.design.exact_check.exact_recheck`): the largest change of a
requirement value, whether every requirement still holds, and the fast optimum's objective
against the exact optimum's (relative).

Run: python benchmarks/bench_fidelity_designs.py [--designs ore_pass,...] [--repeats 5] [--quick]
``--quick``: the ore pass only, one warm repeat (a check that the benchmark runs).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
import tomllib

import _support

import diffsense  # noqa: F401  (float64)
from diffsense.design.exact_check import exact_recheck
from diffsense.design.model import DesignModel
from diffsense.design.optimizer import optimize_design
from diffsense.design.record import design_record
from diffsense.design.spec import load_spec, parse_spec
from diffsense.scene import CHAINS


def fast_twin(path):
    """The spec at ``path`` with ``fidelity = "fast"`` and its explicitly default options removed."""
    raw = tomllib.loads(path.read_text())
    defaults = CHAINS[raw["sensor"]].options
    options = {k: v for k, v in raw.get("options", {}).items() if not (k in defaults and defaults[k][0] == v)}
    raw["options"] = dict(options, fidelity="fast")
    return parse_spec(raw, path)


def timed_optimum(spec, repeats: int):
    model = DesignModel(spec)
    t0 = time.perf_counter()
    first = optimize_design(model)
    first_s = time.perf_counter() - t0
    warm = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        optimize_design(model)
        warm.append(time.perf_counter() - t0)
    return model, first, first_s, statistics.median(warm)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help=_support.QUICK_HELP)
    ap.add_argument("--designs", default="", help="comma-separated design names (default: every shipped one)")
    ap.add_argument("--repeats", type=int, default=5, help="warm optimize_design calls per spec (median)")
    args = ap.parse_args(argv)
    names = [s for s in args.designs.split(",") if s] or (["ore_pass"] if args.quick else
                                                          sorted(p.stem for p in (_support.ROOT / "designs").glob("*.toml")))
    repeats = 1 if args.quick else args.repeats
    print(f"# fidelity fast against exact on the shipped designs, {time.strftime('%Y-%m-%d')}, "
          f"optimize_design with 8 starts, warm: median of {repeats}")
    print(f"{'design':<28} {'switched':<28} {'first s exact/fast':>19} {'warm s exact/fast':>18} {'ratio':>6} "
          f"{'largest change':>15} {'exact met':>9} {'objective rel':>13}")
    for name in names:
        path = _support.ROOT / "designs" / f"{name}.toml"
        fast = fast_twin(path)
        if not fast.fidelity_switched:
            print(f"{name:<28} {'nothing (no fast choice)':<28}")
            continue
        exact_model, exact_opt, exact_first, exact_warm = timed_optimum(load_spec(path), repeats)
        fast_model, fast_opt, fast_first, fast_warm = timed_optimum(fast, repeats)
        rows = design_record(fast_model, fast_opt.x, fast_opt.combo_index)["requirements"]
        check = exact_recheck(fast_model, fast_opt.x, fast_opt.combo_index, rows)
        switched = ", ".join(f"{k}={v}" for k, v in check["switched"].items())
        rel = abs(fast_opt.objective - exact_opt.objective) / max(abs(exact_opt.objective), 1e-300)
        largest = max(check["requirements"], key=lambda r: abs(r["difference"]))
        print(f"{name:<28} {switched:<28} {exact_first:>9.2f}/{fast_first:<9.2f} {exact_warm:>9.3f}/{fast_warm:<8.3f} "
              f"{exact_warm / fast_warm:>6.2f} {largest['difference']:>11.2e} {largest['unit']:<3} "
              f"{str(check['met']):>9} {rel:>13.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
