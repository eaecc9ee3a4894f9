"""``[options] fidelity``: "exact" keeps every option, "fast" switches the options a spec leaves
at their default to the atlas's fast choices, and the answer is re-evaluated exactly."""

import tomllib

import pytest

from diffsense.design.spec import load_spec, parse_spec
from diffsense.design.spec import fidelity as fid
from diffsense.errors import SpecError
from diffsense.scene import CHAINS, Scene, chain_for
from helpers.paths import REPO

ORE = REPO / "designs" / "ore_pass.toml"


def _raw(**options):
    raw = tomllib.loads(ORE.read_text())
    raw["options"].update(options)
    return raw


@pytest.fixture
def shnidman_is_fast(monkeypatch):
    monkeypatch.setattr(fid, "FAST_OPTIONS", {"radar": {"detectability": ("shnidman", "test")}})


def test_fidelity_defaults_to_exact_and_refuses_other_values():
    assert load_spec(ORE).fidelity == "exact" and load_spec(ORE).fidelity_switched == {}
    with pytest.raises(SpecError) as info:
        parse_spec(_raw(fidelity="quick"), "x.toml")
    assert "key 'options.fidelity'" in str(info.value) and "'quick'" in str(info.value)
    with pytest.raises(SpecError):
        parse_spec(_raw(fidelity=True), "x.toml")


def test_fast_switches_options_left_at_their_default(shnidman_is_fast):
    raw = _raw(fidelity="fast")
    del raw["options"]["detectability"]
    spec = parse_spec(raw, "x.toml")
    assert spec.fidelity_switched == {"detectability": "shnidman"}
    assert all(s.option("detectability", None) == "shnidman" for s in spec.scenes.values())
    exact = fid.exact_spec(spec)
    assert exact.fidelity_switched == {} and exact.fidelity == "exact"
    assert all(s.option("detectability", None) == CHAINS["radar"].options["detectability"][0]
               for s in exact.scenes.values())


def test_an_option_the_spec_sets_is_never_switched(shnidman_is_fast):
    spec = parse_spec(_raw(fidelity="fast", detectability="exact"), "x.toml")
    assert spec.fidelity_switched == {}
    assert all(s.option("detectability", None) == "exact" for s in spec.scenes.values())


def test_every_fast_choice_takes_the_parameters_of_the_default():
    for sensor, table in fid.FAST_OPTIONS.items():
        for option, (value, bound) in table.items():
            assert bound, (sensor, option)
            default = Scene(sensor, [], {})
            fast = Scene(sensor, [], {option: value})
            try:
                params = set(chain_for(default).parameters(default))
            except Exception:  # a kind that needs a part: the parts of its shipped designs
                continue
            assert set(chain_for(fast).parameters(fast)) == params, (sensor, option, value)


def test_a_fast_choice_the_chain_refuses_beside_the_other_options_is_not_taken():
    """M-of-N integration has its own exact law: the Chebyshev detectability (the atlas's fast
    choice) is refused beside it, so a fast spec keeps the exact detectability there."""
    assert fid.FAST_OPTIONS["radar"]["detectability"][0] == "chebyshev"
    options, switched = fid.fast_options("radar", {"integration": "binary"})
    assert switched == {} and "detectability" not in options
    options, switched = fid.fast_options("radar", {"integration": "noncoherent"})
    assert switched == {"detectability": "chebyshev"} and options["detectability"] == "chebyshev"
