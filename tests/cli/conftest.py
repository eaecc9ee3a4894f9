"""Running the ``diffsense`` command in the test process, as a user would on a command line."""

import os

import jax
import pytest

from diffsense.cli.app import main


@pytest.fixture
def run_cli(capsys, monkeypatch):
    """``run_cli(*args)`` -> ``(exit code, stdout, stderr)`` of ``diffsense --quiet ARGS``.

    The command line sets its own JAX compilation cache and environment when it starts; both are
    put back afterwards, so that the tests after this one run with the test session's settings."""
    for name in ("XLA_FLAGS", "DIFFSENSE_CACHE_DIR"):
        if name in os.environ:
            monkeypatch.setenv(name, os.environ[name])
        else:
            monkeypatch.delenv(name, raising=False)
    keys = ("jax_compilation_cache_dir", "jax_persistent_cache_min_compile_time_secs")
    saved = {k: getattr(jax.config, k) for k in keys}

    def run(*args):
        capsys.readouterr()
        with pytest.raises(SystemExit) as info:
            main(["--quiet", *map(str, args)])
        out = capsys.readouterr()
        return info.value.code, out.out, out.err

    yield run
    for k, v in saved.items():
        jax.config.update(k, v)
