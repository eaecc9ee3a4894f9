"""``diffsense explore``: the live design explorer of a spec as a local web page (needs the
``explore`` extra). Exit 2 on an invalid spec or a missing extra; Ctrl-C stops the server."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Optional

import typer

from diffsense.cli.output import EXIT_BAD_INPUT, clip, refuse
from diffsense.cli.state import reporter_from

DESIGN_FILE = typer.Argument(..., help="Requirement spec (TOML), e.g. designs/ore_pass.toml.", show_default=False)


def explore(
    ctx: typer.Context,
    design_file: Path = DESIGN_FILE,
    port: int = typer.Option(0, "--port", min=0, max=65535, help="Port on 127.0.0.1 (0: any free port)."),
    no_browser: bool = typer.Option(False, "--no-browser", help="Do not open a browser; print the address only."),
    out: Optional[Path] = typer.Option(None, "--out", help="Folder for the specs and reports the page writes "
                                       "(default: <spec name>_explored beside the spec)."),
):
    """Serve a live explorer of a spec: sliders for the design, budgets, SNR and Pd against range,
    requirements, objective and elasticities recomputed as you move them."""
    from diffsense.errors import SpecError

    reporter = reporter_from(ctx)
    if out is not None and out.exists() and not out.is_dir():
        refuse(reporter, f"--out {clip(out)}: is a file; the explorer writes into a folder")
    try:
        from diffsense.explore.server import serve
    except ImportError as exc:
        reporter.error(f"the explorer needs the 'explore' extra (pip install 'diffsense[explore]'): {exc}")
        raise typer.Exit(code=EXIT_BAD_INPUT)
    from diffsense.explore.session import ExplorerSession

    t0 = time.perf_counter()
    try:
        with reporter.step(f"reading {design_file} and compiling its evaluation"):
            session = ExplorerSession(design_file, out_dir=out)
            session.snapshot(extras=None)  # the quick program; the rest compiles once a page is open
    except SpecError as exc:
        reporter.error(str(exc))
        raise typer.Exit(code=EXIT_BAD_INPUT)

    def ready(url: str) -> None:
        reporter.info(f"ready in {time.perf_counter() - t0:.1f} s")
        print(f"serving {url} (Ctrl-C stops)", flush=True)

    try:
        serve(session, port=port, show=not no_browser, on_ready=ready)
    except OSError as exc:
        reporter.error(f"cannot serve on port {port}: {exc.strerror or exc}")
        raise typer.Exit(code=EXIT_BAD_INPUT)
    except KeyboardInterrupt:
        reporter.info("stopped")
