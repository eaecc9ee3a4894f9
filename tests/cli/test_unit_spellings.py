"""Each unit is spelled one way in what ``diffsense describe`` prints: over the parameters and
outputs of every sensor kind, two unit strings that the ``pint`` units library reads as the same
unit, factor by factor ("deg" and "degree", "Hz" and "hertz", "1" and ""), are one spelling."""

import re
from collections import defaultdict

import pint
import pytest

from diffsense.errors import DomainError
from diffsense.scene import CHAINS, Scene, describe

UREG = pint.UnitRegistry()
FACTOR = re.compile(r"\s*([*/]?)\s*([^*/\s]+)\s*(\*\*\s*-?[\d.]+)?")


def spelling_key(unit: str) -> str:
    """``unit`` with each factor replaced by pint's name for it, operators and powers kept (no
    simplification: "m**2/m**3" stays apart from "1/m"); dimensionless is "1" or ""."""
    key, pos = [], 0
    while pos < len(unit.strip()):
        m = FACTOR.match(unit, pos)
        assert m and m.end() > pos, f"cannot read the unit {unit!r}"
        op, name, power = m.groups()
        key.append(op + ("1" if name == "1" else UREG.get_name(name)) + (power or "").replace(" ", ""))
        pos = m.end()
    return "".join(key) or "1"


def test_spelling_key_reads_pint_names():
    assert spelling_key("deg") == spelling_key("degree") == "degree"
    assert spelling_key("") == spelling_key("1")
    assert spelling_key("dB/km") == "decibel/kilometer"
    assert spelling_key("A/Hz**0.5") == spelling_key("ampere / hertz ** 0.5")
    assert spelling_key("m**2/m**3") != spelling_key("1/m")


def _scenes(kind):
    """Scenes of ``kind`` that the chain accepts: no part, each part alone and all parts, each at
    the default options and with each value of each option."""
    chain = CHAINS[kind]
    part_sets = [[], *([p] for p in chain.parts), list(chain.parts)]
    settings = [{}] + [{k: v} for k, (_, allowed) in chain.options.items() for v in allowed]
    for parts in part_sets:
        for options in settings:
            scene = Scene(kind, parts, options)
            try:
                yield scene, describe(scene)
            except DomainError:
                continue


def _units_in_use():
    """unit string -> the "kind.parameter" and "kind.output" names that carry it."""
    users = defaultdict(set)
    for kind in CHAINS:
        described = 0
        for _, d in _scenes(kind):
            described += 1
            for name, p in d["parameters"].items():
                users[p["unit"]].add(f"{kind}.{name}")
            for name, o in d["outputs"].items():
                users[o["unit"]].add(f"{kind}.{name} (output)")
        assert described >= 2, f"no scene of a {kind} could be described"
    return users


@pytest.fixture(scope="module")
def units_in_use():
    return _units_in_use()


def test_angles_of_every_sensor_are_among_the_units_checked(units_in_use):
    names = {n for users in units_in_use.values() for n in users}
    assert {"sonar.beamwidth_az_deg", "radar.beamwidth_az_deg", "radar.beamwidth_deg (output)",
            "radiometer.depression_angle_deg"} <= names


def test_each_unit_has_one_spelling(units_in_use):
    spellings = defaultdict(dict)
    for unit, users in units_in_use.items():
        spellings[spelling_key(unit)][unit] = sorted(users)
    several = {key: found for key, found in spellings.items() if len(found) > 1}
    assert not several, "one unit, several spellings: " + "; ".join(
        f"{key}: " + ", ".join(f"{unit!r} ({', '.join(users[:3])})" for unit, users in found.items())
        for key, found in several.items())
