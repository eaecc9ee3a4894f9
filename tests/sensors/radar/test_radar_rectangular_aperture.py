"""Rectangular aperture (radar option ``antenna = "rectangular_aperture"``): a fan beam sized by
its width and height.

Independent references: G = 4 pi rho w h / lambda^2 (reciprocity, Skolnik *Radar Handbook* ch. 9)
evaluated in mpmath; the half-power width of a uniformly illuminated line aperture found in
mpmath from its pattern (sin u / u)^2, u = pi (D/lambda) sin theta (Balanis, *Antenna Theory*
4th ed. sec. 12.5): 2 arcsin(1.39156 lambda / (pi D)) -> 0.8859 lambda / D for D >> lambda; and
the chain with ``antenna = "specified"`` fed the same gain and beamwidths (every other term equal).
"""

import math

import jax
import mpmath as mp
import pytest

import diffsense  # noqa: F401  (float64)
from diffsense.errors import DomainError
from diffsense.physics.constants import SPEED_OF_LIGHT_M_S
from diffsense.scene import Scene, complete_parameters, evaluator, parameter_table

MPMATH_DPS = 30

RECT = Scene("radar", ["gas"], {"antenna": "rectangular_aperture", "detectability": "exact", "gas_model": "specified"})
SPEC = Scene("radar", ["gas"], {"antenna": "specified", "detectability": "exact", "gas_model": "specified"})
COMMON = dict(range_m=150e3, peak_power_w=1e6, pulse_width_s=2e-6, freq_hz=1.3e9, bandwidth_hz=0.6e6,
              noise_figure_db=4.0, prf_hz=360.0, n_pulses=10.0, gas_attenuation_db_km=0.003, pd=0.9, pfa=1e-8)
W, H = 9.0, 1.5   # a fan beam: narrow in azimuth, wide in elevation


def _mp_half_power_factor():
    """k with theta_3dB = k lambda / D for a long uniform aperture: 2 u_3 / pi, (sin u/u)^2 = 1/2."""
    u3 = mp.findroot(lambda u: (mp.sin(u) / u) ** 2 - mp.mpf(1) / 2, 1.39)
    return 2 * u3 / mp.pi


def test_default_beamwidth_factor_is_the_uniform_aperture_half_power_width():
    k = parameter_table(RECT)["beamwidth_factor"].default
    assert abs(k - float(_mp_half_power_factor())) < 5e-4  # 0.886 against 0.88589


def test_gain_and_beamwidths_from_width_and_height():
    ev = evaluator(RECT)(complete_parameters(RECT, dict(COMMON, aperture_width_m=W, aperture_height_m=H)))
    lam = mp.mpf(SPEED_OF_LIGHT_M_S) / mp.mpf(COMMON["freq_hz"])
    g = 4 * mp.pi * mp.mpf("0.7") * W * H / lam**2
    assert abs(float(ev["gain_db"]) - float(10 * mp.log10(g))) < 1e-12
    k = mp.mpf("0.886")
    assert abs(float(ev["beamwidth_deg"]) - float(mp.degrees(k * lam / W))) < 1e-12
    assert abs(float(ev["beamwidth_el_deg"]) - float(mp.degrees(k * lam / H))) < 1e-12
    assert float(ev["beamwidth_el_deg"]) / float(ev["beamwidth_deg"]) == pytest.approx(W / H, rel=1e-14)


def test_same_radar_as_the_specified_antenna_with_that_gain():
    p = dict(COMMON, aperture_width_m=W, aperture_height_m=H)
    rect = evaluator(RECT)(complete_parameters(RECT, p))
    spec = evaluator(SPEC)(complete_parameters(SPEC, dict(COMMON, gain_db=float(rect["gain_db"]),
                                                          beamwidth_az_deg=float(rect["beamwidth_deg"]),
                                                          beamwidth_el_deg=float(rect["beamwidth_el_deg"]))))
    for key in ("snr_db", "detection_margin_db", "detection_range_m"):
        assert float(rect[key]) == pytest.approx(float(spec[key]), rel=1e-12, abs=1e-12), key


def test_gradients_match_central_differences():
    ev = evaluator(RECT)

    def margin(w, h):
        return ev(complete_parameters(RECT, dict(COMMON, aperture_width_m=w, aperture_height_m=h)))["detection_margin_db"]

    gw, gh = jax.grad(margin, argnums=(0, 1))(W, H)
    # G ~ w h: d(2 G_dB)/dw = 20 / (w ln 10), the only width/height dependence of the margin
    assert float(gw) == pytest.approx(20 / (W * math.log(10)), rel=1e-10)
    assert float(gh) == pytest.approx(20 / (H * math.log(10)), rel=1e-10)
    step = 1e-6
    fd = (float(margin(W + step, H)) - float(margin(W - step, H))) / (2 * step)
    assert float(gw) == pytest.approx(fd, rel=1e-7)


def test_non_positive_dimension_is_refused():
    with pytest.raises(DomainError, match="aperture_height_m"):
        complete_parameters(RECT, dict(COMMON, aperture_width_m=W, aperture_height_m=0.0))
