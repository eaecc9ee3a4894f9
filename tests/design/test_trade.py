"""``diffsense trade`` on a search radar whose front is P d^4 = K in closed form, and the
``[trade]`` section of a spec."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

import diffsense  # noqa: F401
from diffsense.design.spec import parse_spec
from diffsense.errors import SpecError
from helpers.paths import REPO

SPEC = """
name = "search_trade"
sensor = "radar"
parts = []
[options]
antenna = "circular_aperture"
detectability = "given"
matched_filter = "matched"
[fixed]
freq_hz = "3 GHz"
range_m = "100 km"
rcs_m2 = "1 m^2"
pulse_width_s = "1 us"
bandwidth_hz = "1 MHz"
prf_hz = "1 kHz"
n_pulses = 10
detectability_db = "13 dB"
aperture_efficiency = 0.6
noise_figure_db = "3 dB"
transmit_loss_db = "1 dB"
receive_loss_db = "1 dB"
scan_loss_db = "0 dB"
cfar_loss_db = "0 dB"
misc_loss_db = "0 dB"
[variables.peak_power_w]
lower = "1 kW"
upper = "10 MW"
[variables.antenna_diameter_m]
lower = "0.5 m"
upper = "10 m"
[[requirements]]
output = "snr_margin_db"
at_least = "0 dB"
[objective]
minimize = "peak_power_w"
[trade]
objectives = ["peak_power_w", "antenna_diameter_m"]
points = 30
"""


def closed_form_k():
    # radar equation (Brooker eq 9.1 with G = 4 pi rho A / lambda^2, A = pi d^2 / 4):
    # SNR = P G^2 lambda^2 sigma / ((4 pi)^3 R^4 k T0 B F L_tx L_rx), G^2 = rho^2 pi^4 d^4 / lambda^4,
    # so SNR >= D holds exactly when P d^4 >= K with
    lam = 299792458.0 / 3e9
    k_t0 = 1.380649e-23 * 290.0  # SI Boltzmann constant, IEEE T0 = 290 K
    losses = 10 ** ((3.0 + 1.0 + 1.0) / 10)  # noise figure, transmit and receive lines
    D = 10 ** 1.3
    return D * (4 * math.pi) ** 3 * 1e5 ** 4 * k_t0 * 1e6 * losses * lam ** 2 / (0.6 ** 2 * math.pi ** 4 * 1.0)


def test_trade_traces_the_exact_power_aperture_front(tmp_path):
    spec = tmp_path / "search.toml"
    spec.write_text(SPEC)
    proc = subprocess.run([sys.executable, "-m", "diffsense.cli", "trade", str(spec), "--out", str(tmp_path / "out"),
                           "--json", str(tmp_path / "front.json")], cwd=REPO, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    front = json.loads((tmp_path / "front.json").read_text())["front"]
    conv = [p for p in front if p["converged"]]
    assert len(conv) >= 20
    P = np.array([p["design"]["peak_power_w"]["value"] for p in conv])
    d = np.array([p["design"]["antenna_diameter_m"]["value"] for p in conv])
    K = closed_form_k()
    assert np.max(np.abs(P * d ** 4 / K - 1.0)) <= 1e-6
    # the front's extent in d: from P at its upper bound to d at its upper bound
    d_lo, d_hi = (K / 1e7) ** 0.25, 10.0
    assert (d.max() - d.min()) >= 0.9 * (d_hi - d_lo)
    assert (tmp_path / "out" / "front.csv").exists() and (tmp_path / "out" / "figures" / "front.png").exists()
    assert "snr_margin_db" in (tmp_path / "out" / "trade.md").read_text()


BASE = {"sensor": "sonar", "parts": ["sea_noise"], "options": {"absorption": "book"},
        "fixed": {"range_m": "500 m", "freq_hz": "117 kHz"},
        "variables": {"electrical_power_w": {"lower": "10 W", "upper": "5 kW"}},
        "requirements": [{"output": "snr_margin_db", "at_least": "0 dB"}],
        "objective": {"minimize": "electrical_power_w"}}


@pytest.mark.parametrize("trade, key", [
    ({"objectives": ["electrical_power_w"]}, "trade.objectives"),
    ({"objectives": ["electrical_power_w", "nonsense_output"]}, "trade.objectives[1]"),
    ({"objectives": ["electrical_power_w", "snr_db"], "points": 1}, "trade.points"),
    ({"objectives": ["electrical_power_w", "snr_db"], "pionts": 3}, "trade.pionts"),
])
def test_bad_trade_sections_name_their_key(trade, key):
    with pytest.raises(SpecError) as err:
        parse_spec(dict(BASE, trade=trade))
    assert err.value.key == key


def test_a_spec_without_trade_has_none_and_optimize_ignores_it():
    assert parse_spec(BASE).trade is None
    spec = parse_spec(dict(BASE, trade={"objectives": ["electrical_power_w", {"maximize": "snr_db"}]}))
    assert spec.objective.terms == (("electrical_power_w", 1.0),)
    assert [o.sign for o in spec.trade.objectives] == [1.0, -1.0]


def test_three_objective_trade_reports_parallel_coordinates_and_stretches(tmp_path):
    # power against range against frequency of a sonar (absorption grows with frequency): the
    # front has three objectives, so the report draws parallel coordinates besides the front
    from diffsense.design.model import DesignModel
    from diffsense.design.trade import trade_design, trade_spec
    from diffsense.report.trade import write_trade_report

    raw = dict(BASE, trade={"objectives": ["electrical_power_w", {"maximize": "range_m"}, {"maximize": "freq_hz"}],
                            "points": 9,
                            "variables": {"range_m": {"lower": "100 m", "upper": "2 km"},
                                          "freq_hz": {"lower": "50 kHz", "upper": "200 kHz"}}})
    result = trade_design(DesignModel(trade_spec(parse_spec(raw))))
    assert len(result.points) >= 3 and len(result.labels) == 3
    # every point of the front meets the requirement; where the power is not at its bound the
    # SNR requirement holds the front
    assert all(p["met"] for p in result.points)
    assert any("snr_margin_db" in " ".join(s["active"]) for s in result.stretches)
    files = write_trade_report(result, tmp_path)
    names = sorted(f.name for f in files["figures"])
    assert names == ["front.png", "parallel_coordinates.png"]
    text = files["markdown"].read_text()
    assert "## Active requirements along the front" in text and "snr_margin_db" in text
