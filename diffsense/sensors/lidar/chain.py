"""The lidar (laser rangefinder) chain: ``evaluate(Scene("lidar", parts, options), params)``.

Signal path (every factor a named budget term, see :mod:`diffsense.sensors.lidar.range_equation`)::

    P_r = P_t τ_t (ρ cos θ / π) f (1/R²) A_r τ_r T_haze T_dust          (W)

with f = 1 for an extended target and f = smooth min(1, A cos θ / A_f) for a target of
area A inside the footprint A_f of a beam of divergence θ_t (point target).

Detectors (static option ``detector``):

* ``"pin"`` / ``"apd"`` — direct detection. The electrical SNR is (P_r / NEP)² times the pulse
  response of the single-pole receiver filter. The budget lists the optical terms (their sum
  is P_r in dBW), then −NEP (dBW), the term "square-law detection" = P_r − NEP (dB) that
  counts the optical SNR a second time (SNR ∝ P_r²), and the pulse response
  20 log10(1 − e^(−4Bτ)). NEP = i_n/(ℜ M) includes the shot noise of signal, background
  and dark current, the Johnson noise of the load and the amplifier noise
  (:mod:`diffsense.sensors.lidar.receiver`).
* ``"heterodyne"`` — coherent detection with a local oscillator: SNR ∝ P_r, so the optical
  terms are 10 log10, followed by quantum efficiency, mixing efficiency, −10 log10(hνB), the
  LO shot-noise fraction (0 dB at the quantum limit) and the IF pulse response.

The budget total is ``snr_db`` (single-pulse peak SNR).

Detection statistics (static option ``statistics``):

* ``"threshold"`` (default for PIN/APD): baseband threshold in Gaussian noise, steady return
  (many speckles averaged over the aperture), N pulses averaged —
  :mod:`diffsense.sensors.lidar.statistics`. Only ``swerling`` 0 ("auto") is allowed, and only for
  PIN/APD receivers.
* ``"square_law"`` (default for heterodyne): envelope (square-law) detection of the IF
  signal with N pulses integrated noncoherently, :func:`diffsense.detection.pd` with the
  Swerling case of option ``swerling``. ``"auto"`` means Swerling 1 for heterodyne: the IF
  field of a rough target is a single speckle, complex Gaussian, so the echo power is
  exponentially distributed and frozen over the dwell of a still target (Goodman, J. W.
  (1965), "Some effects of target-induced scintillation on optical radar performance",
  Proc. IEEE 53:1688); Swerling 0 for direct detection.

Scene parts: ``haze`` (Koschmieder/Kim or Kruse extinction from the visibility,
:func:`diffsense.physics.propagation.laser_extinction_db_per_km`), ``dust`` (book §7.2.6/§8.16.2:
mass loading M = 37.3 V^−1.07 g/m³, extinction k·M), ``sun`` (solar background through the
optical filter and field of view, :func:`diffsense.sensors.lidar.range_equation.solar_background_power_w`,
attenuated by the one-way haze and dust of the path). Haze and dust are uniform along the path
(two-way loss 2 R α). The background scene is the target itself for an extended target and a
sunlit background of reflectance ``background_reflectivity`` for a point target.

The detection range solves snr_margin_db(R) = 0 with :func:`diffsense.numerics.rootfind.decreasing_root_log`
in [1 cm, 10 000 km]; it is differentiable implicitly. Outside the bracket the bound is returned.
"""

from __future__ import annotations

import math

import jax.numpy as jnp

from diffsense import detection
from diffsense.errors import DomainError
from diffsense.numerics.db import DB_PER_NEPER, db10, from_db10
from diffsense.physics.antennas import circular_aperture_area_m2
from diffsense.sensors.chain import BudgetBuilder, Chain, Evaluation, Output, Param, collect, needs
from diffsense.sensors.parts import scene_part
from diffsense.physics.constants import ELEMENTARY_CHARGE_C
from diffsense.physics.noise import apd_excess_noise_factor
from diffsense.physics.propagation import (
    dust_laser_extinction_db_per_km,
    dust_mass_loading_g_m3,
    laser_extinction_db_per_km,
)
from diffsense.physics.propagation.free_space import atmospheric_two_way_loss_db
from diffsense.numerics.rootfind import decreasing_root_log
from diffsense.physics.waveforms import range_resolution_pulse_m

from diffsense.sensors.lidar.range_equation import (
    ASTM_G173_GLOBAL_TILT_W_M2_NM,
    beam_footprint_area_m2,
    crossover_range_m,
    intercepted_fraction,
    photon_energy_j,
    solar_background_power_w,
)
from diffsense.sensors.lidar.receiver import (
    direct_detection_noise_current_a,
    heterodyne_noise_psd_a2_hz,
    optimum_apd_gain,
    responsivity_a_w,
    single_pole_pulse_response,
)
from diffsense.sensors.lidar.statistics import threshold_detection_pd, threshold_required_snr_db

__all__ = [
    "LidarChain",
    "haze_two_way_loss_db",
    "haze_two_way_loss_db_kruse",
    "dust_two_way_loss_db",
    "sun_background_power_w",
    "DETECTION_RANGE_BRACKET_M",
    "BOOK_DUST_MASS_EXTINCTION_M2_G",
]

_Q = ELEMENTARY_CHARGE_C

#: Search bracket of the detection range (m).
DETECTION_RANGE_BRACKET_M = (1e-2, 1e7)

#: The book's optimistic dust extinction, 0.1 (dB/km) per (mg/m³) (Brooker §7.2.6.2, §8.16.2),
#: as a mass extinction coefficient: 0.1 dB/km per mg/m³ = 0.1 dB/m per g/m³ = 0.1·ln(10)/10 m²/g.
BOOK_DUST_MASS_EXTINCTION_M2_G = 0.1 / DB_PER_NEPER

#: SNR range handed to :func:`diffsense.detection.pd` (its documented domain).
_SQUARE_LAW_SNR_DB = (-50.0, 80.0)


# --- scene parts ---------------------------------------------------------------------------


@scene_part("haze")
def haze_two_way_loss_db(range_m, visibility_m, wavelength_m):
    """Two-way haze/fog extinction 2 R α(V, λ) (dB), Kim et al. (2001) q(V)."""
    return atmospheric_two_way_loss_db(range_m, laser_extinction_db_per_km(visibility_m, wavelength_m, "kim"))


@scene_part("haze")
def haze_two_way_loss_db_kruse(range_m, visibility_m, wavelength_m):
    """Two-way haze extinction 2 R α(V, λ) (dB), Kruse et al. (1962) q(V)."""
    return atmospheric_two_way_loss_db(range_m, laser_extinction_db_per_km(visibility_m, wavelength_m, "kruse"))


@scene_part("dust")
def dust_two_way_loss_db(range_m, dust_visibility_m, dust_mass_extinction_m2_g):
    """Two-way dust extinction (dB): 2 R k M(V), M = 37.3 V^−1.07 g/m³ (book eq. (7.10)).

    ``dust_mass_extinction_m2_g`` k (m²/g) is converted to the book's (dB/km)/(mg/m³) by
    10/ln(10); the book's 0.1–0.43 (dB/km)/(mg/m³) is 0.0230–0.0990 m²/g.
    """
    mass = dust_mass_loading_g_m3(dust_visibility_m)
    per_km = dust_laser_extinction_db_per_km(mass, dust_mass_extinction_m2_g * DB_PER_NEPER)
    return atmospheric_two_way_loss_db(range_m, per_km)


@scene_part("sun")
def sun_background_power_w(solar_irradiance_w_m2_nm, filter_bandwidth_m, reflectivity, receiver_fov_rad,
                           receiver_area_m2, optics_efficiency, one_way_loss_db):
    """Solar background power (W) collected from the Lambertian scene filling the field of view."""
    transmission = from_db10(-one_way_loss_db)
    return solar_background_power_w(solar_irradiance_w_m2_nm, filter_bandwidth_m, reflectivity, receiver_fov_rad,
                                    receiver_area_m2, optics_efficiency, transmission)


# --- chain -----------------------------------------------------------------------------------


def _link_parameters(target):
    """Laser, optics, target and geometry."""
    ps = [
        Param("range_m", "m", "range to the target R", lo=DETECTION_RANGE_BRACKET_M[0],
              hi=DETECTION_RANGE_BRACKET_M[1]),
        Param("peak_power_w", "W", "transmitted peak optical power P_t (design default: pulsed laser diode)",
              default=25.0, lo=1e-6, hi=1e12),
        Param("pulse_width_s", "s", "rectangular pulse length τ (design default)", default=10e-9,
              lo=1e-12, hi=1e-3),
        Param("wavelength_m", "m", "laser wavelength λ (default 905 nm laser diode)", default=905e-9,
              lo=2e-7, hi=2e-5),
        Param("receiver_diameter_m", "m", "receiver aperture diameter D_r (design default)", default=0.05,
              lo=1e-6, hi=10.0),
        Param("transmit_efficiency", "1", "transmit optics efficiency τ_t (design default)", default=0.9,
              lo=1e-6, hi=1.0),
        Param("receive_efficiency", "1", "receive optics and filter transmission τ_r (design default)",
              default=0.7, lo=1e-6, hi=1.0),
        Param("reflectivity", "1", "diffuse (Lambertian) reflectance ρ of the target (book 8.16: rock ≈ 0.5)",
              default=0.5, lo=1e-6, hi=1.0),
        Param("incidence_rad", "rad", "angle θ between the target normal and the line of sight", default=0.0,
              lo=0.0, hi=0.5 * math.pi, hi_open=True),
    ]
    if target == "point":
        ps += [
            Param("target_area_m2", "m**2", "physical area A of the target plate (design default)",
                  default=1.0, lo=1e-8, hi=1e6),
            Param("beam_divergence_rad", "rad",
                  "full transmit beam divergence θ_t (book 13.9: Riegl FG21-P 2.5 mrad)", default=2.5e-3,
                  lo=1e-7, hi=1.0),
        ]
    return ps


def _receiver_parameters(detector):
    """Detector, load, amplifier and filter; APD gain or local oscillator."""
    ps = [
        Param("quantum_efficiency", "1", "detector quantum efficiency η (design default)", default=0.8,
              lo=1e-6, hi=1.0),
        Param("dark_current_a", "A", "detector (primary) dark current I_d (design default)", default=1e-9,
              lo=0.0, hi=1e-3),
        Param("load_resistance_ohm", "ohm", "load / TIA feedback resistance R_L (design default)",
              default=1e4, lo=1e-3, hi=1e12),
        Param("amplifier_noise_a_rthz", "A/Hz**0.5",
              "amplifier input noise current density i_a (design default)", default=2e-12, lo=0.0, hi=1e-6),
        Param("receiver_temperature_k", "K", "load resistor temperature T (IEEE T0)", default=290.0, lo=1e-3,
              hi=1e4),
        Param("bandwidth_hz", "Hz",
              "receiver noise-equivalent bandwidth B (single-pole filter; IF bandwidth for heterodyne)",
              default=50e6, lo=1.0, hi=1e12),
    ]
    if detector == "apd":
        ps += [
            Param("apd_gain", "1", "APD mean gain M (design default)", default=100.0, lo=1.0, hi=1e4),
            Param("ionization_ratio", "1",
                  "McIntyre ionization ratio k (design default, low-k silicon-like APD)", default=0.02,
                  lo=0.0, hi=1.0),
        ]
    if detector == "heterodyne":
        ps += [
            Param("lo_power_w", "W", "local-oscillator power on the detector P_LO (design default)",
                  default=1e-3, lo=1e-9, hi=1.0),
            Param("mixing_efficiency", "1", "heterodyne mixing efficiency η_m (design default)", default=0.5,
                  lo=1e-6, hi=1.0),
        ]
    return ps


def _scene_part_parameters(scene, target):
    """Haze, dust and sun."""
    ps = []
    if scene.has("haze"):
        ps.append(Param("visibility_m", "m", "meteorological visibility V (default 23 km, clear air)",
                        default=23e3, lo=1.0, hi=1e6, part="haze"))
    if scene.has("dust"):
        ps += [
            Param("dust_visibility_m", "m", "visibility in the dust V (book 8.16.2 ore pass: 20 m)",
                  default=20.0, lo=1.0, hi=1e5, part="dust"),
            Param("dust_mass_extinction_m2_g", "m**2/g",
                  "dust extinction per unit mass loading k (book 0.1-0.43 (dB/km)/(mg/m³) = 0.023-0.099 m²/g; "
                  "default the optimistic 0.1; at most 10 (dB/km)/(mg/m³))", default=BOOK_DUST_MASS_EXTINCTION_M2_G,
                  lo=0.0, hi=10.0 / DB_PER_NEPER, part="dust"),
        ]
    if scene.has("sun"):
        ps += [
            Param("solar_irradiance_w_m2_nm", "W/m**2/nm",
                  "solar spectral irradiance on the scene at λ (ASTM G173-03 global tilt, 905 nm: 0.817)",
                  default=ASTM_G173_GLOBAL_TILT_W_M2_NM[905], lo=0.0, hi=3.0, part="sun"),
            Param("filter_bandwidth_m", "m", "optical filter bandwidth Δλ (design default 10 nm)", default=10e-9,
                  lo=1e-12, hi=1e-5, part="sun"),
            Param("receiver_fov_rad", "rad", "full receiver field of view θ_fov (book 13.9: matched to 2.5 mrad)",
                  default=2.5e-3, lo=1e-7, hi=math.pi, part="sun"),
        ]
        if target == "point":
            ps.append(Param("background_reflectivity", "1",
                            "reflectance of the sunlit background behind a point target (design default)",
                            default=0.3, lo=0.0, hi=1.0, part="sun"))
    return ps


def _detection_parameters():
    """Detection requirement and pulse count."""
    return [
        Param("pd", "1", "required probability of detection", default=0.9, lo=0.5, hi=1.0 - 1e-9),
        Param("pfa", "1", "false-alarm probability per range decision", default=1e-6, lo=1e-15, hi=0.1),
        Param("n_pulses", "1", "pulses averaged (direct) or integrated noncoherently (heterodyne)",
              default=1.0, lo=1.0, hi=1e4, integer=True),
    ]


class LidarChain(Chain):
    """Pulsed laser rangefinder / lidar against a Lambertian target (module docstring)."""

    kind = "lidar"
    description = "pulsed laser rangefinder: laser range equation, PIN/APD/heterodyne receiver, pulse detection"
    parts = {
        "haze": "haze or fog on the path: extinction from the visibility (Kim 2001 / Kruse 1962)",
        "dust": "dust on the path: mass loading from the visibility, extinction per unit mass (book 7.2.6, 8.16.2)",
        "sun": "sunlit scene in the field of view: solar background power and its shot noise",
    }
    options = {
        "target": ("extended", ("extended", "point")),
        "detector": ("apd", ("pin", "apd", "heterodyne")),
        "statistics": ("auto", ("auto", "threshold", "square_law")),
        "swerling": ("auto", ("auto", 0, 1, 2, 3, 4)),
        "haze_model": ("kim", ("kim", "kruse")),
    }

    # static choices ------------------------------------------------------------------------
    def resolved(self, scene):
        """(detector, target, statistics, swerling) with the "auto" choices resolved."""
        detector = self.option(scene, "detector")
        target = self.option(scene, "target")
        stats = self.option(scene, "statistics")
        if stats == "auto":
            stats = "square_law" if detector == "heterodyne" else "threshold"
        swerling = self.option(scene, "swerling")
        if swerling == "auto":
            swerling = 1 if (detector == "heterodyne" and stats == "square_law") else 0
        return detector, target, stats, swerling

    def validate_scene(self, scene):
        super().validate_scene(scene)
        detector, _, stats, swerling = self.resolved(scene)
        if detector == "heterodyne" and stats == "threshold":
            raise DomainError("lidar scene: a heterodyne receiver detects the IF envelope; use statistics "
                              "'square_law' (or 'auto'), not the baseband 'threshold' model")
        if stats == "threshold" and swerling != 0:
            raise DomainError(
                f"lidar scene: statistics 'threshold' models a steady return (swerling 0); got swerling={swerling!r}. "
                "Use statistics='square_law' for a fluctuating target."
            )

    # parameters ----------------------------------------------------------------------------
    def parameters(self, scene):
        detector, target, _, _ = self.resolved(scene)
        return collect(_link_parameters(target) + _receiver_parameters(detector) + _detection_parameters()
                       + _scene_part_parameters(scene, target))

    # outputs --------------------------------------------------------------------------------
    def outputs(self, scene):
        detector, target, stats, swerling = self.resolved(scene)
        outs = [
            Output("received_power_w", "W", "received peak signal power P_r at range_m"),
            Output("received_power_dbm", "dBm", "P_r in dBm"),
            Output("signal_photoelectrons", "1", "mean photoelectrons per pulse η P_r τ / (h ν) (before gain)"),
            Output("nep_w", "W", "noise-equivalent power at the operating point (SNR = 1 in bandwidth B)"),
            Output("snr_db", "dB", "single-pulse peak SNR (the budget total)"),
            Output("required_snr_db", "dB",
                   f"single-pulse SNR needed for pd at pfa with n_pulses ({stats}, swerling {swerling})"),
            Output("snr_margin_db", "dB", "snr_db − required_snr_db"),
            Output("pd", "1", "detection probability at range_m"),
            Output("detection_range_m", "m", "range where snr_margin_db = 0 (within the bracket 1 cm - 10000 km)"),
            Output("range_resolution_m", "m", "c τ / 2"),
        ]
        if target == "point":
            outs.append(Output("crossover_range_m", "m", "range where the footprint equals the projected target area"))
        if scene.has("sun"):
            outs.append(Output("background_power_w", "W", "solar background power on the detector"))
        if scene.has("haze") or scene.has("dust"):
            outs.append(Output("path_loss_db", "dB", "two-way optical extinction of haze and dust at range_m"))
        if detector == "apd":
            outs += [
                Output("excess_noise_factor", "1", "McIntyre excess noise factor F(M)"),
                Output("optimum_apd_gain", "1", "gain maximising the SNR at the operating point (< 1: use M = 1)"),
            ]
        return {o.name: o for o in outs}

    # computation ----------------------------------------------------------------------------
    def _setup(self, scene, p):
        """Range-independent quantities: optical terms at 1 m, per-metre path losses, background
        power without path loss, responsivity. The scene parts are evaluated here, once; the
        extinction is uniform along the path, so the two-way loss at R is R times the loss of
        the first metre."""
        detector, target, _, _ = self.resolved(scene)
        st = {"area_r": circular_aperture_area_m2(p["receiver_diameter_m"]), "cos_i": jnp.cos(p["incidence_rad"])}
        st["fixed"] = [
            ("peak power", db10(p["peak_power_w"])),
            ("transmit optics", db10(p["transmit_efficiency"])),
            ("target reflectance rho cos(theta)/pi", db10(p["reflectivity"] * st["cos_i"] / jnp.pi)),
        ]
        st["rx"] = [("receiver aperture area", db10(st["area_r"])), ("receive optics", db10(p["receive_efficiency"]))]
        st["path_per_m"] = []
        one_m = jnp.ones_like(p["range_m"])
        if scene.has("haze"):
            kruse = self.option(scene, "haze_model") == "kruse"
            haze_fn = haze_two_way_loss_db_kruse if kruse else haze_two_way_loss_db
            st["path_per_m"].append(("haze (two-way)", haze_fn(one_m, p["visibility_m"], p["wavelength_m"])))
        if scene.has("dust"):
            st["path_per_m"].append(("dust (two-way)", dust_two_way_loss_db(one_m, p["dust_visibility_m"],
                                                                            p["dust_mass_extinction_m2_g"])))
        if scene.has("sun"):
            rho_bg = p["background_reflectivity"] if target == "point" else p["reflectivity"]
            st["pb0_w"] = sun_background_power_w(p["solar_irradiance_w_m2_nm"], p["filter_bandwidth_m"], rho_bg,
                                                 p["receiver_fov_rad"], st["area_r"], p["receive_efficiency"],
                                                 jnp.zeros_like(one_m))
        st["resp"] = responsivity_a_w(p["quantum_efficiency"], p["wavelength_m"])
        return st

    def _at_range(self, scene, p, st, range_m):
        """Budget terms, SNR and noise quantities at ``range_m`` (elementwise, cheap)."""
        detector, target, _, _ = self.resolved(scene)
        r = range_m
        optical = list(st["fixed"])
        if target == "point":
            footprint = beam_footprint_area_m2(r, p["beam_divergence_rad"])
            projected = p["target_area_m2"] * st["cos_i"]
            optical.append(("beam fill (intercepted fraction)", db10(intercepted_fraction(projected, footprint))))
        optical.append(("range spreading 1/R^2", -2.0 * db10(r)))
        optical += st["rx"]
        path_db = jnp.zeros_like(r)
        for name, per_m in st["path_per_m"]:
            loss = r * per_m
            optical.append((name, -loss))
            path_db = path_db + loss
        pr_dbw = sum(v for _, v in optical)
        pr_w = from_db10(pr_dbw)
        pb_w = st["pb0_w"] * from_db10(-0.5 * path_db) if scene.has("sun") else jnp.zeros_like(pr_w)

        resp = st["resp"]
        bw = p["bandwidth_hz"]
        tau = p["pulse_width_s"]
        terms = list(optical)
        out = {"pr_dbw": pr_dbw, "pr_w": pr_w, "pb_w": pb_w, "path_db": path_db}
        if detector == "heterodyne":
            hnu_b = photon_energy_j(p["wavelength_m"]) * bw
            psd = heterodyne_noise_psd_a2_hz(pr_w, p["lo_power_w"], pb_w, resp, p["dark_current_a"],
                                             p["receiver_temperature_k"], p["load_resistance_ohm"],
                                             p["amplifier_noise_a_rthz"])
            lo_fraction = 2.0 * _Q * resp * p["lo_power_w"] / psd
            terms += [
                ("quantum efficiency", db10(p["quantum_efficiency"])),
                ("mixing efficiency", db10(p["mixing_efficiency"])),
                ("photon energy x bandwidth 1/(h nu B)", -db10(hnu_b)),
                ("LO shot-noise fraction", db10(lo_fraction)),
                ("pulse response (IF filter)", db10(single_pole_pulse_response(bw, tau, "if"))),
            ]
            out["nep_w"] = hnu_b / (p["quantum_efficiency"] * p["mixing_efficiency"] * lo_fraction)
            out["noise_ratio"] = jnp.ones_like(pr_w)
        else:
            gain = p["apd_gain"] if detector == "apd" else 1.0
            k = p["ionization_ratio"] if detector == "apd" else 0.0
            common = (resp, p["dark_current_a"], bw, p["receiver_temperature_k"], p["load_resistance_ohm"],
                      p["amplifier_noise_a_rthz"], gain, k)
            i_n1 = direct_detection_noise_current_a(pr_w, pb_w, *common)
            i_n0 = direct_detection_noise_current_a(jnp.zeros_like(pr_w), pb_w, *common)
            nep = i_n1 / (resp * gain)
            nep_dbw = db10(nep)
            terms += [
                ("noise-equivalent power", -nep_dbw),
                ("square-law detection (SNR ~ P_r^2)", pr_dbw - nep_dbw),
                ("pulse response (receiver filter)", db10(single_pole_pulse_response(bw, tau, "baseband"))),
            ]
            out["nep_w"] = nep
            out["noise_ratio"] = i_n0 / i_n1
        out["terms"] = terms
        out["snr_db"] = sum(v for _, v in terms)
        return out

    def _required(self, scene, p, noise_ratio):
        _, _, stats, swerling = self.resolved(scene)
        if stats == "threshold":
            return threshold_required_snr_db(p["pd"], p["pfa"], p["n_pulses"], noise_ratio)
        return detection.required_snr_db(p["pd"], p["pfa"], p["n_pulses"], swerling) + jnp.zeros_like(noise_ratio)

    def _pd(self, scene, p, snr_db, noise_ratio):
        _, _, stats, swerling = self.resolved(scene)
        if stats == "threshold":
            return threshold_detection_pd(jnp.clip(snr_db, -300.0, 300.0), p["pfa"], p["n_pulses"], noise_ratio)
        return detection.pd(jnp.clip(snr_db, *_SQUARE_LAW_SNR_DB), p["pfa"], p["n_pulses"], swerling)

    def compute(self, scene, p, wanted=None):
        """The budget at ``range_m`` and the outputs; with ``wanted`` (a frozenset of output names)
        the required-SNR solve, the Pd series and the range root find are traced only when a
        wanted output needs them (see :class:`diffsense.sensors.chain.Chain`)."""
        detector, target, stats, _ = self.resolved(scene)
        st = self._setup(scene, p)
        link = self._at_range(scene, p, st, p["range_m"])
        builder = BudgetBuilder()
        for name, value in link["terms"]:
            builder.add(name, value)
        budget = builder.build()
        snr_db = budget.total

        values = {
            "received_power_w": link["pr_w"],
            "received_power_dbm": link["pr_dbw"] + 30.0,
            "signal_photoelectrons": (p["quantum_efficiency"] * link["pr_w"] * p["pulse_width_s"]
                                      / photon_energy_j(p["wavelength_m"])),
            "nep_w": link["nep_w"],
            "snr_db": snr_db,
        }
        square_law = stats == "square_law"
        # the square-law range root find reuses the requirement at range_m (it does not vary with range)
        if needs(wanted, "required_snr_db", "snr_margin_db") or (square_law and needs(wanted, "detection_range_m")):
            required = self._required(scene, p, link["noise_ratio"])
            values["required_snr_db"] = required
            values["snr_margin_db"] = snr_db - required
        if needs(wanted, "pd"):
            values["pd"] = self._pd(scene, p, snr_db, link["noise_ratio"])
        if needs(wanted, "detection_range_m"):
            if square_law:
                def margin(r):
                    return self._at_range(scene, p, st, r)["snr_db"] - required
            else:
                def margin(r):
                    lk = self._at_range(scene, p, st, r)
                    return lk["snr_db"] - self._required(scene, p, lk["noise_ratio"])

            lo, hi = DETECTION_RANGE_BRACKET_M
            shape = jnp.shape(snr_db)
            values["detection_range_m"] = decreasing_root_log(margin, jnp.full(shape, lo), jnp.full(shape, hi)).root
        values["range_resolution_m"] = range_resolution_pulse_m(p["pulse_width_s"])
        if target == "point":
            values["crossover_range_m"] = crossover_range_m(p["target_area_m2"] * st["cos_i"],
                                                            p["beam_divergence_rad"])
        if scene.has("sun"):
            values["background_power_w"] = link["pb_w"]
        if scene.has("haze") or scene.has("dust"):
            values["path_loss_db"] = link["path_db"]
        if detector == "apd":
            values["excess_noise_factor"] = apd_excess_noise_factor(p["apd_gain"], p["ionization_ratio"])
            # 1e-30 A floor: keeps the root finite when signal, background and dark current all vanish
            primary = st["resp"] * (link["pr_w"] + link["pb_w"]) + p["dark_current_a"] + 1e-30
            values["optimum_apd_gain"] = optimum_apd_gain(primary, p["ionization_ratio"], p["receiver_temperature_k"],
                                                          p["load_resistance_ohm"], p["amplifier_noise_a_rthz"])
        return Evaluation(budget, values)
