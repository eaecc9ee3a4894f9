"""Settings shared by every command of one run (``--quiet``), kept in the click context."""

from __future__ import annotations

from dataclasses import dataclass

import typer

from diffsense.cli.output import Reporter


@dataclass
class RunState:
    quiet: bool = False


def reporter_from(ctx: typer.Context) -> Reporter:
    """The :class:`Reporter` for this run (quiet when ``--quiet`` was given)."""
    root = ctx.find_root()
    state = root.obj if isinstance(root.obj, RunState) else RunState()
    return Reporter(quiet=state.quiet)
