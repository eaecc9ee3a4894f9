"""One compiled program per spec structure (diffsense.design.programs): every step of the design
optimiser goes through one lane program compiled once; a new value of an existing spec key
changes no program; a second process loads the traced programs instead of tracing them."""

import os
import subprocess
import sys
import textwrap

import jax
import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense.design import programs as design_programs
from diffsense.design.model import DesignModel
from diffsense.design.optimizer import optimize_design
from diffsense.design.spec import load_spec
from diffsense.optimize import programs as P
from helpers.paths import DESIGNS, REPO


def test_every_step_of_the_optimiser_runs_through_one_compiled_lane_program(monkeypatch):
    # the ore-pass design takes every step: 10 catalog combinations, an integer pulse count
    # (neighbours), two requirements over an interval (search rounds, dense re-checks) and a flat
    # optimum (the canonical stage with its pinned-lane linearisations). Programs are shared by
    # the models of one structure in a process: start without those another test built.
    monkeypatch.setattr(design_programs, "_SHARED", {})
    model = DesignModel(load_spec(DESIGNS / "ore_pass.toml"))
    before = dict(P.COMPILATIONS)
    opt = optimize_design(model, n_starts=2, seed=0)
    assert opt.feasible and opt.canonical is not None
    compiled = {k: v - before.get(k, 0) for k, v in P.COMPILATIONS.items()}
    assert compiled.get("lanes") == 1, compiled
    # and each of the others at most once: values, search, dense
    assert all(n <= 1 for n in compiled.values()), compiled


def _spec_text(**edits):
    text = (DESIGNS / "ore_pass.toml").read_text()
    for old, new in edits.items():
        assert old in text, old
        text = text.replace(old, new)
    return text


def _model(text, tmp_path, name="spec.toml"):
    path = tmp_path / name
    path.write_text(text)
    return DesignModel(load_spec(path))


def test_new_values_of_existing_keys_change_no_program(tmp_path):
    base = _model(_spec_text(), tmp_path, "a.toml")
    edited = _model(_spec_text(**{
        'range_m = "300 m"': 'range_m = "280 m"',                      # a fixed value
        'upper = "1000 mm"': 'upper = "900 mm"',                        # a variable bound
        'at_most = "1.1 deg"': 'at_most = "1.2 deg"',                   # a requirement limit
        'costs = [0.0, 0.2, 0.5, 0.6, 2.0]': 'costs = [0.0, 0.3, 0.5, 0.6, 2.5]',  # catalog costs
        'peak_power_w = "20 dBm"': 'peak_power_w = "21 dBm"',           # a catalog value
        'over.range_m = ["10 m", "300 m"]': 'over.range_m = ["12 m", "280 m"]',    # an interval
        'minimize = { antenna_diameter_m = 10.0, cost = 1.0 }': 'minimize = { antenna_diameter_m = 12.0, cost = 1.0 }',
    }), tmp_path, "b.toml")
    assert base.structure() == edited.structure()
    for name in ("check", "search", "dense"):
        a, b = getattr(base.programs, name)(), getattr(edited.programs, name)()
        assert a.key == b.key, name
    # the programs themselves: the check program lowers to the same text (no value is a constant)
    a, b = base.programs.check(), edited.programs.check()
    assert jax.jit(a.fn).lower(*a.avals).as_text() == jax.jit(b.fn).lower(*b.avals).as_text()
    # while the inputs differ where the spec does
    assert not np.array_equal(base.inputs().values, edited.inputs().values)


def test_a_new_part_or_option_is_a_new_structure(tmp_path):
    base = _model(_spec_text(), tmp_path, "a.toml")
    other = _model(_spec_text(**{'matched_filter = "two_tuned"': 'matched_filter = "gaussian"'}), tmp_path, "b.toml")
    assert base.structure() != other.structure()
    assert base.programs.check().key != other.programs.check().key


CHILD = textwrap.dedent("""
    import sys, json
    import jax
    jax.config.update("jax_compilation_cache_dir", sys.argv[2])
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)  # as the command line: keep every compilation
    import diffsense
    from diffsense.design.model import DesignModel
    from diffsense.design.spec import load_spec
    from diffsense.optimize import programs as P
    if len(sys.argv) > 3:  # another version of the package: its programs are traced again
        P._CODE_VERSION = sys.argv[3]
    model = DesignModel(load_spec(sys.argv[1]))
    program = model.programs.check()
    program.compiled()
    values = model.programs.values_rows(model.design_values(model.initial, 0)[None, :])[2]
    full = model.programs.values_rows(model.design_values(model.initial, 0)[None, :], full=True)[2]
    print(json.dumps({"from_disk": program.loaded_from_disk, "traces": P.TRACES.get("check", 0),
                      "executable": program.executable_loaded,
                      "values": [float(v) for v in values[0]], "full": [float(v) for v in full[0]]}))
""")


def test_a_second_process_loads_the_traced_program(tmp_path):
    import json

    spec = DESIGNS / "radiometer_submunition.toml"
    env = dict(os.environ, PYTHONPATH=str(REPO))
    runs = []
    for version in ([], [], ["another version"]):
        out = subprocess.run([sys.executable, "-c", CHILD, str(spec), str(tmp_path / "cache"), *version], env=env,
                             capture_output=True, text=True, timeout=900)
        assert out.returncode == 0, out.stderr[-3000:]
        runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
    first, second, upgraded = runs
    assert not first["from_disk"] and first["traces"] == 1 and not first["executable"]
    # the second process neither traces nor compiles: the module and the executable come from disk
    assert second["from_disk"] and second["traces"] == 0 and second["executable"]
    assert len(list((tmp_path / "cache" / "programs").glob("check-*.xlaexec"))) == 1
    assert second["values"] == first["values"] and second["full"] == first["full"]
    # the program loaded from disk compiles to what the traced one did: one executable of each in
    # XLA's persistent cache, so the second process compiled nothing (the outputs program has
    # weakly typed outputs when traced and not when loaded: its packing must not tell them apart)
    for name in ("check", "outputs"):
        assert len(list((tmp_path / "cache").glob(f"jit_diffsense_{name}-*"))) == 1, name
    # a new version of the package traces its programs again; one whose module is unchanged
    # (same computation; modules carry no source locations) finds the executable stored for it
    assert not upgraded["from_disk"] and upgraded["traces"] == 1 and upgraded["executable"]
    assert len(list((tmp_path / "cache" / "programs").glob("check-*.xlaexec"))) == 1
    assert len(list((tmp_path / "cache" / "programs").glob("check-*.jaxexport"))) == 2
    assert upgraded["values"] == first["values"] and upgraded["full"] == first["full"]


LEGACY = textwrap.dedent("""
    import sys, warnings
    import jax, jax.numpy as jnp
    jax.config.update("jax_compilation_cache_dir", sys.argv[1])
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
    if sys.argv[2] == "locked":
        from diffsense.optimize.programs import lock_compilation_cache
        lock_compilation_cache()
    warnings.simplefilter("error")  # JAX reports a failed cache write as a warning
    jax.jit(lambda a: jnp.sin(a) * float(sys.argv[3]))(1.0).block_until_ready()
""")


def test_a_cache_written_without_a_size_limit_keeps_working_with_one(tmp_path):
    """Entries written before the cache had a size limit (no access-time files) are adopted: a
    locked process writes its own entries beside them without a failure."""
    env = dict(os.environ, PYTHONPATH=str(REPO))
    cache = tmp_path / "cache"
    for mode, factor in (("legacy", "2.0"), ("locked", "3.0"), ("locked", "4.0")):
        out = subprocess.run([sys.executable, "-c", LEGACY, str(cache), mode, factor], env=env,
                             capture_output=True, text=True, timeout=300)
        assert out.returncode == 0, out.stderr[-3000:]
    entries = sorted(p.name[:-len("-cache")] for p in cache.glob("*-cache"))
    assert len(entries) >= 3
    assert entries == sorted(p.name[:-len("-atime")] for p in cache.glob("*-atime"))
