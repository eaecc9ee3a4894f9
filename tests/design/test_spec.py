"""Requirement specs: units, validation errors (file, key, problem) and the CLI's exit codes."""

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import diffsense  # noqa: F401
from diffsense.errors import SpecError
from diffsense.design.spec import load_spec
from diffsense.errors import UnitError
from diffsense.design.units import to_unit
from helpers.paths import REPO

ROOT = REPO
DESIGNS = sorted((ROOT / "designs").glob("*.toml"))


@pytest.mark.parametrize("text,unit,expected", [
    ("94 GHz", "Hz", 94e9), ("250 mm", "m", 0.25), ("20 ns", "s", 20e-9),
    ("20 dBm", "W", 0.1), ("-105 dBW", "dBm", -75.0), ("1 mW", "dBm", 0.0),
    ("11.5 dBsm", "m**2", 10 ** 1.15), ("5 degC", "K", 278.15), ("3 dB", "dB", 3.0), ("20 dB", "1", 100.0),
    (7.5, "g/m**3", 7.5),
])
def test_quantities_convert_to_the_parameter_unit(text, unit, expected):
    assert to_unit(text, unit) == pytest.approx(expected, rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("text,unit", [("3 m", "s"), ("3 furlongz", "m"), ("x m", "m"), ("20 dBm", "dB"), (True, "m")])
def test_bad_quantities_raise_unit_error(text, unit):
    with pytest.raises(UnitError):
        to_unit(text, unit)


@pytest.mark.parametrize("path", DESIGNS, ids=[p.stem for p in DESIGNS])
def test_shipped_designs_are_valid(path):
    spec = load_spec(path)
    assert spec.requirements and spec.variables or spec.choices


BASE = """
sensor = "sonar"
parts = ["sea_noise"]
[options]
absorption = "book"
[fixed]
range_m = "500 m"
freq_hz = "117 kHz"
[variables.electrical_power_w]
lower = "10 W"
upper = "5 kW"
[[requirements]]
output = "snr_margin_db"
at_least = "0 dB"
[objective]
minimize = "electrical_power_w"
"""


def _write(tmp_path, text):
    p = tmp_path / "spec.toml"
    p.write_text(textwrap.dedent(text))
    return p


@pytest.mark.parametrize("old,new,key,fragment", [
    ('sensor = "sonar"', 'sensor = "sonarr"', "sensor", "unknown sensor kind"),
    ('parts = ["sea_noise"]', 'parts = ["sea_noise", "fog"]', "parts", "unknown part"),
    ('range_m = "500 m"', 'range_m = "500 s"', "fixed.range_m", "cannot be converted"),
    ('range_m = "500 m"', 'rnge_m = "500 m"', "fixed.rnge_m", "did you mean 'range_m'"),
    ('lower = "10 W"', 'lower = "10 kW"', "variables.electrical_power_w", "bounds inverted"),
    ('output = "snr_margin_db"', 'output = "snr_marg"', "requirements[0].output", "unknown output"),
    ('at_least = "0 dB"', 'at_least = "0 dB"\nat_most = "3 dB"', "requirements[0]", "exactly one of"),
    ('minimize = "electrical_power_w"', 'minimize = "power"', "objective.minimize", "unknown parameter or output"),
    ('[objective]', '[objectiv]', "objectiv", "unknown key"),
    ('range_m = "500 m"', 'range_m = "-5 m"', "fixed.range_m", "outside the model's domain"),
])
def test_invalid_spec_names_file_key_and_problem(tmp_path, old, new, key, fragment):
    assert old in BASE
    path = _write(tmp_path, BASE.replace(old, new, 1))
    with pytest.raises(SpecError) as info:
        load_spec(path)
    assert info.value.key == key
    assert fragment in str(info.value)
    assert str(path) in str(info.value)


def test_missing_requirements_is_an_error(tmp_path):
    text = BASE.split("[[requirements]]")[0] + '[objective]\nminimize = "electrical_power_w"\n'
    with pytest.raises(SpecError, match="at least one"):
        load_spec(_write(tmp_path, text))


def test_cli_invalid_spec_exits_2_without_traceback(tmp_path):
    path = _write(tmp_path, BASE.replace('lower = "10 W"', 'lower = "10 kW"'))
    out = subprocess.run([sys.executable, "-m", "diffsense.cli", "evaluate", str(path)],
                         capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 2
    assert "Traceback" not in out.stdout + out.stderr
    assert "variables.electrical_power_w" in out.stderr  # errors go to standard error
