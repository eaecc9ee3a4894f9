"""The ``diffsense`` command: the application, its global options and the error contract.

Every failure ends with one line ``error: …`` on standard error and an exit code: 2 for bad input
(an invalid spec, a wrong option), 3 for a well-formed design that leaves a requirement unmet,
1 for an internal error (its traceback is shown only with ``DIFFSENSE_DEBUG=1``), 130 when
interrupted. No traceback otherwise. A report of a design that leaves a requirement unmet is a
result, not a failure: ``diffsense report`` names each unmet requirement on standard output
(``requirement … not met: value, limit, shortfall``) and exits 3 without an error line.
"""

from __future__ import annotations

import os
import sys

import typer

try:  # typer 0.2x ships its own copy of click
    from typer._click import exceptions as click_errors
except ImportError:  # older typer runs on click itself
    from click import exceptions as click_errors

from diffsense.cli.cmd_describe import describe
from diffsense.cli.cmd_design import evaluate, optimize, report
from diffsense.cli.cmd_detection import detection
from diffsense.cli.cmd_explore import explore
from diffsense.cli.cmd_trade import trade
from diffsense.cli.output import EXIT_BAD_INPUT, Reporter, clip
from diffsense.cli.state import RunState

app = typer.Typer(add_completion=False, no_args_is_help=True, rich_markup_mode=None,
                  pretty_exceptions_enable=False,
                  help="diffsense: differentiable sensor design. Run 'diffsense COMMAND --help' for a command.")

for command in (optimize, evaluate, report, describe, detection, trade, explore):
    app.command()(command)


@app.callback()
def _global(
    ctx: typer.Context,
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress messages on standard error."),
):
    """diffsense command-line tools."""
    ctx.obj = RunState(quiet=quiet)
    _configure_jax()


def _configure_jax() -> None:
    """The command line's JAX settings: XLA:CPU without its fusion emitters (the loop-heavy
    solver programs compile about 40 % faster at equal run time; read when the backend starts,
    so set before first use), and one cache folder between runs (``DIFFSENSE_CACHE_DIR``,
    default ~/.cache/diffsense/xla) for the design programs, traced and compiled
    (:mod:`diffsense.optimize.programs`), and for JAX's persistent compilation cache, so that
    only the first run of a spec structure pays tracing and compilation."""
    flag = "--xla_cpu_use_fusion_emitters=false"
    if flag not in os.environ.get("XLA_FLAGS", ""):
        os.environ["XLA_FLAGS"] = (os.environ.get("XLA_FLAGS", "") + " " + flag).strip()
    import jax

    cache = os.environ.setdefault("DIFFSENSE_CACHE_DIR",
                                  os.path.join(os.path.expanduser("~"), ".cache", "diffsense", "xla"))
    jax.config.update("jax_compilation_cache_dir", cache)
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
    # a size limit makes JAX lock the cache folder around each read and write (filelock): two
    # processes never read an entry half written (README, Dependencies)
    from diffsense.optimize.programs import lock_compilation_cache

    lock_compilation_cache()


def main(argv=None) -> None:
    """Entry point of the ``diffsense`` script: run the app under the error contract above."""
    reporter = Reporter()
    try:
        code = app(args=argv, prog_name="diffsense", standalone_mode=False)
    except click_errors.NoArgsIsHelpError as exc:
        print(exc.ctx.get_help())
        sys.exit(EXIT_BAD_INPUT)
    except click_errors.UsageError as exc:
        hint = f" (try 'diffsense {exc.ctx.command_path.split(' ', 1)[1] if exc.ctx and ' ' in exc.ctx.command_path else ''} --help')"
        reporter.error(clip(exc.format_message(), 400) + hint.replace("  ", " "))
        sys.exit(EXIT_BAD_INPUT)
    except typer.Exit as exc:
        sys.exit(exc.exit_code)
    except typer.Abort:
        reporter.error("interrupted")
        sys.exit(130)
    except Exception as exc:  # the last line of defence: no traceback for the user
        if os.environ.get("DIFFSENSE_DEBUG") == "1":
            raise
        reporter.error(f"internal error: {type(exc).__name__}: {clip(exc, 400)} "
                       "(run with DIFFSENSE_DEBUG=1 for the traceback, and please report it)")
        sys.exit(1)
    sys.exit(code if isinstance(code, int) else 0)


def run() -> None:
    """Entry point of the ``diffsense`` script and of ``python -m diffsense``: :func:`main` on
    the process's arguments, then the process ends as soon as its work is done.

    What an interpreter's exit does that matters is done here, in its order: the compilations
    still running finish (their programs reach the cache folder), the exit handlers run
    (``atexit``: temporary folders removed, the program log printed), the standard streams are
    flushed. The teardown that follows at a normal exit — freeing every module and JAX's
    compiled executables one by one — is skipped (``os._exit``): it took 0.6–1.1 s of each
    command on the 2-core machine (``evaluate`` with the cache filled: 3.5–3.7 s instead of
    4.2–4.8 s), and nothing outside the process sees it. :func:`main` itself raises
    ``SystemExit`` as usual, for callers in a running interpreter (the tests)."""
    import atexit

    from diffsense.optimize.programs import finish_compiling

    try:
        main()
        code = 0
    except SystemExit as exc:
        code = exc.code
    if code is not None and not isinstance(code, int):
        print(code, file=sys.stderr)
        code = 1
    finish_compiling()
    atexit._run_exitfuncs()  # what the interpreter runs at exit (CPython's own entry point to it)
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe or stream: nothing left to write to
            pass
    os._exit(code or 0)
