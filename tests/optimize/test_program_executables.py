"""Compiled executables kept in the cache folder (diffsense.optimize.programs): a second process
loads the executable instead of compiling, and a program that calls LAPACK (a linear solve)
runs correctly from the loaded executable (its kernels' entry points are set up before loading:
without that the call crashed the process)."""

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]

CHILD = textwrap.dedent("""
    import sys, json
    import jax
    jax.config.update("jax_compilation_cache_dir", sys.argv[1])
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
    import jax.numpy as jnp
    import numpy as np
    import diffsense  # noqa: F401  (float64)
    from diffsense.optimize.programs import Program
    A = np.array([[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]])
    b = np.array([1.0, 2.0, 3.0])
    program = Program("solve", lambda a, v: jnp.linalg.solve(a, v), (A, b), "lapack-test")
    x = np.asarray(program(A, b))
    print(json.dumps({"x": x.tolist(), "executable": program.executable_loaded}))
""")


def test_a_second_process_runs_a_lapack_program_from_its_stored_executable(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(REPO))
    runs = []
    for _ in range(2):
        out = subprocess.run([sys.executable, "-c", CHILD, str(tmp_path / "cache")], env=env,
                             capture_output=True, text=True, timeout=600)
        assert out.returncode == 0, out.stderr[-3000:]
        runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
    first, second = runs
    assert not first["executable"] and second["executable"]
    assert len(list((tmp_path / "cache" / "programs").glob("solve-*.xlaexec"))) == 1
    A = np.array([[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]])
    expected = np.linalg.solve(A, [1.0, 2.0, 3.0])
    for run in runs:
        np.testing.assert_allclose(run["x"], expected, rtol=1e-14)
