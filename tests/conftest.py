"""Test-session settings.

* XLA:CPU's fusion emitters are disabled: compile time of the loop-heavy detection and solver
  programs drops by about 40 % at equal run time. This changes no computed value.
* Compiled programs are released after each test module. Every loaded XLA executable holds a
  few hundred memory mappings, and one worker running the whole suite otherwise accumulates
  enough of them to exceed the kernel's limit (vm.max_map_count = 65530) and crash mid-compile.
"""

import os

import pytest

_FLAG = "--xla_cpu_use_fusion_emitters=false"
if _FLAG not in os.environ.get("XLA_FLAGS", ""):
    os.environ["XLA_FLAGS"] = (os.environ.get("XLA_FLAGS", "") + " " + _FLAG).strip()


@pytest.fixture(autouse=True, scope="module")
def _release_compiled_programs():
    yield
    import gc

    import jax

    jax.clear_caches()
    gc.collect()
