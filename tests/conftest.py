"""Test-session settings.

* XLA:CPU's fusion emitters are disabled: compile time of the loop-heavy detection and solver
  programs drops by about 40 % at equal run time. This changes no computed value.
* One persistent XLA compilation cache serves the whole run (``.cache/xla`` in the checkout, or
  ``DIFFSENSE_CACHE_DIR``).
* Compiled programs are released after each test module. Every loaded XLA executable holds a
  few hundred memory mappings, and one worker running the whole suite otherwise accumulates
  enough of them to exceed the kernel's limit (vm.max_map_count = 65530) and crash mid-compile.
"""

import os
from pathlib import Path

import mpmath
import pytest

mpmath.mp.dps = 30  # reference values computed at import time (collection) use 30 digits

_FLAG = "--xla_cpu_use_fusion_emitters=false"
if _FLAG not in os.environ.get("XLA_FLAGS", ""):
    os.environ["XLA_FLAGS"] = (os.environ.get("XLA_FLAGS", "") + " " + _FLAG).strip()

# One persistent compilation cache for the whole run, as the command line keeps one for users
# (DIFFSENSE_CACHE_DIR): the same design programs are compiled by many tests, in both workers and
# in the command-line subprocesses. A cache entry is keyed by the program itself, so it changes no
# result; remove the folder to time cold compilations.
_CACHE_DIR = os.environ.setdefault("DIFFSENSE_CACHE_DIR", str(Path(__file__).resolve().parents[1] / ".cache" / "xla"))

import jax  # noqa: E402  (after XLA_FLAGS)

jax.config.update("jax_compilation_cache_dir", _CACHE_DIR)
jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.5)
# as the command line: a size limit makes JAX lock the folder around each read and write, so a
# worker never reads an entry the other is still writing
from diffsense.optimize.programs import lock_compilation_cache  # noqa: E402

lock_compilation_cache()


@pytest.fixture(autouse=True, scope="module")
def _release_compiled_programs():
    yield
    import gc

    import jax

    jax.clear_caches()
    gc.collect()


@pytest.fixture(autouse=True)
def _mpmath_working_precision(request):
    """Each test starts at its module's ``MPMATH_DPS`` (30 digits if the module sets none), so a
    test that raises the precision cannot change the reference values of a later one."""
    mpmath.mp.dps = getattr(request.module, "MPMATH_DPS", 30)
    yield
    mpmath.mp.dps = getattr(request.module, "MPMATH_DPS", 30)
