"""The ``"radiometer"`` chain: a passive millimetre-wave radiometer detecting a target by its
brightness contrast against the ground, through the atmosphere, the antenna beam and the
receiver's radiometric noise.

The relations are beside it: radiative transfer (:mod:`.brightness`), the antenna beam
(:mod:`.antenna`), sensitivity and Gaussian detection (:mod:`.sensitivity`); the Planck
brightness is :func:`diffsense.physics.radiance.planck_brightness_temperature_k`, the total-power
ΔT and the antenna temperature are in :mod:`diffsense.physics.noise`.

* Sensitivity: total power ``ΔT = T_sys sqrt(1/(Bτ) + (ΔG/G)²)`` or the unbalanced Dicke
  ``ΔT = sqrt([2(T_A + T_R)² + 2(T_ref + T_R)²]/(Bτ) + (ΔG/G)² (T_A − T_ref)²)``.
* Detection: Gaussian statistic, ``Pd = Q(Q⁻¹(Pfa) − d)`` with ``d = |ΔT_c|/ΔT_rms``. The chain
  reports ``snr_db = 10 log10 d`` (the ratio of the contrast to the rms, both temperatures, i.e.
  powers k T B — the book's convention SNR = P/NEP, §9.1.3.5).

Sources: Ulaby, Moore & Fung, *Microwave Remote Sensing* Vol. I (1981), ch. 4–6; Skou & Le Vine,
*Microwave Radiometer Systems* (2nd ed., 2006), ch. 2–3; Kraus, *Radio Astronomy* (2nd ed.,
1986), §3. Specific attenuations: ITU-R P.676-12 (gases), P.838-3 (rain), P.840-7 (cloud and fog)
via :mod:`diffsense.physics.propagation`.
"""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np

from diffsense.numerics.checks import check_range, is_concrete
from diffsense.numerics.db import DB_PER_NEPER, db10, from_db10
from diffsense.numerics.rootfind import decreasing_root_log
from diffsense.physics import antennas, noise
from diffsense.physics.propagation import (
    cloud_attenuation_db_per_km,
    oxygen_attenuation_db_per_km,
    rain_attenuation_db_per_km,
    water_vapour_attenuation_db_per_km,
)
from diffsense.physics.radiance import planck_brightness_temperature_k
from diffsense.sensors.chain import BudgetBuilder, Chain, Evaluation, Output, Param, collect, needs
from diffsense.sensors.parts import scene_part
from diffsense.sensors.radiometer.antenna import _fill_fraction, _gaussian_beamwidth, beam_solid_angle_sr
from diffsense.sensors.radiometer.brightness import (
    COSMIC_BACKGROUND_TEMPERATURE_K,
    _through_layer,
    apparent_temperature_k,
)
from diffsense.detection.gaussian import gaussian_pd, gaussian_required_deflection
from diffsense.sensors.radiometer.sensitivity import unbalanced_dicke_delta_t_k

__all__ = [
    "RadiometerChain",
    "gas_specific_attenuation_db_per_km",
    "rain_specific_attenuation_db_per_km",
    "fog_specific_attenuation_db_per_km",
]

_CONTRAST_FLOOR_K = 1e-9  # |ΔT| is evaluated as sqrt(ΔT² + floor²) so SNR (dB) stays finite


def _smooth_abs(x, floor):
    return jnp.sqrt(x * x + floor * floor)


# ---------------------------------------------------------------------------------------------
# Scene parts (path attenuation)
# ---------------------------------------------------------------------------------------------


@scene_part("gas")
def gas_specific_attenuation_db_per_km(oxygen_db_per_km, water_vapour_db_per_km):
    """Gaseous specific attenuation of the sensor–target path γ_o + γ_w (dB/km), ITU-R P.676-12
    Annex 1 eq. (1); the surface values are the ones the clear-sky opacity already computed."""
    return oxygen_db_per_km + water_vapour_db_per_km


@scene_part("rain")
def rain_specific_attenuation_db_per_km(freq_hz, rain_rate_mm_h):
    """Rain specific attenuation (dB/km), ITU-R P.838-3 with tilt 45° (unpolarised thermal
    emission: the mean of horizontal and vertical)."""
    return rain_attenuation_db_per_km(freq_hz, rain_rate_mm_h, polarization="circular")


@scene_part("fog")
def fog_specific_attenuation_db_per_km(freq_hz, liquid_water_g_m3, temperature_k):
    """Fog (cloud-droplet) specific attenuation (dB/km), ITU-R P.840-7 Rayleigh model."""
    return cloud_attenuation_db_per_km(freq_hz, liquid_water_g_m3, temperature_k)


# ---------------------------------------------------------------------------------------------
# Chain
# ---------------------------------------------------------------------------------------------

_DETECTION_BRACKET_M = (1.0, 1e5)
_ROOT_SLOPE_GUARD_DB = 1e-12  # shifts the detection range by < 1e-12 dB of margin


class RadiometerChain(Chain):
    """Passive mm-wave radiometer detecting a target by its brightness contrast (e.g. a metal
    vehicle mirroring the cold sky against warm ground, seen from a descending submunition).

    Geometry: the radiometer looks down at ``depression_angle_deg`` over the slant range
    ``range_m``; both target and ground reflect the sky in the specular direction (elevation =
    depression angle). The sky is the clear atmosphere (ITU-R P.676 specific attenuation at the
    surface times oxygen and water-vapour equivalent heights, secant law) plus, when the scene
    has them, a rain column of ``rain_height_m`` and a fog layer of ``fog_thickness_m``.
    The parts "gas", "rain", "fog" also attenuate the sensor–target path (whole path inside the
    rain/fog) and add its emission at the air temperature. Receiver: "total_power" (with gain
    fluctuations) or "dicke" (unbalanced, reference load at ``reference_temperature_k``).
    Detection: Gaussian statistic, Pd = Q(Q⁻¹(Pfa) − d), d = |ΔT_A|/ΔT_rms.
    """

    kind = "radiometer"
    description = "passive mm-wave radiometer: target/ground brightness contrast against radiometric noise"
    parts = {
        "gas": "oxygen and water-vapour absorption and emission on the sensor-target path (ITU-R P.676-12)",
        "rain": "rain on the path and in the sky column (ITU-R P.838-3)",
        "fog": "fog on the path and in a fog layer above the target (ITU-R P.840-7)",
    }
    options = {"receiver": ("total_power", ("total_power", "dicke"))}

    def parameters(self, scene):
        ps = [
            Param("freq_hz", "Hz", "radiometer centre frequency", default=94e9, lo=1e9, hi=1e12),
            Param("bandwidth_hz", "Hz", "predetection bandwidth B", default=1e9, lo=0.0, hi=1e11, lo_open=True),
            Param("integration_time_s", "s", "post-detection integration time τ (dwell on the target)",
                  default=1e-3, lo=0.0, hi=1e4, lo_open=True),
            Param("noise_figure_db", "dB", "receiver noise figure (front-end losses included); T_R = 290 (F − 1)",
                  default=6.0, lo=0.0, hi=30.0),
            Param("gain_variation", "1", "RMS receiver gain fluctuation ΔG/G over the integration time",
                  default=1e-4, lo=0.0, hi=0.1),
            Param("antenna_diameter_m", "m", "antenna (circular aperture) diameter", default=0.15,
                  lo=0.0, hi=100.0, lo_open=True),
            Param("aperture_efficiency", "1", "aperture efficiency η_a (A_e = η_a π D²/4)", default=0.6,
                  lo=0.0, hi=1.0, lo_open=True),
            Param("main_beam_efficiency", "1", "main-beam efficiency η_M (sidelobes see the ground)",
                  default=0.9, lo=0.0, hi=1.0, lo_open=True),
            Param("range_m", "m", "slant range to the target", default=150.0, lo=1.0, hi=1e5),
            Param("depression_angle_deg", "deg", "depression angle of the line of sight (= elevation of "
                  "the specularly reflected sky)", default=60.0, lo=5.0, hi=90.0),
            Param("target_area_m2", "m**2", "target area normal to the line of sight", default=20.0,
                  lo=0.0, hi=1e4, lo_open=True),
            Param("target_emissivity", "1", "target emissivity (metal ≈ 0)", default=0.0, lo=0.0, hi=1.0),
            Param("target_temperature_k", "K", "target physical temperature", default=300.0, lo=0.0, hi=1000.0,
                  lo_open=True),
            Param("ground_emissivity", "1", "ground (background) emissivity", default=0.9, lo=0.0, hi=1.0),
            Param("ground_temperature_k", "K", "ground physical temperature", default=290.0, lo=0.0, hi=1000.0,
                  lo_open=True),
            Param("air_temperature_k", "K", "surface air temperature (path emission, gas and fog models)",
                  default=288.15, lo=233.15, hi=323.15),
            Param("pressure_hpa", "hPa", "surface barometric pressure", default=1013.25, lo=300.0, hi=1100.0),
            Param("water_vapour_g_m3", "g/m**3", "surface water-vapour density", default=7.5, lo=0.0, hi=30.0),
            Param("oxygen_equivalent_height_m", "m", "equivalent height of oxygen absorption (zenith "
                  "opacity = surface γ_o × height; ≈ 5–6 km outside the 60/118 GHz lines)", default=6000.0,
                  lo=0.0, hi=20000.0),
            Param("water_vapour_equivalent_height_m", "m", "equivalent height of water-vapour absorption "
                  "(≈ 1.7–2 km outside the 22/183 GHz lines)", default=2000.0, lo=0.0, hi=10000.0),
            Param("sky_mean_radiating_temperature_k", "K", "mean radiating temperature of the atmosphere",
                  default=275.0, lo=150.0, hi=320.0),
            Param("cosmic_temperature_k", "K", "cosmic background temperature", default=COSMIC_BACKGROUND_TEMPERATURE_K,
                  lo=0.0, hi=10.0, lo_open=True),
            Param("pfa", "1", "false-alarm probability per decision", default=1e-6, lo=1e-300, hi=0.5),
            Param("pd", "1", "required probability of detection (> pfa)", default=0.9, lo=0.0, hi=1.0 - 1e-12,
                  lo_open=True),
        ]
        return collect(ps + self._option_and_part_parameters(scene))

    def _option_and_part_parameters(self, scene):
        ps = []
        if self.option(scene, "receiver") == "dicke":
            ps.append(Param("reference_temperature_k", "K", "physical temperature of the Dicke reference load",
                            default=290.0, lo=0.0, hi=1000.0, lo_open=True))
        if scene.has("rain"):
            ps += [
                Param("rain_rate_mm_h", "mm/h", "rain rate", default=4.0, lo=0.0, hi=200.0, part="rain"),
                Param("rain_height_m", "m", "height of the rain column above the target (≈ 0 °C isotherm)",
                      default=3000.0, lo=0.0, hi=10000.0, part="rain"),
            ]
        if scene.has("fog"):
            ps += [
                Param("fog_liquid_water_g_m3", "g/m**3", "fog liquid water content (0.05 moderate, 0.5 thick)",
                      default=0.1, lo=0.0, hi=5.0, part="fog"),
                Param("fog_thickness_m", "m", "fog layer thickness above the target", default=100.0,
                      lo=0.0, hi=2000.0, part="fog"),
            ]
        return ps

    def outputs(self, scene):
        outs = [
            Output("sky_temperature_k", "K", "sky brightness in the specular direction (incl. rain/fog columns)"),
            Output("target_apparent_temperature_k", "K", "target apparent temperature at the surface"),
            Output("ground_apparent_temperature_k", "K", "ground apparent temperature at the surface"),
            Output("contrast_k", "K", "apparent-temperature contrast target − ground at the surface"),
            Output("path_transmission", "1", "transmissivity of the sensor-target path e^−τ"),
            Output("antenna_gain_db", "dB", "antenna gain 10 log10(4π/Ω_A) = 10 log10(4π η_a A/λ²)"),
            Output("beamwidth_rad", "rad", "half-power beamwidth of the equivalent Gaussian main beam"),
            Output("footprint_diameter_m", "m", "half-power footprint diameter normal to the beam at range_m"),
            Output("beam_fill", "1", "fraction of the main beam filled by the target"),
            Output("antenna_temperature_k", "K", "antenna temperature, ground only in the beam"),
            Output("antenna_temperature_target_k", "K", "antenna temperature, target centred in the beam"),
            Output("antenna_contrast_k", "K", "antenna-temperature contrast (signed)"),
            Output("system_temperature_k", "K", "system noise temperature T_A + T_R"),
            Output("delta_t_k", "K", "radiometric sensitivity ΔT_rms"),
            Output("snr_db", "dB", "10 log10(|antenna contrast| / ΔT_rms)"),
            Output("required_snr_db", "dB", "10 log10 of the Gaussian deflection needed for (pd, pfa)"),
            Output("snr_margin_db", "dB", "snr_db − required_snr_db"),
            Output("pd", "1", "probability of detection at range_m"),
            Output("detection_range_m", "m", "slant range where snr_db = required_snr_db (bracket 1 m–100 km)"),
        ]
        return {o.name: o for o in outs}

    # ---- model -------------------------------------------------------------------------

    def _sky_and_specific(self, scene, p):
        """Sky brightness and the parts' specific attenuations (dB/km): range independent, computed
        once outside the detection-range solve."""
        f = p["freq_hz"]
        gamma_o = oxygen_attenuation_db_per_km(f, p["pressure_hpa"], p["air_temperature_k"], p["water_vapour_g_m3"])
        gamma_w = water_vapour_attenuation_db_per_km(f, p["pressure_hpa"], p["air_temperature_k"],
                                                     p["water_vapour_g_m3"])
        zenith_db = (gamma_o * p["oxygen_equivalent_height_m"] + gamma_w * p["water_vapour_equivalent_height_m"]) / 1e3
        specific = {}
        if scene.has("gas"):
            specific["gas"] = gas_specific_attenuation_db_per_km(gamma_o, gamma_w)
        if scene.has("rain"):
            specific["rain"] = rain_specific_attenuation_db_per_km(f, p["rain_rate_mm_h"])
            zenith_db = zenith_db + specific["rain"] * p["rain_height_m"] / 1e3
        if scene.has("fog"):
            specific["fog"] = fog_specific_attenuation_db_per_km(f, p["fog_liquid_water_g_m3"], p["air_temperature_k"])
            zenith_db = zenith_db + specific["fog"] * p["fog_thickness_m"] / 1e3
        sin_el = jnp.sin(jnp.deg2rad(p["depression_angle_deg"]))
        tau_sky = zenith_db / DB_PER_NEPER / sin_el  # secant law on the zenith opacity (Np)
        t_sky = _through_layer(planck_brightness_temperature_k(p["cosmic_temperature_k"], f), tau_sky,
                               planck_brightness_temperature_k(p["sky_mean_radiating_temperature_k"], f))
        return t_sky, specific

    def _path_db(self, scene, p, specific, range_m):
        """Per-part one-way attenuation (dB) of the sensor-target path at ``range_m``."""
        return {part: gamma * range_m / 1e3 for part, gamma in specific.items()}

    def _receiver(self, scene, p, ta_ground):
        """Receiver noise temperature, system temperature and radiometric sensitivity ΔT (K)."""
        t_rec = noise.noise_temperature_k(p["noise_figure_db"])
        t_sys = ta_ground + t_rec
        if self.option(scene, "receiver") == "dicke":
            t_ref = planck_brightness_temperature_k(p["reference_temperature_k"], p["freq_hz"])
            delta_t = unbalanced_dicke_delta_t_k(ta_ground, t_rec, t_ref, p["bandwidth_hz"], p["integration_time_s"],
                                                 p["gain_variation"])
        else:
            delta_t = noise.total_power_radiometer_delta_t_k(t_sys, p["bandwidth_hz"], p["integration_time_s"],
                                                             p["gain_variation"])
        return t_sys, delta_t

    def _at_range(self, scene, p, t_sky, specific, range_m):
        """Everything that depends on the range: returns a dict of named quantities."""
        f = p["freq_hz"]
        t_target = apparent_temperature_k(p["target_emissivity"],
                                          planck_brightness_temperature_k(p["target_temperature_k"], f), t_sky)
        t_ground = apparent_temperature_k(p["ground_emissivity"],
                                          planck_brightness_temperature_k(p["ground_temperature_k"], f), t_sky)
        path_terms = self._path_db(scene, p, specific, range_m)
        path_db = sum(path_terms.values()) if path_terms else jnp.zeros_like(range_m)
        tau = path_db / DB_PER_NEPER
        t_air = planck_brightness_temperature_k(p["air_temperature_k"], f)
        t_target_s = _through_layer(t_target, tau, t_air)
        t_ground_s = _through_layer(t_ground, tau, t_air)

        area = antennas.circular_aperture_area_m2(p["antenna_diameter_m"])
        omega_a = beam_solid_angle_sr(antennas.wavelength_m(f), area, p["aperture_efficiency"])
        omega_m = p["main_beam_efficiency"] * omega_a
        fill = _fill_fraction(p["target_area_m2"] / (range_m * range_m), omega_m)
        eta = p["main_beam_efficiency"]
        main = fill * t_target_s + (1.0 - fill) * t_ground_s
        ta_target = noise.antenna_temperature_k(main, t_ground_s, eta)
        ta_ground = noise.antenna_temperature_k(t_ground_s, t_ground_s, eta)
        t_sys, delta_t = self._receiver(scene, p, ta_ground)
        return dict(
            t_target=t_target, t_ground=t_ground, contrast=t_target - t_ground, path_terms=path_terms, tau=tau,
            omega_a=omega_a, omega_m=omega_m, fill=fill, ta_target=ta_target, ta_ground=ta_ground, t_sys=t_sys,
            delta_t=delta_t, antenna_contrast=ta_target - ta_ground,
        )

    def _budget(self, p, q):
        """SNR budget (dB): contrast, path attenuation, beam efficiency and fill against ΔT."""
        b = BudgetBuilder()
        b.add("surface brightness contrast (dBK)", db10(_smooth_abs(q["contrast"], _CONTRAST_FLOOR_K)))
        for part, a_db in q["path_terms"].items():
            b.add(f"{part} path attenuation", -a_db)
        b.add("main-beam efficiency", db10(p["main_beam_efficiency"]))
        b.add("beam fill", db10(q["fill"]))
        b.add("radiometric sensitivity ΔT (dBK)", -db10(q["delta_t"]))
        return b.build()

    def compute(self, scene, p, wanted=None):
        """The budget at ``range_m`` and the outputs; with ``wanted`` (a frozenset of output names)
        the range root find is traced only when ``detection_range_m`` is wanted (see
        :class:`diffsense.sensors.chain.Chain`)."""
        if is_concrete(p["pd"]) and is_concrete(p["pfa"]):
            check_range("pd - pfa", np.asarray(p["pd"]) - np.asarray(p["pfa"]), 0.0, None, lo_open=True,
                        where="radiometer chain")
        t_sky, specific = self._sky_and_specific(scene, p)
        q = self._at_range(scene, p, t_sky, specific, p["range_m"])
        required_db = db10(gaussian_required_deflection(p["pd"], p["pfa"]))
        budget = self._budget(p, q)
        snr_db = budget.total

        def residual(r):
            qr = self._at_range(scene, p, t_sky, specific, r)
            d = _smooth_abs(qr["antenna_contrast"], _CONTRAST_FLOOR_K) / qr["delta_t"]
            # a 1e-12 dB/Np slope keeps the residual strictly decreasing where the beam is filled
            # and the path is clear (flat SNR), so the implicit derivative of the root stays finite
            return db10(d) - required_db - _ROOT_SLOPE_GUARD_DB * jnp.log(r)

        beamwidth = _gaussian_beamwidth(q["omega_m"])
        values = {
            "sky_temperature_k": t_sky,
            "target_apparent_temperature_k": q["t_target"],
            "ground_apparent_temperature_k": q["t_ground"],
            "contrast_k": q["contrast"],
            "path_transmission": jnp.exp(-q["tau"]),
            "antenna_gain_db": db10(4.0 * math.pi / q["omega_a"]),
            "beamwidth_rad": beamwidth,
            "footprint_diameter_m": p["range_m"] * beamwidth,
            "beam_fill": q["fill"],
            "antenna_temperature_k": q["ta_ground"],
            "antenna_temperature_target_k": q["ta_target"],
            "antenna_contrast_k": q["antenna_contrast"],
            "system_temperature_k": q["t_sys"],
            "delta_t_k": q["delta_t"],
            "snr_db": snr_db,
            "required_snr_db": required_db,
            "snr_margin_db": snr_db - required_db,
            "pd": gaussian_pd(from_db10(snr_db), p["pfa"]),
        }
        if needs(wanted, "detection_range_m"):
            values["detection_range_m"] = decreasing_root_log(residual, *_DETECTION_BRACKET_M).root
        return Evaluation(budget, values)

