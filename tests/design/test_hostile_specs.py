"""Hostile specs on the newer sections (``over``, ``[trade]``, ``[uncertain]``, catalogs and
objectives, names shown on screens): each gets one clear line in bounded time.

Each file of ``tests/design/hostile_specs/`` is one attack or careless mistake; its first line
says what the command must answer (``# expect: exit 2; key '...'; message contains '...'``), its
second which command runs it (``# command: trade --points 100000``). Every run must: exit with
the expected code; print at most five rows of 80 columns on standard error, the last one
``error:`` naming the file (or the command-line option) and the key; no traceback; no control
character on either stream; leave the spec unchanged and write nothing (the refusals come
before any work, so ``--out`` is never created); and stay within 120 s and 4 GB (every refusal
here happens before anything compiles).
"""

import hashlib
import re
import resource
import time

import pytest

import diffsense  # noqa: F401
from diffsense.cli.app import main
from helpers.paths import REPO

CORPUS = REPO / "tests" / "design" / "hostile_specs"
FILES = sorted(CORPUS.glob("*.toml"))
EXPECT = re.compile(r"^# expect: exit (\d); key '(.*?)'; message contains '(.*)'$")
COMMAND = re.compile(r"^# command: (.*)$")
#: what a run may take (the acceptance bound; the refusals take well under a second)
MAX_SECONDS, MAX_RSS_BYTES = 120.0, 4 << 30
#: the error contract's size: five rows of an 80-column terminal
MAX_ERROR_CHARACTERS = 5 * 80
CATEGORIES = ("uncertain_", "probability_", "over_", "trade_", "objective_", "catalog_", "choices_", "work_",
              "requirements_", "no_variables", "variables_", "variable_", "long_", "escape_", "nul_", "bidi_",
              "csi_", "value_", "bound_", "limit_", "choice_", "path_")


def _expectation(path):
    head = path.read_text(encoding="utf-8").splitlines()
    m, c = EXPECT.match(head[0]), COMMAND.match(head[1])
    assert m and c, f"{path.name}: the first two lines must be '# expect: ...' and '# command: ...'"
    return int(m.group(1)), m.group(2), m.group(3), c.group(1).split()


def _control(text: str) -> list:
    return sorted({f"U+{ord(ch):04X}" for ch in text if not ch.isprintable() and ch != "\n"})


def test_the_corpus_has_at_least_100_files_in_every_category():
    assert len(FILES) >= 100
    for prefix in ("uncertain_", "over_", "trade_", "objective_", "catalog_", "work_", "long_", "escape_"):
        assert sum(p.stem.startswith(prefix) for p in FILES) >= 2, prefix
    assert all(p.stem.startswith(CATEGORIES) for p in FILES), [p.stem for p in FILES if not p.stem.startswith(CATEGORIES)]


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_hostile_spec_gets_one_clear_line(path, capsys, tmp_path, monkeypatch):
    expect_code, key, fragment, (command, *options) = _expectation(path)
    before = hashlib.sha256(path.read_bytes()).hexdigest()
    listing = sorted(p.name for p in CORPUS.iterdir())
    monkeypatch.chdir(tmp_path)
    out_dir = tmp_path / "out"
    args = ["--quiet", command, str(path), *options]
    if command in ("report", "trade"):
        args += ["--out", str(out_dir)]
    t0 = time.perf_counter()
    with pytest.raises(SystemExit) as info:
        main(args)
    seconds = time.perf_counter() - t0
    captured = capsys.readouterr()
    err = captured.err
    assert info.value.code == expect_code, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert len(err.strip()) <= MAX_ERROR_CHARACTERS, len(err)
    assert "Traceback" not in err and "internal error" not in err, err
    assert not _control(err) and not _control(captured.out), (_control(err), _control(captured.out))
    if key:
        assert f"key '{key}'" in err, err
    assert str(path) in err or (not key and fragment.startswith("--")), err
    assert fragment in err, err
    assert hashlib.sha256(path.read_bytes()).hexdigest() == before  # the spec is never touched
    assert sorted(p.name for p in CORPUS.iterdir()) == listing  # nothing written beside it
    assert list(tmp_path.iterdir()) == []  # nothing written: not --out, not the working folder
    assert seconds <= MAX_SECONDS
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 <= MAX_RSS_BYTES
