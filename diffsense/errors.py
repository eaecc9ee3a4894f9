"""The errors diffsense raises on bad input, in one public module.

* :class:`DomainError` — an argument of a model lies outside its documented domain (raised at
  the API edge for concrete values; see :mod:`diffsense.numerics.checks`).
* :class:`UnitError` — a quantity string that the units registry cannot read or convert.
* :class:`SpecError` — an invalid requirement spec, naming the file, the key and the problem.

All three derive from :class:`ValueError`, so ``except ValueError`` catches any of them.
"""

from __future__ import annotations


class DomainError(ValueError):
    """An argument lies outside the documented domain of a model."""


class UnitError(ValueError):
    """A quantity could not be read or converted to the required unit."""


#: the longest message of a :class:`SpecError` (characters): with "error: " in front it fits in
#: five rows of an 80-column terminal
MAX_MESSAGE = 393
#: the longest file name and key shown in a message (characters)
MAX_FILE, MAX_KEY = 160, 72


def escaped(text, keep: str = "") -> str:
    r"""``text`` with every control or format character shown as its Python escape (``\x1b``,
    ``\u202e``) except those in ``keep``: what a terminal, a table or a message shows is never
    an escape sequence.

    >>> escaped("a\x1b[2Jb"), escaped("a\nb", keep="\n")
    ('a\\x1b[2Jb', 'a\nb')
    """
    return "".join(ch if ch.isprintable() or ch in keep else ch.encode("unicode_escape").decode() for ch in str(text))


def one_line(text, limit: int, keep_end: bool = False) -> str:
    """``text`` on one line with every control or format character escaped (``\\x1b``), at most
    ``limit`` characters: cut with "…" (at the start when ``keep_end``, as for a file path whose
    name is at its end).

    >>> one_line("a\x1b[2Jb", 40)
    'a\\\\x1b[2Jb'
    >>> one_line("/very/long/folder/spec.toml", 14, keep_end=True)
    '…der/spec.toml'
    """
    s = escaped(text)
    if len(s) <= limit:
        return s
    return "…" + s[len(s) - limit + 1:] if keep_end else s[:limit - 1] + "…"


class SpecError(ValueError):
    """An invalid requirement spec: ``file``, ``key`` (dotted path) and what is wrong.

    The message is one line of at most :data:`MAX_MESSAGE` characters whatever the spec holds:
    control characters escaped, a long file name shortened at its start, a long key and problem
    at their end.

    >>> str(SpecError("spec.toml", "fixed." + "k" * 500, "unknown parameter"))[:40]
    "spec.toml: key 'fixed.kkkkkkkkkkkkkkkkkk"
    >>> len(str(SpecError("spec.toml", "fixed." + "k" * 500, "x" * 5000))) <= MAX_MESSAGE
    True
    """

    def __init__(self, file, key: str, problem: str):
        self.file = str(file)
        self.key = one_line(key, MAX_KEY)
        where = f"key '{self.key}': " if key else ""
        head = f"{one_line(self.file, MAX_FILE, keep_end=True)}: {where}"
        self.problem = one_line(problem, MAX_MESSAGE - len(head))
        super().__init__(head + self.problem)
