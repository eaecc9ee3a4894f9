"""The notebooks in ``notebooks/`` run top to bottom on a fresh kernel, and each reproduces numbers
from an independent source: the book, a published detection table, or a closed form computed here.

Each notebook's last cell prints a JSON record of its numbers as its last line; the test parses it.
The notebooks run in the repository root (``designs/*.toml`` resolve from there). The ore-pass
walkthrough compiles the full design optimiser (about 140 s of wall time on a busy 2-core
machine), so it is marked slow.
"""

import json
import math
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient
from scipy.optimize import brentq

from diffsense.design.spec import load_spec
from helpers.paths import REPO

ROOT = REPO
C = 299792458.0  # m/s, exact
K_BOLTZMANN = 1.380649e-23  # J/K, exact
T0 = 290.0  # K, IEEE reference noise temperature


def run_notebook(name: str) -> dict:
    """Execute ``notebooks/<name>.ipynb``; assert every code cell ran without error; return the
    JSON record printed as the last line of the last code cell."""
    nb = nbformat.read(ROOT / "notebooks" / f"{name}.ipynb", as_version=4)
    client = NotebookClient(nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(ROOT)}})
    client.execute()  # raises CellExecutionError at the first failing cell
    cells = [c for c in nb.cells if c.cell_type == "code"]
    assert all(c.execution_count is not None for c in cells)
    errors = [o for c in cells for o in c.outputs if o.output_type == "error"]
    assert not errors, errors
    text = "".join(o.text for o in cells[-1].outputs if o.output_type == "stream" and o.name == "stdout")
    return json.loads(text.strip().splitlines()[-1])


def check_detection_explorer(rec):
    req = rec["required_snr_db_pd0.9_pfa1e-6_n1"]
    # DiFranco & Rubin / Skolnik detection tables: Pd 0.9, Pfa 1e-6, one pulse -> 13.18 dB steady,
    # 21.14 dB Swerling 1 (printed to 0.01 dB: tolerance half a unit of the last digit)
    assert req["0"] == pytest.approx(13.18, abs=0.005)
    assert req["1"] == pytest.approx(21.14, abs=0.005)
    # Swerling 1, one pulse, closed form Pd = Pfa^(1/(1+SNR)): SNR = ln Pfa / ln Pd - 1
    assert req["1"] == pytest.approx(10 * math.log10(math.log(1e-6) / math.log(0.9) - 1.0), abs=1e-6)
    # with one pulse the pulse-to-pulse cases equal the scan-to-scan ones (Swerling 2 = 1, 4 = 3)
    assert req["2"] == pytest.approx(req["1"], abs=1e-6)
    assert req["4"] == pytest.approx(req["3"], abs=1e-6)


def check_sidescan_sonar_design(rec):
    # book eq 12.48: SL = 225.3 dB re 1 uPa at 1 m for 1500 W at 40 %, 1.5 x 60 deg beams
    assert rec["book_source_level_db"] == pytest.approx(225.3, abs=0.05)
    # book eq 7.44: alpha = 0.036 f^2/(f^2 + 3600) + 3.2e-7 f^2 dB/m, f in kHz
    f = 117.0
    assert rec["book_absorption_db_per_m"] == pytest.approx(0.036 * f * f / (f * f + 3600.0) + 3.2e-7 * f * f,
                                                            rel=1e-12)
    # closed form of the minimum power: SL grows as 10 log10 P and nothing else depends on P, so
    # P* = P0 10^(-m0/10) with m0 the margin at P0 (optimiser tolerance: rel 1e-5)
    assert rec["feasible"]
    p0, m0 = rec["reference_power_w"], rec["reference_margin_db"]
    assert rec["optimal_power_w"] == pytest.approx(p0 * 10 ** (-m0 / 10), rel=1e-5)
    # a narrower beam only helps (higher DI): the azimuth beam sits on its 1 deg lower bound
    assert rec["optimal_beamwidth_az_deg"] == pytest.approx(1.0, abs=1e-6)


def check_fire_control_trade_study(rec):
    # Radar equation (book 9.9.1.2) in clear air with the spec's fixed values: solve
    # SNR(R) - 2 alpha R = detectability for R, G = rho (pi d / lambda)^2 (book 8.16.9.1), and the
    # two-tuned-circuit mismatch loss at beta tau = 0.613 from book Table 9.1 (0.56 dB, printed to
    # 0.01 dB: 0.005 dB changes R by 0.03 %, hence rel 5e-4).
    spec = load_spec(ROOT / "designs" / "fire_control.toml")
    p = spec.fixed["aircraft"]
    band = spec.choices["band"].settings[spec.choices["band"].option_names.index("X band, 9.5 GHz")]
    assert rec["x_band_freq_hz"] == band["freq_hz"]
    lam = C / band["freq_hz"]
    d, pt = rec["x_band_diameter_m"], rec["peak_power_w"]
    gain = p["aperture_efficiency"] * (math.pi * d / lam) ** 2
    losses_db = p["transmit_loss_db"] + p["cfar_loss_db"] + p["misc_loss_db"] + 0.56 + p["noise_figure_db"] + p["receive_loss_db"]

    def margin_db(r):
        snr = pt * gain ** 2 * lam ** 2 * p["rcs_m2"] / ((4 * math.pi) ** 3 * r ** 4 * K_BOLTZMANN * T0 * p["bandwidth_hz"])
        return 10 * math.log10(snr) - losses_db - 2 * band["gas_attenuation_db_km"] * r / 1e3 - p["detectability_db"]

    r_det = brentq(margin_db, 100.0, 1e6, xtol=1e-9)
    assert rec["x_band_clear_range_m"] == pytest.approx(r_det, rel=5e-4)


def check_ore_pass_walkthrough(rec):
    # book 8.16.9: 94 GHz with the Gunn transmitter
    assert rec["feasible"]
    assert rec["chosen"] == {"freq_hz": "94 GHz", "transmitter": "Gunn oscillator, 20 dBm"}
    # book 8.16.9.1: 250 mm Cassegrain, efficiency 0.7, at 94 GHz: G = 42,432 (46.2 dB) and theta = 0.89 deg.
    # The book's lambda uses c = 3e8 (0.006 dB in G): tolerance 0.01 dB; theta printed to 0.01 deg.
    assert rec["book_design_94ghz_gain_db"] == pytest.approx(10 * math.log10(42432.0), abs=0.01)
    assert rec["book_design_94ghz_beamwidth_deg"] == pytest.approx(0.89, abs=0.005)
    # the cheapest antenna just fits the beam in the pass: d* = 70 lambda / 1.1 deg (book 8.16.9)
    d_star = 70.0 * (C / rec["freq_hz"]) / 1.1
    assert rec["antenna_diameter_m"] == pytest.approx(d_star, rel=1e-5)
    # envelope theorem: F* = 10 d* + cost with d* = 70 lambda / theta, so dF*/dtheta = -10 d*/theta
    assert rec["beam_limit_shadow_price_per_deg"] == pytest.approx(-10.0 * d_star / 1.1, rel=1e-4)


def check_explore_ore_pass(rec):
    # the explorer moved to the book's design: 94 GHz, 250 mm (book 8.16.9)
    assert rec["freq_hz"] == 94e9 and rec["antenna_diameter_m"] == pytest.approx(0.25, rel=1e-12)
    # book 8.16.9.1: G = 42,432 (46.2 dB; the book's lambda uses c = 3e8: 0.01 dB) and theta = 0.89 deg
    assert rec["gain_db"] == pytest.approx(10 * math.log10(42432.0), abs=0.01)
    assert rec["beamwidth_deg"] == pytest.approx(0.89, abs=0.005)
    assert set(rec["statuses"]) <= {"met", "active", "unmet"}


def check_uncertainty_air_surveillance(rec):
    # lognormal RCS (s dB): the margin is normal in dB, so P[m >= 0] >= p is m_nom >= s Phi^-1(p), the
    # shipped spec's closed form with the limit raised: P d^4 = C, d^5 = 4 a C, a P = d / 4 (clear air binding)
    from statistics import NormalDist

    s, p, a = rec["sigma_db"], rec["probability"], rec["cost_per_w"]
    c = rec["initial_power_w"] * rec["initial_diameter_m"] ** 4 * 10 ** (
        (s * NormalDist().inv_cdf(p) - rec["initial_clear_margin_db"]) / 10)
    d_star = (4 * a * c) ** 0.2
    assert rec["feasible"]
    # smoothing bias and the design sample's error: 3.5e-5 in probability, 0.001 dB in the margin
    assert rec["antenna_diameter_m"] == pytest.approx(d_star, rel=2e-4)
    assert rec["peak_power_w"] == pytest.approx(d_star / (4 * a), rel=2e-4)
    # the probability at the optimum (closed form) is the asked one
    assert NormalDist().cdf(rec["clear_margin_at_optimum_db"] / s) == pytest.approx(p, abs=1e-4)
    # the independent Monte Carlo (>= 1e5 draws) contains it; the heavy-rain case has 0.1 dB to spare
    clear, rain = rec["mc_clear"], rec["mc_rain"]
    assert clear["samples"] >= 100_000 and clear["lower"] <= p <= clear["upper"]
    assert rain["estimate"] > p


CHECKS = {
    "detection_explorer": check_detection_explorer,
    "sidescan_sonar_design": check_sidescan_sonar_design,
    "fire_control_trade_study": check_fire_control_trade_study,
    "ore_pass_walkthrough": check_ore_pass_walkthrough,
    "uncertainty_air_surveillance": check_uncertainty_air_surveillance,
    "explore_ore_pass": check_explore_ore_pass,
}


@pytest.mark.parametrize("name", [
    "detection_explorer",
    "sidescan_sonar_design",
    "fire_control_trade_study",
    pytest.param("ore_pass_walkthrough", marks=pytest.mark.slow),
    "uncertainty_air_surveillance",
    "explore_ore_pass",
])
def test_notebook_runs_and_reproduces_independent_numbers(name):
    CHECKS[name](run_notebook(name))
