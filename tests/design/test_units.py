"""Spec units read without pint (:mod:`diffsense.design.units`): bit for bit what pint computes
for SI prefixes and units already in the target, the power levels dBm and dBW against mpmath,
every other unit still through pint, and no shipped spec needing pint at all."""

import math
import os
import subprocess
import sys
from pathlib import Path

import mpmath
import pint
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from diffsense.design.units import _PREFIXED_BASES, _PREFIXES, _without_pint, to_unit

REPO = Path(__file__).resolve().parents[2]
UREG = pint.UnitRegistry()
VALUES = st.floats(min_value=-1e12, max_value=1e12, allow_nan=False, allow_infinity=False)


def _pint(value, unit, target):
    return float(UREG.Quantity(value, unit).to(target).magnitude)


@settings(max_examples=60, deadline=None)
@given(VALUES)
def test_prefixed_units_convert_as_pint_does_bit_for_bit(value):
    for base in sorted(_PREFIXED_BASES):
        for prefix in _PREFIXES:
            if prefix == "µ":
                continue  # pint spells it "u" or "micro" in a unit string
            assert _without_pint(value, prefix + base, base) == _pint(value, prefix + base, base), (prefix, base)


@settings(max_examples=60, deadline=None)
@given(VALUES)
def test_compound_units_with_a_prefixed_leading_base_convert_as_pint_does(value):
    for unit, target in (("pA/Hz^0.5", "A/Hz**0.5"), ("mW/m^2", "W/m**2"), ("kHz*s", "Hz*s"),
                         ("W/m^2/nm", "W/m**2/nm"), ("m/s^2", "m/s**2")):
        assert _without_pint(value, unit, target) == _pint(value, unit.replace("^", "**"), target), unit


@settings(max_examples=200, deadline=None)
@given(st.floats(min_value=-150.0, max_value=80.0), st.sampled_from([("dBm", 30), ("dBW", 0)]))
def test_power_levels_are_within_16_ulp_of_the_exact_watts(level, scale):
    unit, offset = scale
    watts = to_unit(f"{level!r} {unit}", "W")
    exact = mpmath.power(10, (mpmath.mpf(level) - offset) / 10)
    assert abs(mpmath.mpf(watts) - exact) <= 16 * math.ulp(watts)


def test_round_levels_give_round_watts():
    # pint gave 0.10000000000000005 W for 20 dBm and 1.0000000000000007 W for 30 dBm
    assert to_unit("20 dBm", "W") == 0.1 and to_unit("30 dBm", "W") == 1.0 and to_unit("0 dBW", "W") == 1.0


@pytest.mark.parametrize("text, target, expected", [
    ("1 mi", "m", 1609.344),            # not a prefix: pint's mile
    ("2 mm^2", "m**2", 2e-6),           # a prefix under a power: pint
    ("3 nmi", "m", 3 * 1852.0),         # nautical miles, not nano-"mi"
    ("90 deg", "rad", math.pi / 2),
])
def test_other_units_still_convert_through_pint(text, target, expected):
    assert to_unit(text, target) == pytest.approx(expected, rel=1e-15)


def test_no_shipped_spec_imports_pint():
    code = ("import glob, sys\nfrom diffsense.design.spec import load_spec\n"
            "[load_spec(f) for f in sorted(glob.glob('designs/*.toml'))]\nprint('pint' in sys.modules)")
    env = dict(os.environ, PYTHONPATH=str(REPO))
    out = subprocess.run([sys.executable, "-c", code], cwd=REPO, env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip().splitlines()[-1] == "False"
