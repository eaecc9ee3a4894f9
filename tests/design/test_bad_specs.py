"""Every bad spec gets one clear error: a corpus of invalid specs run through the real command line.

Each file of ``tests/design/bad_specs/`` is one mistake; its first line says what the command must
answer (``# expect: exit 2; key 'fixed.pd'; message contains 'pd - pfa'``). Cases that are
impractical as files (invalid UTF-8, deep nesting, 100,000-character values, markup in the file
name) are written by the tests below. For each: the exit code (2 bad input, 3 a well-formed spec
whose requirements are not met), at most five lines on standard error starting ``error:``, the
file, the key and the problem named, no traceback, values echoed shortened and literally (rich
markup is never interpreted), no code executed, and no NaN or Infinity in any JSON written.
"""

import ast
import json
import re
import shutil
import subprocess
import sys

import pytest

import diffsense  # noqa: F401
from diffsense.cli.app import main
from helpers.paths import DESIGNS, REPO

CORPUS = REPO / "tests" / "design" / "bad_specs"
FILES = sorted(CORPUS.glob("*.toml"))
HEADER = re.compile(r"^# expect: exit (\d); key (.*?); message contains (.*)$")
MARKER = "pwned_marker"


def run_cli(args, capsys):
    """``(exit code, stdout, stderr)`` of ``diffsense ARGS`` run in this process."""
    with pytest.raises(SystemExit) as info:
        main(["--quiet", *map(str, args)] if args and args[0] != "--quiet" else list(map(str, args)))
    out = capsys.readouterr()
    return info.value.code, out.out, out.err


def check_error(code, err, *, expect_code=2, file=None, key=None, fragment=None):
    """The error contract: exit code, one short ``error:`` line naming file, key and problem."""
    assert code == expect_code, err
    lines = err.strip().splitlines()
    assert 1 <= len(lines) <= 5, err
    assert lines[-1].startswith("error: "), err
    assert "Traceback" not in err and "internal error" not in err, err
    assert max(len(line) for line in lines) <= 1010, err
    assert "np.float64" not in err and not re.search(r"\d 1 lies", err), err
    if file is not None:
        assert str(file) in err, err
    if key:
        assert f"key '{key}'" in err, err
    if fragment:
        assert fragment in err, err


def expectation(path):
    m = HEADER.match(path.read_text().splitlines()[0])
    assert m, f"{path.name}: first line must be '# expect: exit N; key ...; message contains ...'"
    return int(m.group(1)), ast.literal_eval(m.group(2)), ast.literal_eval(m.group(3))


def test_the_corpus_covers_at_least_80_mistakes():
    assert len(FILES) >= 80


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_bad_spec_gets_one_clear_error(path, capsys, tmp_path, monkeypatch):
    expect_code, key, fragment = expectation(path)
    monkeypatch.chdir(tmp_path)  # a code-like value that ran would leave its marker here
    code, out, err = run_cli(["evaluate", path, "--json", tmp_path / "out.json"], capsys)
    check_error(code, err, expect_code=expect_code, file=path, key=key, fragment=fragment)
    assert not (tmp_path / MARKER).exists()
    assert not (tmp_path / "out.json").exists()  # nothing is written for an invalid spec


@pytest.mark.parametrize("name", ["radiometer_pd_below_pfa", "percent_for_angle", "objective_nan_weight"])
def test_optimize_and_report_stop_at_load_like_evaluate(name, capsys, tmp_path):
    path = CORPUS / f"{name}.toml"
    _, key, fragment = expectation(path)
    for args in (["optimize", path], ["report", path, "--out", tmp_path / "report"]):
        code, _, err = run_cli(args, capsys)
        check_error(code, err, file=path, key=key, fragment=fragment)
    assert not (tmp_path / "report").exists()


def _base(tmp_path, name="spec.toml"):
    """A valid spec (the side-scan sonar) copied under ``name``, and its text."""
    text = (DESIGNS / "sidescan_sonar.toml").read_text()
    path = tmp_path / name
    path.write_text(text)
    return path, text


def test_invalid_utf8(tmp_path, capsys):
    path, text = _base(tmp_path)
    path.write_bytes(text.encode().replace(b'sensor = "sonar"', b'sensor = "s\xff\xfeonar"'))
    check_error(*run_cli(["evaluate", path], capsys)[::2], file=path, key="", fragment="not valid UTF-8")


def test_utf16_file(tmp_path, capsys):
    path, text = _base(tmp_path)
    path.write_bytes(text.encode("utf-16"))
    check_error(*run_cli(["evaluate", path], capsys)[::2], file=path, fragment="not valid UTF-8")


@pytest.mark.parametrize("depth", [50, 5000, 200_000])
def test_deep_nesting(tmp_path, capsys, depth):
    path, text = _base(tmp_path)
    path.write_text(re.sub(r'(?m)^range_m = .*$', "range_m = " + "[" * depth + "1" + "]" * depth, text, count=1))
    code, _, err = run_cli(["evaluate", path], capsys)
    check_error(code, err, file=path)
    assert len(err) < 1100


def test_deep_nested_tables(tmp_path, capsys):
    path, text = _base(tmp_path)
    path.write_text(text + "\n[x" + ".y" * 3000 + "]\nz = 1\n")
    check_error(*run_cli(["evaluate", path], capsys)[::2], file=path)


def test_100000_character_value_is_not_echoed_whole(tmp_path, capsys):
    path, text = _base(tmp_path)
    for value in ['"' + "x" * 100_000 + '"', '"1 ' + "m" * 100_000 + '"', "[" + ", ".join(["1"] * 30_000) + "]"]:
        path.write_text(re.sub(r'(?m)^range_m = .*$', "range_m = " + value, text, count=1))
        code, _, err = run_cli(["evaluate", path], capsys)
        check_error(code, err, file=path, key="fixed.range_m")
        assert len(err) < 600, len(err)


def test_100000_character_key(tmp_path, capsys):
    path, text = _base(tmp_path)
    path.write_text(text.replace("[fixed]", "[fixed]\n" + "k" * 100_000 + " = 1", 1))
    code, _, err = run_cli(["evaluate", path], capsys)
    check_error(code, err, file=path, fragment="unknown parameter")
    assert len(err) < 700


def test_huge_file(tmp_path, capsys):
    path, text = _base(tmp_path)
    path.write_text(text + "\n# " + "padding " * 200_000 + "\n")
    check_error(*run_cli(["evaluate", path], capsys)[::2], file=path, fragment="larger than")


@pytest.mark.parametrize("content", ["", "   \n\n  \t\n", "# only a comment\n"])
def test_empty_file(tmp_path, capsys, content):
    path = tmp_path / "empty.toml"
    path.write_text(content)
    check_error(*run_cli(["evaluate", path], capsys)[::2], file=path)


def test_not_a_table_of_keys(tmp_path, capsys):
    path = tmp_path / "list.toml"
    path.write_text('["radar", "sonar"]\n')
    check_error(*run_cli(["evaluate", path], capsys)[::2], file=path, fragment="not valid TOML")


def test_missing_file_and_directory(tmp_path, capsys):
    check_error(*run_cli(["evaluate", tmp_path / "nope.toml"], capsys)[::2], file=tmp_path / "nope.toml",
                fragment="cannot read")
    check_error(*run_cli(["evaluate", tmp_path], capsys)[::2], file=tmp_path, fragment="directory")


@pytest.mark.parametrize("name", ["[bold]spec[/bold].toml", "[/].toml", "[red]x[/red] [link=file:x]y.toml"])
def test_markup_in_the_file_name_prints_literally(tmp_path, capsys, name):
    folder, _, file = name.rpartition("/")  # a "/" of the markup is a folder separator
    (tmp_path / folder).mkdir(parents=True, exist_ok=True)
    path, text = _base(tmp_path / folder, file)
    assert str(path).endswith(name)
    path.write_text(text.replace('sensor = "sonar"', 'sensor = "sonarr"'))
    check_error(*run_cli(["evaluate", path], capsys)[::2], file=path, key="sensor")


def test_control_characters_in_a_value_stay_on_one_line(tmp_path, capsys):
    path, text = _base(tmp_path)
    path.write_text(re.sub(r'(?m)^range_m = .*$', r'range_m = "1\\n2\\r\\u001b[31m m"', text, count=1))
    code, _, err = run_cli(["evaluate", path], capsys)
    check_error(code, err, file=path, key="fixed.range_m")
    assert "\x1b" not in err and len(err.strip().splitlines()) == 1


def test_unknown_output_suggests_at_most_three_names(capsys):
    path = CORPUS / "unknown_output.toml"
    _, _, err = run_cli(["evaluate", path], capsys)
    assert err.count("', '") <= 2  # at most three suggestions, no list of every output
    assert "diffsense describe sonar" in err


def test_infeasible_initial_design_exits_3_with_strict_json(tmp_path, capsys):
    path, text = _base(tmp_path)
    path.write_text(re.sub(r'at_least = "[^"]*dB"', 'at_least = "400 dB"', text, count=1))
    out_json = tmp_path / "out.json"
    code, out, err = run_cli(["evaluate", path, "--json", out_json], capsys)
    check_error(code, err, expect_code=3, fragment="not met")
    record = json.loads(out_json.read_text(), parse_constant=lambda c: pytest.fail(f"{c} in JSON"))
    assert record["requirements"]
    assert "…" not in err and "compiling" not in err and "reading" not in err  # no progress off a terminal


def test_budget_shows_the_option_behind_the_matched_filter_loss(capsys):
    code, out, _ = run_cli(["evaluate", DESIGNS / "ore_pass.toml"], capsys)
    assert code in (0, 3)
    assert "matched_filter_loss_db (matched_filter =" in out


def test_describe_lists_option_defaults(capsys):
    code, out, _ = run_cli(["describe", "radar"], capsys)
    assert code == 0 and "two_tuned" in out and "default" in out


def test_subprocess_cross_key_error_has_no_traceback(tmp_path):
    shutil.copy(CORPUS / "radiometer_pd_below_pfa.toml", tmp_path / "spec.toml")
    res = subprocess.run([sys.executable, "-m", "diffsense.cli", "evaluate", "spec.toml"], capture_output=True,
                         text=True, cwd=tmp_path)
    check_error(res.returncode, res.stderr, file="spec.toml", key="fixed.pd", fragment="pd - pfa")
