"""The ``"infrared"`` chain: passive infrared point-target detection (IRST), from the band
contrast intensity of the target through the atmosphere and the optics to the detector's noise.

The relations are beside it: point-target radiometry (:mod:`.radiometry`) and detectors — D*,
BLIP, NETD (:mod:`.detector`); blackbody band radiances in energy and photon units are in
:mod:`diffsense.physics.radiance`, NEP from D* in :mod:`diffsense.physics.noise`.

Detection uses the Gaussian-shift statistic of
:func:`diffsense.detection.gaussian.gaussian_detection_probability` (Pd = Q(Q⁻¹(Pfa) − SNR));
``snr_db = 10 log10 SNR`` with SNR = P/NEP (Brooker, *Introduction to Sensors for Ranging and
Imaging*, §9.1.3.5). Sources: Hudson, *Infrared System Engineering* (1969) §11.2; Dereniak &
Boreman, *Infrared Detectors and Systems* (1996) §5.3, §11.
"""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np

from diffsense.detection.gaussian import gaussian_pd, gaussian_required_deflection
from diffsense.numerics.checks import check_range, is_concrete
from diffsense.numerics.db import db10, from_db10
from diffsense.numerics.rootfind import decreasing_root_log
from diffsense.physics import noise, radiance
from diffsense.physics.propagation import laser_extinction_db_per_km
from diffsense.sensors.chain import BudgetBuilder, Chain, Evaluation, Output, Param, collect, needs
from diffsense.sensors.infrared.detector import NOISE_GAIN, _blip_dstar, _netd, blip_netd_k
from diffsense.sensors.infrared.radiometry import contrast_intensity_w_sr, point_target_irradiance_w_m2
from diffsense.sensors.parts import scene_part

__all__ = ["InfraredChain", "haze_extinction_db_per_km"]

_CONTRAST_FLOOR = 1e-150  # |contrast| evaluated as sqrt(x² + floor²): finite SNR (dB) at zero contrast


# ---------------------------------------------------------------------------------------------
# Scene parts
# ---------------------------------------------------------------------------------------------


@scene_part("haze")
def haze_extinction_db_per_km(visibility_m, wavelength_m):
    """Aerosol extinction (dB/km) from the visibility, Kim et al. (2001) size-distribution model."""
    return laser_extinction_db_per_km(visibility_m, wavelength_m, "kim")


# ---------------------------------------------------------------------------------------------
# Chain
# ---------------------------------------------------------------------------------------------

_DETECTION_BRACKET_M = (1.0, 1e7)


class InfraredChain(Chain):
    """Infrared search and track: a hot point target against a uniform background.

    Signal: band contrast intensity J = A_t[ε_t L(T_t) − ε_b L(T_b)], attenuated by
    exp(−σR) (σ from ``absorption_db_per_km`` plus, with the "haze" part, the Kim-model aerosol
    extinction at the band centre) and spread as 1/R². Detector option "detector":

    * ``"given"``: band-averaged D* (``d_star_jones``); SNR = E A_o τ_o D*/sqrt(A_d Δf);
    * ``"blip_photovoltaic"`` / ``"blip_photoconductive"``: ideal background-limited photon
      detector (quantum efficiency η) whose cold stop matches the optics (sin θ = 1/(2F)) and
      sees a blackbody background at ``background_temperature_k``; the signal is counted in
      photons (band photon contrast intensity).

    The whole blur spot falls on one detector. NETD refers to a blackbody scene at the
    background temperature. Detection is Gaussian: Pd = Q(Q⁻¹(Pfa) − SNR). The sun (glint,
    solar background in 3–5 µm) is not modelled: it acts as structured clutter whose level
    depends on geometry and surface reflectance, not as a noise term of this budget.
    """

    kind = "infrared"
    description = "passive infrared point-target detection (IRST)"
    parts = {"haze": "aerosol (haze/fog) extinction from the meteorological visibility (Kim et al. 2001)"}
    options = {"detector": ("given", ("given", "blip_photovoltaic", "blip_photoconductive"))}

    def parameters(self, scene):
        ps = [
            Param("range_m", "m", "range to the target", default=10e3, lo=1.0, hi=1e6),
            Param("wavelength_lo_m", "m", "lower edge of the spectral band", default=3e-6, lo=2e-7, hi=2e-5),
            Param("wavelength_hi_m", "m", "upper edge of the spectral band (> lower edge; BLIP peak)",
                  default=5e-6, lo=2e-7, hi=2e-5),
            Param("target_area_m2", "m**2", "projected radiating area of the target", default=1.0, lo=0.0, hi=1e4),
            Param("target_temperature_k", "K", "target temperature", default=500.0, lo=0.0, hi=3000.0, lo_open=True),
            Param("target_emissivity", "1", "target emissivity", default=0.9, lo=0.0, hi=1.0),
            Param("background_temperature_k", "K", "background (and NETD scene) temperature; ≥ 150 K keeps the "
                  "background photon flux of every band in the domain a normal float64 (no space backgrounds)",
                  default=280.0, lo=150.0, hi=1000.0),
            Param("background_emissivity", "1", "emissivity of the background hidden by the target",
                  default=1.0, lo=0.0, hi=1.0),
            Param("aperture_diameter_m", "m", "entrance aperture diameter", default=0.15, lo=0.0, hi=10.0,
                  lo_open=True),
            Param("f_number", "1", "working f-number F = f/D", default=2.0, lo=0.5, hi=100.0),
            Param("optics_transmission", "1", "optics transmission τ_o", default=0.7, lo=0.0, hi=1.0,
                  lo_open=True),
            Param("detector_area_m2", "m**2", "detector (pixel) area A_d", default=(25e-6) ** 2, lo=0.0, hi=1e-2,
                  lo_open=True),
            Param("bandwidth_hz", "Hz", "noise bandwidth Δf (1/(2 t_int) for an integrating detector)",
                  default=50.0, lo=0.0, hi=1e9, lo_open=True),
            Param("absorption_db_per_km", "dB/km", "band-averaged clear-air molecular extinction (from "
                  "LOWTRAN/MODTRAN or measurement; 0 = none)", default=0.0, lo=0.0, hi=100.0),
            Param("pfa", "1", "false-alarm probability per decision", default=1e-6, lo=1e-300, hi=0.5),
            Param("pd", "1", "required probability of detection (> pfa)", default=0.9, lo=0.0, hi=1.0 - 1e-12,
                  lo_open=True),
        ]
        if self.option(scene, "detector") == "given":
            ps.append(Param("d_star_jones", "cm*Hz**0.5/W", "band-averaged specific detectivity D*",
                            default=1e11, lo=0.0, hi=1e15, lo_open=True))
        else:
            ps.append(Param("quantum_efficiency", "1", "detector quantum efficiency η", default=0.7,
                            lo=0.0, hi=1.0, lo_open=True))
        if scene.has("haze"):
            ps.append(Param("visibility_m", "m", "meteorological visibility (Koschmieder, 550 nm)",
                            default=23e3, lo=50.0, hi=1e6, part="haze"))
        return collect(ps)

    def outputs(self, scene):
        outs = [
            Output("contrast_intensity_w_sr", "W/sr", "band contrast radiant intensity of the target"),
            Output("transmission", "1", "atmospheric transmission over range_m"),
            Output("irradiance_w_m2", "W/m**2", "contrast irradiance at the aperture"),
            Output("nep_w", "W", "noise-equivalent power (BLIP: at the peak wavelength)"),
            Output("d_star_jones", "cm*Hz**0.5/W", "specific detectivity used (BLIP: peak value)"),
            Output("netd_k", "K", "noise-equivalent temperature difference for a scene at the background temperature"),
            Output("ifov_rad", "rad", "detector angular subtense sqrt(A_d)/f"),
            Output("snr_db", "dB", "10 log10(signal / rms noise) at range_m"),
            Output("required_snr_db", "dB", "10 log10 of the Gaussian deflection needed for (pd, pfa)"),
            Output("snr_margin_db", "dB", "snr_db − required_snr_db"),
            Output("pd", "1", "probability of detection at range_m"),
            Output("detection_range_m", "m", "range where snr_db = required_snr_db (bracket 1 m–10,000 km)"),
        ]
        return {o.name: o for o in outs}

    def _check(self, p):
        where = "infrared chain"
        if is_concrete(p["pd"]) and is_concrete(p["pfa"]):
            check_range("pd - pfa", np.asarray(p["pd"]) - np.asarray(p["pfa"]), 0.0, None, lo_open=True, where=where)
        if is_concrete(p["wavelength_lo_m"]) and is_concrete(p["wavelength_hi_m"]):
            check_range("wavelength_hi_m - wavelength_lo_m",
                        np.asarray(p["wavelength_hi_m"]) - np.asarray(p["wavelength_lo_m"]), 0.0, None,
                        lo_open=True, where=where)

    def _optics(self, p):
        """Aperture area A_o (m²), detector solid angle Ω_d (sr) and focal length (m)."""
        a_o = math.pi * p["aperture_diameter_m"] ** 2 / 4.0
        focal = p["f_number"] * p["aperture_diameter_m"]
        return a_o, p["detector_area_m2"] / focal**2, focal

    def _given_detector(self, p, a_o, ifov_sr):
        """Detector given by its band-averaged D*: signal in W/sr against the NEP."""
        lo, hi = p["wavelength_lo_m"], p["wavelength_hi_m"]
        d_star = p["d_star_jones"]
        nep = noise.nep_from_detectivity_w(p["detector_area_m2"], p["bandwidth_hz"], d_star)
        dldt = radiance.band_radiance_temperature_derivative(lo, hi, p["background_temperature_k"])
        return dict(
            d_star=d_star, nep=nep, signal=None, noise_equiv=nep,
            netd=_netd(nep, a_o, ifov_sr, p["optics_transmission"], dldt),
            labels=("target contrast intensity (dBW/sr)", "noise-equivalent power (dBW)"),
        )

    def _blip_detector(self, p, detector):
        """Background-limited photon detector: signal in photons/s/sr against the noise-equivalent photon rate."""
        lo, hi, t_b = p["wavelength_lo_m"], p["wavelength_hi_m"], p["background_temperature_k"]
        g, eta = NOISE_GAIN[detector], p["quantum_efficiency"]
        etendue_factor = math.pi / (4.0 * p["f_number"] ** 2)  # A_o Ω_d / A_d = π sin²θ
        eq = etendue_factor * radiance.band_photon_radiance(lo, hi, t_b)
        d_star = _blip_dstar(hi, eq, eta, g)
        lq_t = radiance.band_photon_radiance(lo, hi, p["target_temperature_k"])
        lq_b = radiance.band_photon_radiance(lo, hi, t_b)
        return dict(
            d_star=d_star,
            nep=noise.nep_from_detectivity_w(p["detector_area_m2"], p["bandwidth_hz"], d_star),
            signal=p["target_area_m2"] * (p["target_emissivity"] * lq_t - p["background_emissivity"] * lq_b),
            # noise-equivalent photon rate: sqrt(g η E_q A_d Δf)/η (photons/s)
            noise_equiv=jnp.sqrt(g * eta * eq * p["detector_area_m2"] * p["bandwidth_hz"]) / eta,
            netd=blip_netd_k(lo, hi, t_b, p["f_number"], p["detector_area_m2"], p["bandwidth_hz"], eta,
                             p["optics_transmission"], detector=detector),
            labels=("target contrast photon intensity (dB photons/s/sr)", "noise-equivalent photon rate (dB photons/s)"),
        )

    def compute(self, scene, p, wanted=None):
        """The budget at ``range_m`` and the outputs; with ``wanted`` (a frozenset of output names)
        the range root find is traced only when ``detection_range_m`` is wanted (see
        :class:`diffsense.sensors.chain.Chain`)."""
        self._check(p)
        lo, hi = p["wavelength_lo_m"], p["wavelength_hi_m"]
        a_o, ifov_sr, focal = self._optics(p)
        # contrast intensity (energy units, reported in every mode)
        j_w = contrast_intensity_w_sr(p["target_area_m2"], p["target_emissivity"], p["target_temperature_k"],
                                      p["background_emissivity"], p["background_temperature_k"], lo, hi)
        # extinction (dB/km), per source
        ext_terms = {"absorption": p["absorption_db_per_km"]}
        if scene.has("haze"):
            ext_terms["haze"] = haze_extinction_db_per_km(p["visibility_m"], 0.5 * (lo + hi))
        mode = self.option(scene, "detector")
        det = (self._given_detector(p, a_o, ifov_sr) if mode == "given"
               else self._blip_detector(p, "photovoltaic" if mode == "blip_photovoltaic" else "photoconductive"))
        signal_source = j_w if det["signal"] is None else det["signal"]
        source_label, noise_label = det["labels"]

        def snr_terms(r):
            terms = [(source_label, db10(jnp.sqrt(signal_source**2 + _CONTRAST_FLOOR**2))),
                     ("range spreading 1/R²", -2.0 * db10(r))]
            terms += [(f"{name} extinction", -a * r / 1e3) for name, a in ext_terms.items()]
            return terms + [("aperture area (dBm²)", db10(a_o)),
                            ("optics transmission", db10(p["optics_transmission"])),
                            (noise_label, -db10(det["noise_equiv"]))]

        b = BudgetBuilder()
        for name, value in snr_terms(p["range_m"]):
            b.add(name, value)
        budget = b.build()
        snr_db = budget.total
        required_db = db10(gaussian_required_deflection(p["pd"], p["pfa"]))

        def residual(r):
            return sum(v for _, v in snr_terms(r)) - required_db

        transmission = from_db10(-sum(ext_terms.values()) * p["range_m"] / 1e3)
        values = {
            "contrast_intensity_w_sr": j_w,
            "transmission": transmission,
            "irradiance_w_m2": point_target_irradiance_w_m2(j_w, p["range_m"], transmission),
            "nep_w": det["nep"],
            "d_star_jones": det["d_star"],
            "netd_k": det["netd"],
            "ifov_rad": jnp.sqrt(p["detector_area_m2"]) / focal,
            "snr_db": snr_db,
            "required_snr_db": required_db,
            "snr_margin_db": snr_db - required_db,
            "pd": gaussian_pd(from_db10(snr_db), p["pfa"]),
        }
        if needs(wanted, "detection_range_m"):
            values["detection_range_m"] = decreasing_root_log(residual, *_DETECTION_BRACKET_M).root
        return Evaluation(budget, values)
