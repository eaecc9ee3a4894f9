"""The command line (``diffsense``): :mod:`.app` (the application and its error contract),
:mod:`.cmd_design` (evaluate, optimize, report), :mod:`.cmd_describe`, :mod:`.cmd_detection`,
:mod:`.records` and :mod:`.output` (what is printed and written)."""

from diffsense.cli.app import app, main, run

__all__ = ["app", "main", "run"]
