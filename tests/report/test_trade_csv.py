"""``front.csv`` of the ore-pass trade study: one column per quantity, each named once and saying
what it holds, although the trade's second objective is the design variable ``rcs_fade_db``
and the catalog ``freq_hz`` is both a parameter (Hz) and an option name."""

import csv

import pytest
from helpers.paths import REPO

ORE_PASS = REPO / "designs" / "ore_pass.toml"


@pytest.fixture(scope="module")
def front(tmp_path_factory):
    """(header, rows) of front.csv written for a two-point ore-pass trade."""
    from diffsense.design.model import DesignModel
    from diffsense.design.spec import load_spec
    from diffsense.design.trade import trade_design, trade_spec
    from diffsense.report.trade import write_csv

    result = trade_design(DesignModel(trade_spec(load_spec(ORE_PASS))), points=2)
    path = write_csv(result, tmp_path_factory.mktemp("ore_trade") / "front.csv")
    with open(path, newline="") as fh:
        table = list(csv.reader(fh))
    return table[0], table[1:]


def test_every_column_name_is_unique(front):
    header, rows = front
    assert len(set(header)) == len(header), sorted(n for n in header if header.count(n) > 1)
    assert rows and all(len(r) == len(header) for r in rows)


def test_objectives_variables_and_catalog_options_say_what_they_are(front):
    header, _ = front
    assert header[:2] == ["objective: minimize 10·antenna_diameter_m + cost", "objective: maximize rcs_fade_db (dB)"]
    for name in ("rcs_fade_db (dB)", "antenna_diameter_m (m)", "n_pulses", "freq_hz (Hz)", "peak_power_w (W)",
                 "freq_hz (catalog option)", "transmitter (catalog option)"):
        assert name in header
    assert header[-4:] == ["kkt_residual", "anchor_of", "knee", "active_requirements"]


def test_the_columns_hold_what_their_names_say(front):
    header, rows = front
    col = {name: k for k, name in enumerate(header)}
    cost = {"Gunn oscillator, 20 dBm": 1.0, "pulsed IMPATT, 30 dBm": 4.0}  # the spec's catalog costs
    band_cost = {24e9: 0.0, 35e9: 0.2, 77e9: 0.5, 94e9: 0.6, 140e9: 2.0}
    power = {"Gunn oscillator, 20 dBm": 0.1, "pulsed IMPATT, 30 dBm": 1.0}  # 20 dBm = 0.1 W, 30 dBm = 1 W
    for r in rows:
        # the maximised objective is the freed fade depth itself
        assert float(r[col["objective: maximize rcs_fade_db (dB)"]]) == float(r[col["rcs_fade_db (dB)"]])
        # the band's option name and its frequency in Hz agree
        f_hz = float(r[col["freq_hz (Hz)"]])
        assert f_hz == pytest.approx(float(r[col["freq_hz (catalog option)"]].split()[0]) * 1e9, rel=1e-12)
        option = r[col["transmitter (catalog option)"]]
        assert float(r[col["peak_power_w (W)"]]) == pytest.approx(power[option], rel=1e-12)
        # minimize 10·d + cost: the catalog cost is the transmitter's plus the band's
        d = float(r[col["antenna_diameter_m (m)"]])
        assert float(r[col["objective: minimize 10·antenna_diameter_m + cost"]]) == pytest.approx(
            10.0 * d + cost[option] + band_cost[f_hz], rel=1e-9)
