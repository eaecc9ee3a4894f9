"""What the command line prints: one error line, progress on stderr, tables, JSON files.

Rules: results go to standard output, errors and progress to standard error; text the user gave
(file names, keys, values) is never read as markup and is shortened before it is echoed; every
error is one line starting ``error:``; progress is shown only on a terminal and never under
``--quiet``; JSON written holds no NaN or Infinity (a non-finite value is written as ``null``).
"""

from __future__ import annotations

import contextlib
import math
from pathlib import Path
from typing import Iterator, Optional

from rich.console import Console
from rich.table import Table
from rich.text import Text

from diffsense.errors import escaped

#: the longest piece of user text echoed in a message (characters)
MAX_ECHO = 160
#: the longest error line (characters): one message naming the file, the key and the problem
MAX_ERROR = 393
#: exit codes: bad input, and a well-formed design that leaves a requirement unmet
EXIT_BAD_INPUT = 2
EXIT_UNMET = 3


def clip(text: object, limit: int = MAX_ECHO) -> str:
    """``text`` as one line of at most ``limit`` characters (control characters shown escaped).

    >>> clip("a" * 500, 20)
    'aaaaaaaaaaaaaaaaa… (500 characters)'
    >>> clip("line1\\nline2")
    'line1\\\\nline2'
    """
    s = escaped(text)
    if len(s) <= limit:
        return s
    return f"{s[:limit - 3]}… ({len(s)} characters)"


def plain(text: object) -> str:
    """``text`` with every control or format character escaped (no length limit): what reaches
    a terminal is never an escape sequence.

    >>> plain("a\x1b[2Jb")
    'a\\\\x1b[2Jb'
    """
    return escaped(text, keep="\n")


def fmt(value: float) -> str:
    """A number for a table: 4 significant decimals or scientific notation, never ``-0``.

    >>> fmt(-0.0), fmt(1234.5678), fmt(2.5e-7), fmt(float("inf"))
    ('0', '1234.6', '2.5e-07', 'inf')
    """
    if not math.isfinite(value):
        return str(value)
    a = abs(value)
    if a != 0 and (a < 1e-3 or a >= 1e6):
        out = f"{value:.4g}"
    elif a < 1e3:
        out = f"{value:.4f}".rstrip("0").rstrip(".")
    else:
        out = f"{value:.1f}"
    return "0" if out in ("-0", "-0.0", "") else out


def fmt_db(value: float) -> str:
    """A signed dB value with two decimals, ``+0.00`` rather than ``-0.00``."""
    out = f"{value:+.2f}"
    return "+0.00" if out == "-0.00" else out


class Reporter:
    """The consoles of one command: results on stdout, errors and progress on stderr."""

    def __init__(self, quiet: bool = False):
        self.out = Console(markup=False, highlight=False, soft_wrap=False)
        self.err = Console(stderr=True, markup=False, highlight=False, soft_wrap=True)
        self.quiet = quiet

    @property
    def interactive(self) -> bool:
        """Progress is shown: stderr is a terminal and ``--quiet`` was not given."""
        return not self.quiet and self.err.is_terminal

    def error(self, message: str) -> None:
        """One line ``error: message`` on stderr: never read as markup, control characters
        escaped, at most :data:`MAX_ERROR` characters."""
        self.err.print(Text.assemble(("error:", "bold red"), " ", clip(message, MAX_ERROR)))

    def warn(self, label: str, message: str) -> None:
        self.err.print(Text.assemble((f"{label}:", "yellow"), " ", clip(message, MAX_ERROR)))

    def info(self, message: str, wrap: bool = True) -> None:
        """A line of output (stdout): files written, summaries (control characters escaped);
        ``wrap=False`` keeps it one line whatever the terminal's width."""
        self.out.print(Text(plain(message)), soft_wrap=not wrap)

    @contextlib.contextmanager
    def step(self, text: str) -> Iterator[None]:
        """Show ``text`` with a spinner on stderr while the block runs (terminals only)."""
        if not self.interactive:
            yield
            return
        with self.err.status(Text(plain(text)), spinner="dots"):
            yield

    def table(self, title: str, columns, rows, right=()) -> None:
        """Print a table; title, headers and cells are plain text (never markup), control
        characters escaped."""
        t = Table(title=Text(plain(title)))
        for c in columns:
            # a long word folds onto the next line, never cut to an ellipsis (a value must be read whole)
            t.add_column(Text(plain(c)), justify="right" if c in right else "left", overflow="fold")
        for row in rows:
            t.add_row(*(Text(plain(cell.plain), style=cell.style) if isinstance(cell, Text) else Text(plain(cell))
                        for cell in row))
        self.out.print(t)


def finite_json(value):
    """``value`` with every non-finite float replaced by ``None`` (JSON ``null``)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: finite_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite_json(v) for v in value]
    return value


def refuse(reporter: "Reporter", message: str):
    """Print the one error line ``message`` and stop with :data:`EXIT_BAD_INPUT`."""
    import typer

    reporter.error(message)
    raise typer.Exit(code=EXIT_BAD_INPUT)


def check_json_target(path: Optional[Path], reporter: "Reporter", protect=(), force: bool = False) -> None:
    """Before any work: refuse a ``--json`` file that would replace the spec, a folder or a file
    diffsense did not write (without ``force``; :func:`diffsense.report.files.check_single_file`)."""
    from diffsense.report.files import OutputError, check_single_file

    if path is None:
        return
    try:
        check_single_file(path, protect, force)
    except OutputError as exc:
        refuse(reporter, str(exc))


def write_json(record: dict, path: Optional[Path], reporter: Reporter, protect=(), force: bool = False) -> None:
    """Write ``record`` as strict JSON (no NaN/Infinity) to ``path`` (nothing when ``None``),
    atomically, marked as written by diffsense; never over the spec (``protect``) nor, without
    ``force``, over a file diffsense did not write."""
    from diffsense.report.files import OutputError, write_json_file

    if path is None:
        return
    try:
        write_json_file(path, finite_json(record), protect, force)
    except OutputError as exc:
        refuse(reporter, str(exc))
    reporter.info(f"wrote {path}")


