"""Infrared physics and the IRST chain (diffsense.sensors.infrared), and the photon-unit band
radiances of diffsense.physics.radiance.

References used by the assertions:
- Planck's law in photon units integrated by mpmath.quad (30 digits), its temperature
  derivative by mpmath.diff; photon Stefan–Boltzmann law M_q = 4πζ(3)k³T³/(h³c²) =
  1.52e15 T³ photons s⁻¹ m⁻² (Dereniak & Boreman, *Infrared Detectors and Systems*, 1996, §2).
- BLIP detectivity D* = (λ_c/hc)(η/(2 Q_B))^½ with Q_B = sin²(θ/2) ∫_0^λc M_q dλ (θ the full
  field-of-view angle): Bielecki & Rogalski, *Detekcja sygnałów optycznych*, eqs (2.21)–(2.22);
  Dereniak & Boreman §5.3 (photoconductor: g-r noise, D* lower by √2).
- BLIP NETD = 1/(τ_o C_T sqrt(η N_c)), N_c = A_det t_int Q_B: Handbook of Optics Vol. I
  (2nd ed.) ch. 23 "Infrared detector arrays", eqs (16a)–(16b).
- FLIR support note "What is the sensitivity of Tau cameras in Watts per m²?": NEdT < 50 mK
  at f/1 ↔ minimum resolvable flux change < 0.14 W/m² (7.5–13.5 µm, 300 K scene); other
  f-numbers: multiply by (f/#)².
- Hudson, *Infrared System Engineering* (1969) §11.2: point-target SNR = E A_o τ_o D*/√(A_d Δf);
  with extinction σ the range equation R² e^{σR} = R0² has the closed form
  R = (2/σ) W(σ R0/2) (Lambert W, mpmath.lambertw).
- Spectral D*(λ) = D*_peak λ/λ_peak of an ideal photon detector (Dereniak & Boreman §5.3):
  the photon-counting SNR equals ∫ ΔE_λ D*(λ) dλ A_o τ_o/√(A_d Δf) (mpmath.quad).
"""

import math

import jax
import mpmath as mp
import pytest

import diffsense  # noqa: F401
from diffsense.sensors import infrared as ir
from diffsense.physics import radiance
from diffsense.errors import DomainError
from diffsense.scene import complete_parameters, evaluate
from diffsense.sensors.parts import traced_parts
from diffsense.physics.constants import BOLTZMANN_J_K, PLANCK_J_S, SPEED_OF_LIGHT_M_S
from diffsense.scene import Scene

from helpers.chain_checks import WeightedOutputs
from helpers.function_suite import function_suite

MPMATH_DPS = 30  # working precision of this module's tests (set per test by tests/conftest.py)
H, C, K = mp.mpf(PLANCK_J_S), mp.mpf(SPEED_OF_LIGHT_M_S), mp.mpf(BOLTZMANN_J_K)


def _breaks(a, b):
    return [a] + [mp.mpf(x) for x in ("1e-7", "1e-6", "3e-6", "1e-5", "3e-5", "1e-4", "1e-3") if a < mp.mpf(x) < b] + [b]


def mp_photon_radiance(a, b, t):
    a, b, t = mp.mpf(a), mp.mpf(b), mp.mpf(t)
    return mp.quad(lambda lam: 2 * C / lam**4 / mp.expm1(H * C / (lam * K * t)), _breaks(a, b))


def mp_radiance(a, b, t):
    a, b, t = mp.mpf(a), mp.mpf(b), mp.mpf(t)
    return mp.quad(lambda lam: 2 * H * C**2 / lam**5 / mp.expm1(H * C / (lam * K * t)), _breaks(a, b))


SPECS = [
    ("photon_radiance", radiance.band_photon_radiance, [(1e-7, 5e-6, 1), (6e-6, 1e-3, 1), (50.0, 6000.0, 1)], [(2, 0.0), (0, 0.0)]),
    ("photon_radiance_dT", radiance.band_photon_radiance_temperature_derivative, [(1e-7, 5e-6, 1), (6e-6, 1e-3, 1), (50.0, 6000.0, 1)],
     [(1, 20.0)]),
    ("background_photon_irradiance", ir.background_photon_irradiance,
     [(1e-6, 5e-6, 1), (6e-6, 2e-5, 1), (100.0, 400.0, 1), (0.05, 1.5707, 0)], [(3, 2.0), (3, 0.0)]),
    ("blip_dstar", ir.blip_detectivity_jones, [(2e-6, 2e-5, 1), (100.0, 400.0, 1), (0.1, 1.0, 0), (0.05, 1.5707, 0)],
     [(2, 0.0), (2, 1.5)]),
    ("contrast_intensity", ir.contrast_intensity_w_sr,
     [(0.01, 10.0, 1), (0.1, 1.0, 0), (300.0, 1500.0, 1), (0.1, 1.0, 0), (200.0, 300.0, 1), (3e-6, 3.5e-6, 0), (4e-6, 5e-6, 0)],
     [(1, 1.2), (0, -1.0)]),
    ("irradiance", ir.point_target_irradiance_w_m2, [(1.0, 1e3, 1), (10.0, 1e5, 1), (0.01, 1.0, 0)], [(1, 0.0), (2, 1.5)]),
    ("irst_snr", ir.irst_snr, [(1e-12, 1e-6, 1), (1e-4, 0.1, 1), (0.3, 1.0, 0), (1e9, 1e12, 1), (1e-10, 1e-8, 1), (1.0, 1e4, 1)],
     [(0, -1e-9), (2, 0.0)]),
    ("netd", ir.netd_k, [(1e-10, 1e-8, 1), (1.0, 1e4, 1), (1e9, 1e12, 1), (1e-4, 0.1, 1), (1e-9, 1e-6, 1), (0.3, 1.0, 0), (0.1, 10.0, 1)],
     [(6, 0.0), (4, 0.0)]),
    ("blip_netd", lambda lo, hi, t, fno, ad, df, eta, tau: ir.blip_netd_k(lo, hi, t, fno, ad, df, eta, tau),
     [(3e-6, 3.5e-6, 0), (4e-6, 5e-6, 0), (200.0, 350.0, 1), (0.7, 6.0, 1), (1e-10, 1e-8, 1), (1.0, 1e3, 1), (0.3, 1.0, 0), (0.3, 1.0, 0)],
     [(3, 0.2), (6, 0.0)]),
]


def _contrast_terms(args):
    """Size A·max(ε_t L_t, ε_b L_b) of the two intensities whose difference is the contrast."""
    area, e_t, t_t, e_b, t_b, lo, hi = args
    return area * max(e_t * float(radiance.band_radiance_w_m2_sr(lo, hi, t_t)),
                      e_b * float(radiance.band_radiance_w_m2_sr(lo, hi, t_b)))


globals().update(function_suite(SPECS, jit_rel=1e-13, vmap_rtol=1e-13, value_floor=0.0,
                                term_scales={"contrast_intensity": _contrast_terms}))


def test_reversed_band_and_bad_detector_raise():
    with pytest.raises(DomainError):
        radiance.band_photon_radiance(5e-6, 3e-6, 300.0)
    with pytest.raises(DomainError):
        ir.blip_detectivity_jones(1e-5, 300.0, detector="bolometer")


# --- reference values -------------------------------------------------------------------------

BANDS = [(3e-6, 5e-6, 300.0), (8e-6, 12e-6, 300.0), (1e-9, 1e-5, 300.0), (1e-7, 1e-3, 50.0), (2e-6, 2.2e-6, 6000.0),
         (1e-5, 1e-2, 3000.0), (4e-6, 4.1e-6, 250.0), (5e-7, 1e-6, 3000.0)]


@pytest.mark.parametrize("lo,hi,t", BANDS)
def test_photon_radiance_and_derivative_vs_mpmath(lo, hi, t):
    assert float(radiance.band_photon_radiance(lo, hi, t)) == pytest.approx(float(mp_photon_radiance(lo, hi, t)), rel=1e-13)
    ref = mp.diff(lambda tt: mp_photon_radiance(lo, hi, tt), mp.mpf(t))
    assert float(radiance.band_photon_radiance_temperature_derivative(lo, hi, t)) == pytest.approx(float(ref), rel=1e-12)


def test_photon_stefan_boltzmann_law():
    t = 1000.0
    closed = 4 * mp.pi * mp.zeta(3) * K**3 * mp.mpf(t) ** 3 / (H**3 * C**2)
    got = math.pi * float(radiance.band_photon_radiance(1e-9, 10.0, t))  # tails beyond the band < 1e-12
    assert got == pytest.approx(float(closed), rel=1e-11)
    assert float(closed) / t**3 == pytest.approx(1.52e15, rel=3e-3)  # Dereniak & Boreman's 1.52e15


def test_blip_detectivity_matches_photon_flux_formula():
    lam_c, t = 10e-6, 300.0
    q_b = mp.pi * mp_photon_radiance(1e-9, lam_c, t)  # 2π sr: sin²(90°) = 1
    ref_pv = mp.mpf(lam_c) / (H * C) * mp.sqrt(1 / (2 * q_b)) * 100  # Jones
    assert float(q_b) / 1e4 == pytest.approx(4.8978e17, rel=1e-4)  # photons s⁻¹ cm⁻²
    assert float(ir.blip_detectivity_jones(lam_c, t)) == pytest.approx(float(ref_pv), rel=1e-13)
    assert float(ref_pv) == pytest.approx(5.086e10, rel=1e-3)
    pc = float(ir.blip_detectivity_jones(lam_c, t, detector="photoconductive"))
    assert pc == pytest.approx(float(ref_pv) / math.sqrt(2), rel=1e-13)
    # quantum efficiency enters as sqrt(η); a cold shield of half-angle θ raises D* by 1/sin θ
    assert float(ir.blip_detectivity_jones(lam_c, t, 0.64)) == pytest.approx(0.8 * float(ref_pv), rel=1e-13)
    theta = math.radians(15.0)
    assert float(ir.blip_detectivity_jones(lam_c, t, 1.0, theta)) == pytest.approx(float(ref_pv) / math.sin(theta), rel=1e-13)


def test_blip_netd_equals_handbook_thermal_contrast_form():
    lo, hi, t, fno, ad, t_int, eta, tau_o = 3.4e-6, 4.8e-6, 295.0, 2.5, (20e-6) ** 2, 5e-3, 0.75, 0.8
    df = 1 / (2 * t_int)
    lq = mp_photon_radiance(lo, hi, t)
    c_t = mp.diff(lambda tt: mp_photon_radiance(lo, hi, tt), mp.mpf(t)) / lq
    q_b = mp.pi * lq / (4 * fno**2)
    n_c = ad * t_int * q_b
    ref = 1 / (tau_o * c_t * mp.sqrt(eta * n_c))
    got = float(ir.blip_netd_k(lo, hi, t, fno, ad, df, eta, tau_o))
    assert got == pytest.approx(float(ref), rel=1e-12)
    assert float(c_t) == pytest.approx(0.0383, rel=0.01)  # thermal contrast ≈ 3.8 %/K in 3.4–4.8 µm


def test_netd_flir_tau_published_conversion():
    # NETD 50 mK at f/1 <-> ΔM < 0.14 W/m² (FLIR, 7.5-13.5 µm, 300 K): build a detector whose NEP
    # equals the focal-plane power of ΔM = 0.14 W/m² at f/1 and check NETD; then F² scaling.
    lo, hi, t = 7.5e-6, 13.5e-6, 300.0
    dldt = float(radiance.band_radiance_temperature_derivative(lo, hi, t))
    ad, df, d_ap, tau_o = (17e-6) ** 2, 30.0, 0.01, 1.0
    a_o = math.pi * d_ap**2 / 4
    for fno in (1.0, 2.0):
        omega_d = ad / (fno * d_ap) ** 2
        nep = tau_o * a_o * (ad / d_ap**2) * 0.14 / math.pi  # at f/1: same detector for both F
        dstar = math.sqrt(ad * 1e4 * df) / nep
        netd = float(ir.netd_k(ad, df, dstar, a_o, omega_d, tau_o, dldt))
        assert netd == pytest.approx(0.050 * fno**2, rel=0.02)  # FLIR rounds 0.1386 W/m² to 0.14
        # closed form 4F² sqrt(Δf)/(π τ_o D* sqrt(A_d) ∂L/∂T), SI D* = Jones/100
        closed = 4 * fno**2 * math.sqrt(df) / (math.pi * tau_o * dstar / 100 * math.sqrt(ad) * dldt)
        assert netd == pytest.approx(closed, rel=1e-13)


def test_irst_snr_and_irradiance_closed_form():
    j, r, tau_a = 150.0, 12e3, 0.6
    e = float(ir.point_target_irradiance_w_m2(j, r, tau_a))
    assert e == pytest.approx(j * tau_a / r**2, rel=1e-15)
    a_o, tau_o, dstar, ad, df = 0.0177, 0.7, 1e11, (25e-6) ** 2, 50.0
    snr = float(ir.irst_snr(e, a_o, tau_o, dstar, ad, df))
    assert snr == pytest.approx(e * a_o * tau_o * dstar / math.sqrt(ad * 1e4 * df), rel=1e-14)


# --- the IRST chain -----------------------------------------------------------------------------

GIVEN = Scene("infrared")
HAZE = Scene("infrared", ["haze"])
BLIP = Scene("infrared", ["haze"], {"detector": "blip_photovoltaic"})


def _hand_given(p, lam_mid_ext_db_per_km):
    lo, hi = p["wavelength_lo_m"], p["wavelength_hi_m"]
    j = p["target_area_m2"] * (p["target_emissivity"] * mp_radiance(lo, hi, p["target_temperature_k"])
                               - p["background_emissivity"] * mp_radiance(lo, hi, p["background_temperature_k"]))
    sigma = mp.log(10) / 10 * lam_mid_ext_db_per_km / 1000
    a_o = mp.pi * mp.mpf(p["aperture_diameter_m"]) ** 2 / 4
    nep = mp.sqrt(p["detector_area_m2"] * 1e4 * p["bandwidth_hz"]) / p["d_star_jones"]
    k_const = abs(j) * a_o * p["optics_transmission"] / nep
    return j, sigma, k_const


GIVEN_PARAMS = dict(range_m=15e3, target_area_m2=0.8, target_temperature_k=650.0, target_emissivity=0.85,
                    background_temperature_k=270.0, background_emissivity=0.9, aperture_diameter_m=0.12,
                    f_number=2.5, optics_transmission=0.65, detector_area_m2=(30e-6) ** 2, bandwidth_hz=100.0,
                    d_star_jones=2e11, absorption_db_per_km=0.35, pfa=1e-8, pd=0.95)


def test_irst_chain_snr_and_lambert_w_detection_range():
    p = dict(complete_parameters(GIVEN, GIVEN_PARAMS))
    p = {k: float(v) for k, v in p.items()}
    ev = evaluate(GIVEN, GIVEN_PARAMS)
    j, sigma, k_const = _hand_given(p, p["absorption_db_per_km"])
    r = mp.mpf(p["range_m"])
    snr = k_const * mp.e ** (-sigma * r) / r**2
    assert float(ev["contrast_intensity_w_sr"]) == pytest.approx(float(j), rel=1e-12)
    assert float(ev["snr_db"]) == pytest.approx(float(10 * mp.log10(snr)), abs=1e-10)
    d_req = mp.sqrt(2) * (mp.erfinv(2 * mp.mpf(p["pd"]) - 1) + mp.erfinv(1 - 2 * mp.mpf(p["pfa"])))
    assert float(ev["required_snr_db"]) == pytest.approx(float(10 * mp.log10(d_req)), abs=1e-11)
    # range equation R² e^{σR} = R0², R0 the free-space range: R = (2/σ) W(σ R0/2)
    r0 = mp.sqrt(k_const / d_req)
    r_det = 2 / sigma * mp.lambertw(sigma * r0 / 2)
    assert float(ev["detection_range_m"]) == pytest.approx(float(mp.re(r_det)), rel=1e-10)
    # budget terms add up to the SNR and the margin is zero at the detection range
    assert float(sum(ev.budget.values)) == pytest.approx(float(ev["snr_db"]), abs=1e-12)
    at_r = evaluate(GIVEN, dict(GIVEN_PARAMS, range_m=float(ev["detection_range_m"])))
    assert float(at_r["snr_margin_db"]) == pytest.approx(0.0, abs=1e-9)
    assert float(at_r["pd"]) == pytest.approx(p["pd"], abs=1e-9)
    # NETD closed form with the detector IFOV of the optics
    dldt = mp.diff(lambda tt: mp_radiance(p["wavelength_lo_m"], p["wavelength_hi_m"], tt), mp.mpf(p["background_temperature_k"]))
    netd = 4 * p["f_number"] ** 2 * mp.sqrt(p["bandwidth_hz"]) / (
        mp.pi * p["optics_transmission"] * p["d_star_jones"] / 100 * mp.sqrt(p["detector_area_m2"]) * dldt)
    assert float(ev["netd_k"]) == pytest.approx(float(netd), rel=1e-11)


def test_irst_chain_haze_extinction_is_kim_model_at_band_centre():
    from diffsense.physics.propagation import laser_extinction_db_per_km

    params = dict(GIVEN_PARAMS, visibility_m=8e3)
    ev = evaluate(HAZE, params)
    haze = float(laser_extinction_db_per_km(8e3, 4e-6))
    assert float(ev.budget["haze extinction"]) == pytest.approx(-haze * 15.0, rel=1e-13)
    p = {k: float(v) for k, v in complete_parameters(HAZE, params).items()}
    _, sigma, k_const = _hand_given(p, p["absorption_db_per_km"] + haze)
    d_req = mp.sqrt(2) * (mp.erfinv(2 * mp.mpf(p["pd"]) - 1) + mp.erfinv(1 - 2 * mp.mpf(p["pfa"])))
    r_det = 2 / sigma * mp.lambertw(sigma * mp.sqrt(k_const / d_req) / 2)
    assert float(ev["detection_range_m"]) == pytest.approx(float(mp.re(r_det)), rel=1e-10)


def test_blip_chain_equals_spectral_dstar_integral():
    params = dict(range_m=8e3, target_area_m2=0.5, target_temperature_k=700.0, target_emissivity=0.9,
                  background_temperature_k=290.0, background_emissivity=1.0, wavelength_lo_m=3.6e-6,
                  wavelength_hi_m=4.9e-6, aperture_diameter_m=0.1, f_number=2.0, optics_transmission=0.8,
                  detector_area_m2=(20e-6) ** 2, bandwidth_hz=60.0, quantum_efficiency=0.65, visibility_m=20e3)
    ev = evaluate(BLIP, params)
    lo, hi, tb, fno, eta = 3.6e-6, 4.9e-6, 290.0, 2.0, 0.65
    # D* at the peak from the background through the matched cold stop (sin θ = 1/(2F))
    dstar = float(ir.blip_detectivity_jones(hi, tb, eta, math.asin(1 / (2 * fno)), cuton_wavelength_m=lo))
    assert float(ev["d_star_jones"]) == pytest.approx(dstar, rel=1e-13)
    # SNR = A_o τ_o τ_a /(R² sqrt(A_d Δf)) ∫ ΔI_λ D*(λ) dλ with D*(λ) = D*_peak λ/λ_peak
    from diffsense.physics.propagation import laser_extinction_db_per_km

    tau_a = 10 ** (-float(laser_extinction_db_per_km(20e3, 0.5 * (lo + hi))) * 8.0 / 10)
    planck = lambda lam, t: 2 * H * C**2 / lam**5 / mp.expm1(H * C / (lam * K * t))
    d_i = mp.quad(lambda lam: 0.5 * (0.9 * planck(lam, 700) - planck(lam, tb)) * (dstar / 100) * lam / hi, [lo, hi])
    a_o = mp.pi * 0.1**2 / 4
    snr = d_i * a_o * 0.8 * tau_a / (8e3**2 * mp.sqrt((20e-6) ** 2 * 60.0))
    assert float(ev["snr_db"]) == pytest.approx(float(10 * mp.log10(snr)), abs=1e-9)
    assert float(ev["netd_k"]) == pytest.approx(
        float(ir.blip_netd_k(lo, hi, tb, fno, (20e-6) ** 2, 60.0, eta, 0.8)), rel=1e-13)


CHECKS = WeightedOutputs(("snr_margin_db", "detection_range_m", "netd_k", "pd"),
                        [1.0, 1e-4, 30.0, 3.0])  # generic weights: one gradient checks every output


def test_irst_chain_jit_and_vmap():
    CHECKS.assert_jit_and_vmap(GIVEN, complete_parameters(GIVEN, GIVEN_PARAMS), [5e3, 15e3, 40e3])


@pytest.mark.parametrize("scene,extra", [(HAZE, {"visibility_m": 10e3}),
                                         (BLIP, {"visibility_m": 10e3, "quantum_efficiency": 0.6})],
                         ids=["given_dstar_haze", "blip_haze"])
def test_irst_chain_gradient_matches_central_difference(scene, extra):
    known = complete_parameters(scene, {})
    base = complete_parameters(scene, dict({k: v for k, v in GIVEN_PARAMS.items() if k in known}, **extra))
    names = ["range_m", "aperture_diameter_m", "target_temperature_k", "visibility_m", "wavelength_hi_m",
             "absorption_db_per_km", "pd", "pfa", "background_temperature_k", "bandwidth_hz", "f_number"]
    names.append("d_star_jones" if "d_star_jones" in base else "quantum_efficiency")
    CHECKS.assert_gradient_matches_fd(scene, base, names, rel_step=1e-5)
    # values and gradients finite over the documented domain (30 random points, same compiled program)
    doms = {"range_m": (1.0, 1e6), "target_temperature_k": (100.0, 3000.0), "background_temperature_k": (150.0, 1000.0),
            "visibility_m": (50.0, 1e6), "wavelength_hi_m": (5.5e-6, 2e-5), "target_emissivity": (0.0, 1.0),
            "f_number": (0.5, 100.0), "bandwidth_hz": (1e-3, 1e9)}
    CHECKS.assert_finite_over(scene, extra, doms, seed=20240611)


def test_irst_absent_haze_is_not_traced():
    for scene, expected in ((GIVEN, set()), (HAZE, {"haze"}), (BLIP, {"haze"})):
        p = complete_parameters(scene, {})
        jx = jax.make_jaxpr(lambda q: evaluate(scene, q).values)(p)
        assert traced_parts(jx) == expected
    assert "visibility_m" not in complete_parameters(GIVEN, {})
    assert "quantum_efficiency" in complete_parameters(BLIP, {}) and "d_star_jones" not in complete_parameters(BLIP, {})


def test_irst_chain_domain_errors():
    with pytest.raises(DomainError):
        evaluate(GIVEN, range_m=0.0)
    with pytest.raises(DomainError):
        evaluate(GIVEN, wavelength_lo_m=5e-6, wavelength_hi_m=4e-6)
    with pytest.raises(DomainError):
        evaluate(GIVEN, pd=1e-7, pfa=1e-6)
    with pytest.raises(DomainError):
        evaluate(Scene("infrared", ["rain"]))
    with pytest.raises(DomainError):
        evaluate(Scene("infrared", options={"detector": "bolometer"}))
    with pytest.raises(DomainError):
        evaluate(GIVEN, visibility_m=1e4)  # belongs to the absent haze part
