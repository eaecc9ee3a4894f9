"""Run time against error for every model choice a spec can make, and every numerical knob the
solver turns: one atlas, side by side in one run.

Each family (``benchmarks/_fidelity_<family>.py``, see ``_fidelity_support.py``) measures every
choice the package offers for one decision — warm time per evaluation, size of its optimised
program (HLO operations), worst error over the family's domain grid against the package's most
exact choice and against an independent reference (mpmath, a published table, quadrature of the
definition) — and names the fastest choice within a stated bound (what ``[options] fidelity =
"fast"`` takes).

Prints one table per family; without ``--quick`` writes ``docs/speed_accuracy.md`` (the tables,
the default choice per family and why) and one figure per family in ``docs/figures/`` (time per
evaluation against worst error against the reference, log–log, one marker per choice, the
Pareto-best choices joined).

Run: python benchmarks/bench_fidelity.py [--quick] [--only FAMILY,...] [--docs DIR]
(needs the ``bench`` extras: scipy and mpmath). ``--quick`` runs every family on small grids with
few repeats and draws its figures into a temporary folder (docs/ is left as it is).
"""

from __future__ import annotations

import argparse
import importlib
import math
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import _support

_support.require("bench_fidelity.py", "scipy", "mpmath")

import jax  # noqa: E402

jax.config.update("jax_enable_x64", True)

from _fidelity_support import Family, pareto  # noqa: E402

HERE = Path(__file__).resolve().parent


def family_modules(only=None):
    """The family modules, in file-name order (``only``: the module suffixes to keep)."""
    names = sorted(p.stem for p in HERE.glob("_fidelity_*.py") if p.stem != "_fidelity_support")
    if only:
        names = [n for n in names if n[len("_fidelity_"):] in only]
    return [importlib.import_module(n) for n in names]


def _num(x, digits=3) -> str:
    if x is None:
        return "–"
    if isinstance(x, float) and (math.isnan(x)):
        return "n/a"
    if isinstance(x, float) and math.isinf(x):
        return "inf"
    if isinstance(x, int):
        return str(x)
    return f"{x:.{digits}g}"


def table_lines(f: Family):
    """The Markdown table of one family."""
    best = {c.name for c in pareto(f.choices)}
    lines = [f"| choice | time per evaluation | HLO ops | worst error vs {f.exact} ({f.error_unit}) | "
             f"worst error vs reference ({f.error_unit}) | Pareto-best | note |", "|---|---|---|---|---|---|---|"]
    for c in f.choices:
        timed = f"{_num(c.seconds_per_eval)} s" if math.isfinite(c.seconds_per_eval) else "not timed"
        lines.append(f"| {c.name} | {timed} | {_num(c.hlo_ops)} | {_num(c.error_vs_exact)} | "
                     f"{_num(c.error_vs_reference)} | {'yes' if c.name in best else ''} | {c.note} |")
    return lines


def family_text(f: Family, figure=None):
    """The Markdown section of one family."""
    lines = [f"## {f.title}", "", f"Domain: {f.domain}", "", f"Reference: {f.reference}", ""]
    lines += table_lines(f) + [""]
    lines.append(f"Default: **{f.default}** — {f.why_default}")
    if not f.model_option:
        lines.append(f"A solver or spec setting, which `fidelity` leaves to the spec; the fastest choice within the "
                     f"bound ({f.fast_bound}): **{f.fast or f.default}**.")
    elif f.fast:
        lines.append(f"`fidelity = \"fast\"` takes **{f.fast}** ({f.fast_bound}).")
    else:
        lines.append(f"`fidelity = \"fast\"` keeps the default: {f.fast_bound or 'no faster choice meets the bound'}.")
    if figure is not None:
        lines += ["", f"![{f.title}: time per evaluation against worst error]({figure})"]
    return lines + [""]


def draw(f: Family, path: Path) -> Path:
    """Time per evaluation against worst error vs the reference, log–log, one marker per choice,
    the Pareto-best choices joined."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.4), layout="constrained")
    floor = 1e-17
    for c in f.choices:
        if not (c.seconds_per_eval > 0 and math.isfinite(c.seconds_per_eval)):
            continue
        err = max(c.error_vs_reference, floor) if math.isfinite(c.error_vs_reference) else None
        if err is None:
            continue
        ax.loglog(c.seconds_per_eval, err, "o", ms=7)
        ax.annotate(c.name, (c.seconds_per_eval, err), textcoords="offset points", xytext=(6, 4), fontsize=8)
    front = [c for c in pareto(f.choices) if c.seconds_per_eval > 0 and math.isfinite(c.error_vs_reference)]
    if len(front) > 1:
        ax.loglog([c.seconds_per_eval for c in front], [max(c.error_vs_reference, floor) for c in front], "-",
                  color="0.5", lw=1, zorder=0, label="Pareto-best choices")
        ax.legend(loc="best", fontsize=8)
    ax.set_xlabel("time per evaluation (s, warm)")
    ax.set_ylabel(f"worst error vs reference ({f.error_unit})")
    ax.set_title(f.title, fontsize=10, wrap=True)
    ax.grid(True, which="both", alpha=0.3)
    ax.margins(0.25)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _commit() -> str:
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=HERE, capture_output=True,
                              text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help=_support.QUICK_HELP)
    ap.add_argument("--only", default="", help="comma-separated family modules (e.g. detection,solver)")
    ap.add_argument("--docs", default=str(HERE.parent / "docs"), help="where speed_accuracy.md and figures/ go")
    args = ap.parse_args(argv)
    only = [s for s in args.only.split(",") if s]
    t0 = time.perf_counter()
    families = []
    for mod in family_modules(only):
        t = time.perf_counter()
        got = mod.run(quick=args.quick)
        families += got
        print(f"# {mod.__name__}: {len(got)} famil{'y' if len(got) == 1 else 'ies'} in {time.perf_counter() - t:.1f} s",
              flush=True)
    docs = Path(tempfile.mkdtemp()) if args.quick else Path(args.docs)
    (docs / "figures").mkdir(parents=True, exist_ok=True)
    sections = []
    for f in families:
        print()
        fast = (f.fast or f.default) if f.model_option else f"(a setting) {f.fast or f.default}"
        print(f"{f.title} — errors in {f.error_unit}; default {f.default}; fast {fast}")
        for line in table_lines(f):
            print(line)
        fig = draw(f, docs / "figures" / f"fidelity_{f.key}.png")
        sections += family_text(f, f"figures/{fig.name}")
    header = ["# Run time against error: every model choice", "",
              f"Generated by `python benchmarks/bench_fidelity.py` on commit {_commit()}, "
              f"{time.strftime('%Y-%m-%d')}, {platform.machine()} with {jax.device_count()} JAX CPU device(s), "
              f"JAX {jax.__version__}, float64 unless a row says otherwise. Times are warm (compiled) "
              "medians per evaluation of a batch over the family's grid (solver knobs: per solve or check, as "
              "their notes say) on a 2-core machine; errors are the worst over the stated domain. "
              "`[options] fidelity = \"fast\"` takes, per family, the fastest choice whose worst error against "
              "the reference stays within the bound stated under its table.", ""]
    summary = ["| family | default | fast | bound |", "|---|---|---|---|"]
    for f in families:
        fast = (f.fast or f.default) if f.model_option else f"– (a setting; fastest within the bound: {f.fast or f.default})"
        summary.append(f"| {f.title} | {f.default} | {fast} | {f.fast_bound or '–'} |")
    text = "\n".join(header + summary + [""] + sections)
    (docs / "speed_accuracy.md").write_text(text)
    print(f"\nwrote {docs / 'speed_accuracy.md'} and {len(families)} figures in {docs / 'figures'} "
          f"({time.perf_counter() - t0:.1f} s)")


if __name__ == "__main__":
    sys.exit(main())
