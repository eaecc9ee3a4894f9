"""Radar option ``scan_loss_model``: the beam-shape loss computed from the beam spacing.

Independent reference: the SNR-averaged loss of a Gaussian beam (one-way pattern
exp(-4 ln2 u^2), u in beamwidths) over a spacing s, L = -10 log10((1/s) int_{-s/2}^{s/2}
exp(-8 ln2 u^2) du) per scanned axis, by mpmath quadrature at 30 digits; the chain with
``scan_loss_model = "given"`` fed that number must give the same SNR.
"""

import jax
import mpmath as mp
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense.scene import Scene, complete_parameters, evaluator, parameter_table

MPMATH_DPS = 30
COMMON = dict(range_m=40e3, peak_power_w=2e5, pulse_width_s=1e-6, freq_hz=3e9, bandwidth_hz=1.2e6, noise_figure_db=3.0,
              prf_hz=1e3, n_pulses=12.0, gain_db=33.0, beamwidth_az_deg=1.5, beamwidth_el_deg=3.0, detectability_db=10.0)
OPTIONS = {"antenna": "specified", "detectability": "given", "matched_filter": "matched"}


def _mp_loss_db(s, dims):
    mean = mp.quad(lambda u: mp.exp(-8 * mp.log(2) * u * u), [-s / 2, 0, s / 2]) / s
    return float(-10 * dims * mp.log10(mean))


@pytest.mark.parametrize("model,dims", [("beam_shape_1d", 1), ("beam_shape_2d", 2)])
@pytest.mark.parametrize("spacing", [0.5, 1.0, 1.7])
def test_computed_scan_loss_equals_the_definition_and_the_given_form(model, dims, spacing):
    scene = Scene("radar", [], dict(OPTIONS, scan_loss_model=model))
    ev = evaluator(scene)(complete_parameters(scene, dict(COMMON, beam_spacing=spacing)))
    loss = _mp_loss_db(mp.mpf(spacing), dims)
    assert abs(-float(ev.budget["scan_loss_db"]) - loss) < 1e-12
    given = Scene("radar", [], OPTIONS)
    ref = evaluator(given)(complete_parameters(given, dict(COMMON, scan_loss_db=loss)))
    assert float(ev["snr_db"]) == pytest.approx(float(ref["snr_db"]), abs=1e-11)


def test_parameters_follow_the_option():
    assert "beam_spacing" in parameter_table(Scene("radar", [], dict(OPTIONS, scan_loss_model="beam_shape_1d")))
    assert "scan_loss_db" not in parameter_table(Scene("radar", [], dict(OPTIONS, scan_loss_model="beam_shape_1d")))
    assert "beam_spacing" not in parameter_table(Scene("radar", [], OPTIONS))


def test_gradient_in_the_spacing_matches_central_differences():
    scene = Scene("radar", [], dict(OPTIONS, scan_loss_model="beam_shape_2d"))
    ev = evaluator(scene)

    def snr(s):
        return ev(complete_parameters(scene, dict(COMMON, beam_spacing=s)))["snr_db"]

    g = float(jax.grad(snr)(1.2))
    h = 1e-5
    fd = (_mp_loss_db(mp.mpf(1.2) - h, 2) - _mp_loss_db(mp.mpf(1.2) + h, 2)) / (2 * h)
    assert g == pytest.approx(fd, rel=1e-8)
