"""What a user waits for: each command-line job in a fresh process, with an empty compilation
cache, with the cache filled by that first run, and after editing one fixed value of the spec.

Jobs (on every shipped design; ``--quick``: the ore-pass design, ``optimize`` and ``report``):

* ``optimize`` — ``diffsense -q optimize DESIGN``;
* ``evaluate`` — ``diffsense -q evaluate DESIGN`` (exit 3 when the initial design misses a
  requirement is a result, not a failure);
* ``report`` — ``diffsense -q report DESIGN --out DIR`` (the main job);
* ``trade`` — ``diffsense -q trade DESIGN --out DIR`` (designs with a ``[trade]`` section);
* ``explore`` — the live explorer's first numbers: a fresh process that opens the session
  (:class:`diffsense.explore.session.ExplorerSession`) and takes its first snapshot, as the
  page does before the other programs are compiled.

Each job gets its own cache folder (``DIFFSENSE_CACHE_DIR``): *empty* is its first run, *filled*
the same command again, *edited* the spec with its first ``[fixed]`` number multiplied by 1.01
(a new value of an existing key: the programs must come from the cache). Columns: wall and CPU
seconds of the whole process (the children's ``resource`` usage), the programs traced and XLA-compiled (from JAX's own
compilation log, ``JAX_LOG_COMPILES=1``: a compilation that hit the persistent cache does not
count; ``eager`` counts the small programs of operations run outside a compiled program), and the
exit code.

``--code DIR`` runs the jobs with the package from another checkout (``PYTHONPATH=DIR``, e.g. a
``git worktree`` of an earlier commit) to set the table beside an earlier version's in one run;
the explorer job needs the current session API and is skipped then.

Run: python benchmarks/bench_jobs.py [--quick] [--designs ore_pass,fire_control] [--jobs optimize,report]
     [--code DIR]
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _support import QUICK_HELP, ROOT

DESIGNS = ROOT / "designs"
JOBS = ("optimize", "evaluate", "report", "trade", "explore")
STATES = ("empty", "filled", "edited")
#: the design programs (their names in JAX's compilation log)
PROGRAMS = ("lanes", "check", "outputs", "evaluation", "search", "dense", "front", "explorer")

EXPLORE = """
import sys, time
t0 = time.perf_counter()
from diffsense.cli.app import _configure_jax
_configure_jax()
from diffsense.explore.session import ExplorerSession
s = ExplorerSession(sys.argv[1])
snap = s.snapshot(extras=None)
print(f"first numbers after {time.perf_counter() - t0:.2f} s: {len(snap['requirements'])} requirements")
"""


def edited_copy(path: Path, folder: Path) -> Path:
    """The spec with its first numeric ``[fixed]`` value (plain number or quantity text)
    multiplied by 1.01, written into ``folder`` under the same name."""
    import tomlkit

    doc = tomlkit.parse(path.read_text())
    fixed = doc.get("fixed", {})
    for key in fixed:
        value = fixed[key]
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            fixed[key] = float(value) * 1.01
            break
        if isinstance(value, str):
            m = re.match(r"^\s*([-+0-9.eE]+)(\s*.*)$", value)
            if m:
                try:
                    number = float(m.group(1))
                except ValueError:
                    continue
                fixed[key] = f"{number * 1.01:.10g}{m.group(2)}"
                break
    out = folder / path.name
    out.write_text(tomlkit.dumps(doc))
    return out


def command(job: str, spec: Path, out_dir: Path):
    exe = [sys.executable, "-m", "diffsense.cli"]
    if job == "explore":
        return [sys.executable, "-c", EXPLORE, str(spec)]
    if job in ("report", "trade"):
        return exe + ["-q", job, str(spec), "--out", str(out_dir)]
    return exe + ["-q", job, str(spec)]


def compile_counts(log: str) -> dict:
    """Programs XLA-compiled without a persistent-cache hit (JAX's log), programs traced (the
    package's own program log: the others were loaded from the cache folder), and small
    programs of operations run outside a compiled program ("eager")."""
    # a program whose executable the package stores compiles as diffsense_NAME (optimize.programs)
    hits = set(re.findall(r"Persistent compilation cache hit for 'jit_(?:diffsense_)?([A-Za-z0-9_]+)'", log))
    compiled = re.findall(r"Finished XLA compilation of jit\((?:diffsense_)?([A-Za-z0-9_<>]+)\)", log)
    named = [c for c in compiled if c in PROGRAMS and c not in hits]
    eager = [c for c in compiled if c not in PROGRAMS and c not in hits]
    traced = re.findall(r"^program (\S+) traced", log, re.M)
    return {"compiled": named, "eager": len(eager), "traced": traced}


def run(job: str, spec: Path, cache: Path, out_dir: Path, code: Path = ROOT) -> dict:
    env = dict(os.environ, DIFFSENSE_CACHE_DIR=str(cache), JAX_LOG_COMPILES="1", DIFFSENSE_PROGRAM_LOG="1",
               PYTHONPATH=str(code))
    t0 = time.perf_counter()
    proc = subprocess.Popen(command(job, spec, out_dir), cwd=code, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    stdout, stderr = proc.communicate()
    wall = time.perf_counter() - t0
    return {"wall": wall, "code": proc.returncode, **compile_counts(stderr), "stderr": stderr, "stdout": stdout}


def run_timed(job: str, spec: Path, cache: Path, out_dir: Path, code: Path = ROOT) -> dict:
    """:func:`run` with the child's CPU time from ``resource`` (children's rusage difference)."""
    import resource

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = run(job, spec, cache, out_dir, code)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    r["cpu"] = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return r


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=QUICK_HELP)
    parser.add_argument("--designs", default=None, help="comma-separated design names (default: every shipped one)")
    parser.add_argument("--jobs", default=None, help=f"comma-separated jobs of {', '.join(JOBS)}")
    parser.add_argument("--code", default=None, help="run the jobs with the package of this checkout (PYTHONPATH)")
    args = parser.parse_args()
    code = ROOT if args.code is None else Path(args.code).resolve()
    names = (["ore_pass"] if args.quick else sorted(p.stem for p in DESIGNS.glob("*.toml"))) \
        if args.designs is None else args.designs.split(",")
    jobs = (["optimize", "report"] if args.quick else list(JOBS)) if args.jobs is None else args.jobs.split(",")
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=code, capture_output=True,
                            text=True).stdout.strip() or "?"
    print(f"# jobs in fresh processes, {time.strftime('%Y-%m-%d')}, commit {commit}, {os.cpu_count()} cores")
    print(f"{'design':24s} {'job':9s} {'cache':7s} {'wall s':>7s} {'cpu s':>7s} {'exit':>4s}  "
          f"{'compiled (traced)':32s} eager")
    failures = []
    with tempfile.TemporaryDirectory(prefix="bench-jobs-") as tmp:
        tmp = Path(tmp)
        for name in names:
            spec = DESIGNS / f"{name}.toml"
            has_trade = "[trade]" in spec.read_text()
            edited_dir = tmp / f"{name}-edited"
            edited_dir.mkdir()
            edited = edited_copy(spec, edited_dir)
            for job in jobs:
                if (job == "trade" and not has_trade) or (job == "explore" and code != ROOT):
                    continue
                cache = tmp / f"cache-{name}-{job}"
                for state in STATES:
                    out_dir = tmp / f"out-{name}-{job}-{state}"
                    r = run_timed(job, edited if state == "edited" else spec, cache, out_dir, code)
                    ok = r["code"] in (0, 3)
                    if not ok:
                        failures.append((name, job, state, r["stderr"][-2000:]))
                    comp = ",".join(r["compiled"]) or "-"
                    traced = ",".join(r["traced"]) or "-"
                    print(f"{name:24s} {job:9s} {state:7s} {r['wall']:7.1f} {r['cpu']:7.1f} {r['code']:4d}  "
                          f"{comp + ' (' + traced + ')':32s} {r['eager']}", flush=True)
                    shutil.rmtree(out_dir, ignore_errors=True)
    for name, job, state, err in failures:
        print(f"\nFAILED {name} {job} {state}:\n{err}", file=sys.stderr)
    if failures:
        sys.exit(1)


if __name__ == "__main__":
    main()
