"""Shared parts of ``bench_fidelity.py``: how a model choice is timed, sized and compared.

A *family* is one modelling decision a spec (or the solver) makes — detectability, gas
attenuation, multipath, clutter, the interval search grid … Each family module
(``benchmarks/_fidelity_<family>.py``) exposes ``run(quick: bool) -> Family``: every choice the
package offers for that decision, each

* timed warm per evaluation: the choice jitted over a batch of the family's domain grid, the
  median of several calls divided by the batch size (:func:`time_per_eval`);
* sized: the number of operations in its optimised HLO (:func:`hlo_ops`);
* compared: its worst error over the grid against the package's most exact choice
  (``error_vs_exact``) and against a reference that is not the code under test — mpmath, a
  published table, quadrature of the definition (``error_vs_reference``).

``bench_fidelity.py`` prints every family's table, writes ``docs/speed_accuracy.md`` and draws
one figure per family (time per evaluation against worst error, log–log, the Pareto-best
choices joined).
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass, field
from typing import Callable, Dict, List, Optional

import jax
import numpy as np


@dataclass
class Choice:
    """One choice of a family, measured."""

    name: str
    seconds_per_eval: float
    hlo_ops: Optional[int]
    error_vs_exact: float
    error_vs_reference: float
    note: str = ""


@dataclass
class Family:
    """One modelling decision and its measured choices."""

    key: str  # short identifier, used in file names ("detectability")
    title: str
    domain: str  # the grid the errors are taken over, in words
    error_unit: str  # "dB", "dB/km", "relative", ...
    reference: str  # what the independent reference is
    exact: str  # the name of the package's most exact choice
    default: str  # the choice a spec gets by default
    why_default: str
    choices: List[Choice] = field(default_factory=list)
    fast: Optional[str] = None  # the choice fidelity = "fast" takes (None: the default)
    fast_bound: Optional[str] = None  # the bound the fast choice meets, in words
    #: a model option ``[options] fidelity`` switches (False: a solver or spec setting, such as a
    #: search grid or a sample size, which the spec states and ``fidelity`` leaves alone)
    model_option: bool = True

    @property
    def by_name(self) -> Dict[str, Choice]:
        """The choices by name."""
        return {c.name: c for c in self.choices}


def time_per_eval(fn: Callable, *args, batch: int, repeats: int = 5) -> float:
    """Median seconds per element of ``fn(*args)`` (already jitted, ``batch`` elements per call),
    after one warm-up call (compilation excluded)."""
    jax.block_until_ready(fn(*args))
    ts = []
    for _ in range(repeats):
        t = time.perf_counter()
        jax.block_until_ready(fn(*args))
        ts.append(time.perf_counter() - t)
    return float(np.median(ts)) / batch


_OP = re.compile(r"^\s*(ROOT\s+)?%?[\w.\-]+\s*=\s*\S+\s+\w", re.M)


def hlo_ops(fn: Callable, *args) -> int:
    """Operations in the optimised HLO of ``jax.jit(fn)`` at ``args`` (instructions of every
    computation, fusions counted inside)."""
    text = jax.jit(fn).lower(*args).compile().as_text()
    return len(_OP.findall(text))


#: XLA presets (diffsense.optimize.compile): the package's default, and optimisation level 0 for
#: ``quick`` (a third of the compile time at about 1.5-3x the run time: quick times are indicative)
PRESET, QUICK_PRESET = "optimized", "fast"


def compile_all(jobs, quick: bool, alongside=None) -> list:
    """``(compiled, HLO operations)`` of each ``(fn, args)``, compiled two at a time in background
    threads (XLA compiles without Python's lock) with :data:`PRESET` (``quick``: :data:`QUICK_PRESET`),
    while this thread calls ``alongside()`` if given."""
    import concurrent.futures

    from diffsense.optimize.compile import jit_with_options

    preset = QUICK_PRESET if quick else PRESET
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        futures = [pool.submit(jit_with_options(fn, preset).lower(*args).compile) for fn, args in jobs]
        if alongside is not None:
            alongside()
        return [(c, len(_OP.findall(c.as_text()))) for c in (f.result() for f in futures)]


def measure_tiled(jobs, repeats: int, columns: int, quick: bool):
    """Per ``(fn, grid)`` of ``jobs`` (``grid``: a tuple of (rows, width) arrays, one row per static
    case): ``(values on the grid, seconds per point, HLO operations per row)``. Each grid is tiled
    to ``columns`` per row for the timing; the programs are compiled by :func:`compile_all`, then
    timed one after another."""
    tiled = [tuple(np.tile(np.asarray(a), (1, -(-columns // np.shape(a)[1]))) for a in grid) for _, grid in jobs]
    compiled = compile_all([(fn, args) for (fn, _), args in zip(jobs, tiled)], quick)
    out = []
    for (_, grid), args, (program, ops) in zip(jobs, tiled, compiled):
        width, rows = np.shape(grid[0])[1], np.shape(grid[0])[0]
        values = np.asarray(program(*args))[:, :width]
        seconds = time_per_eval(program, *args, batch=args[0].size, repeats=repeats)
        out.append((values, seconds, ops // rows))
    return out


def worst(a, b, relative: bool = False) -> float:
    """max |a − b| (or max |a − b| / |b|) over finite pairs; inf when ``a`` has a non-finite value
    where ``b`` is finite."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    ok = np.isfinite(b)
    if not np.all(np.isfinite(a[ok])):
        return float("inf")
    d = np.abs(a[ok] - b[ok])
    if relative:
        d = d / np.maximum(np.abs(b[ok]), 1e-300)
    return float(np.max(d)) if d.size else float("nan")


def pareto(choices: List[Choice]) -> List[Choice]:
    """The choices no other choice beats in both time per evaluation and error against the
    reference, sorted by time; a choice without a finite error (a number the user gives, whose
    error is the user's) is not ranked."""
    import math

    choices = [c for c in choices if math.isfinite(c.error_vs_reference) and math.isfinite(c.seconds_per_eval)]
    out = []
    for c in choices:
        if not any((o.seconds_per_eval <= c.seconds_per_eval and o.error_vs_reference <= c.error_vs_reference)
                   and (o.seconds_per_eval < c.seconds_per_eval or o.error_vs_reference < c.error_vs_reference)
                   for o in choices):
            out.append(c)
    return sorted(out, key=lambda c: c.seconds_per_eval)


def print_family(f: Family) -> None:
    """One family as plain text: its domain, reference, choices and the fast choice."""
    print(f"\n{f.title}\n  domain: {f.domain}\n  reference: {f.reference}")
    print(f"  errors in {f.error_unit}; exact: {f.exact}; default: {f.default} ({f.why_default})")
    print(f"  fast: {f.fast or 'the default'} — {f.fast_bound}")
    print(f"  {'choice':24s} {'time/eval (s)':>13s} {'HLO ops':>8s} {'err vs exact':>13s} {'err vs ref':>11s}  note")
    for c in f.choices:
        ops = "–" if c.hlo_ops is None else str(c.hlo_ops)
        print(f"  {c.name:24s} {c.seconds_per_eval:13.3g} {ops:>8s} {c.error_vs_exact:13.3g} "
              f"{c.error_vs_reference:11.3g}  {c.note}")


def main_alone(run: Callable, doc: str, argv=None) -> None:
    """``python benchmarks/_fidelity_<family>.py [--quick]``: run one module's families and print them."""
    import argparse

    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small grids, few repeats")
    args = ap.parse_args(argv)
    t = time.perf_counter()
    families = run(args.quick)
    for f in families:
        print_family(f)
    print(f"\n({len(families)} families in {time.perf_counter() - t:.1f} s)")


__all__ = ["Choice", "Family", "PRESET", "QUICK_PRESET", "time_per_eval", "compile_all", "measure_tiled", "hlo_ops", "worst", "pareto", "print_family", "main_alone"]
