"""Receiver noise: thermal noise and noise temperatures, noise figures, antenna temperature and
radiometer sensitivity, photodetector and voltage noise, and noise jamming.

Pure ``jnp`` formulas, jit/vmap/grad-able. SI units; dB quantities are 10·log10 of power
ratios and say so in their names. Boltzmann's constant is the exact SI value
(``diffsense.physics.constants``); the book (Brooker) rounds it to 1.38e-23 J/K, which moves its
printed noise levels by 0.002 dB — below its rounding.

Sources (book = Brooker, *Introduction to Sensors for Ranging and Imaging*): receiver noise
§9.1.1 eqs (9.1)–(9.3); photodetector noise §9.1.3 eqs (9.6)–(9.8); amplifier voltage noise
§12.8; noise jamming §9.10 eq (9.31). Others are cited per function. Blackbody radiation is in
:mod:`diffsense.physics.radiance`, underwater ambient noise in :mod:`diffsense.physics.sea_noise`.

The thermal noise density at the IEEE reference temperature is the well-known −174 dBm/Hz:

>>> from diffsense.physics.noise import thermal_noise_power_dbw
>>> round(float(thermal_noise_power_dbw(1.0)) + 30.0, 1)  # dBW → dBm, 1 Hz at 290 K
-174.0
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from diffsense.numerics.checks import check_range, is_concrete
from diffsense.numerics.db import DB_PER_NEPER, db10, from_db10
from diffsense.physics.constants import BOLTZMANN_J_K, ELEMENTARY_CHARGE_C, REFERENCE_TEMPERATURE_K

__all__ = [
    "thermal_noise_power_w",
    "thermal_noise_power_dbw",
    "noise_temperature_k",
    "noise_figure_db",
    "lossy_line_noise_figure_db",
    "cascade_noise_figure_db",
    "system_noise_temperature_k",
    "receiver_noise_power_dbw",
    "shot_noise_variance_a2",
    "johnson_noise_variance_a2",
    "johnson_noise_voltage_v",
    "apd_excess_noise_factor",
    "photodetector_noise_current_a",
    "nep_from_detectivity_w",
    "detectivity_from_nep_jones",
    "nep_from_noise_current_w",
    "voltage_noise_rms_v",
    "add_uncorrelated_rms",
    "total_power_radiometer_delta_t_k",
    "dicke_radiometer_delta_t_k",
    "antenna_temperature_k",
    "jammer_noise_density_w_hz",
    "self_screening_burn_through_range_m",
]

_K = BOLTZMANN_J_K
_Q = ELEMENTARY_CHARGE_C
_T0 = REFERENCE_TEMPERATURE_K


# ---------------------------------------------------------------------------------------------
# Receiver thermal noise
# ---------------------------------------------------------------------------------------------


def thermal_noise_power_w(bandwidth_hz, temperature_k=_T0):
    """Available thermal noise power ``P_N = k T β`` (W), book eq (9.1).

    Args:
        bandwidth_hz: noise bandwidth β (Hz), in (0, ∞).
        temperature_k: noise temperature T (K), in (0, ∞); default T0 = 290 K.

    Valid for hf ≪ kT (all radio and microwave bands; at 290 K hf/kT = 0.016 at 94 GHz).
    """
    w = "thermal_noise_power_w"
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("temperature_k", temperature_k, 0.0, None, lo_open=True, where=w)
    return _K * temperature_k * bandwidth_hz


def thermal_noise_power_dbw(bandwidth_hz, temperature_k=_T0):
    """``10 log10(k T β)`` (dBW); −127.0 dBW for 50 MHz at 290 K (book §8.16.11)."""
    return db10(thermal_noise_power_w(bandwidth_hz, temperature_k))


def noise_temperature_k(noise_figure_db_, reference_temperature_k=_T0):
    """Effective input noise temperature ``T_e = T0 (F − 1)`` (K) from a noise figure.

    Args:
        noise_figure_db_: noise figure NF = 10 log10 F (dB), in [0, 60].
        reference_temperature_k: T0 (K), in (0, ∞); default 290 K (IEEE).

    A noise factor of 2 (NF = 10 log10 2 = 3.01 dB) doubles the noise: T_e = T0.

    >>> import math
    >>> round(float(noise_temperature_k(10 * math.log10(2.0))), 9)
    290.0
    """
    w = "noise_temperature_k"
    check_range("noise_figure_db", noise_figure_db_, 0.0, 60.0, where=w)
    check_range("reference_temperature_k", reference_temperature_k, 0.0, None, lo_open=True, where=w)
    return reference_temperature_k * jnp.expm1(noise_figure_db_ / DB_PER_NEPER)


def noise_figure_db(noise_temperature_k_, reference_temperature_k=_T0):
    """Noise figure ``NF = 10 log10(1 + T_e / T0)`` (dB) from an input noise temperature.

    Args:
        noise_temperature_k_: effective input noise temperature T_e (K), in [0, 1e8].
        reference_temperature_k: T0 (K), in (0, ∞); default 290 K.

    >>> import math
    >>> abs(float(noise_figure_db(290.0)) - 10 * math.log10(2.0)) < 1e-12  # T_e = T0: F = 2
    True
    """
    w = "noise_figure_db"
    check_range("noise_temperature_k", noise_temperature_k_, 0.0, 1e8, where=w)
    check_range("reference_temperature_k", reference_temperature_k, 0.0, None, lo_open=True, where=w)
    return DB_PER_NEPER * jnp.log1p(noise_temperature_k_ / reference_temperature_k)


def lossy_line_noise_figure_db(loss_db, physical_temperature_k=_T0):
    """Noise figure of a matched passive loss L at physical temperature T_p (dB).

    ``F = 1 + (L − 1) T_p / T0``; equal to the loss when T_p = T0.

    Args:
        loss_db: loss 10 log10 L (dB), in [0, 100].
        physical_temperature_k: T_p (K), in [0, 1e4].

    Source: Pozar, *Microwave Engineering*, §10.1 (noise of a lossy line).
    """
    w = "lossy_line_noise_figure_db"
    check_range("loss_db", loss_db, 0.0, 100.0, where=w)
    check_range("physical_temperature_k", physical_temperature_k, 0.0, 1e4, where=w)
    t_e = jnp.expm1(loss_db / DB_PER_NEPER) * physical_temperature_k
    return DB_PER_NEPER * jnp.log1p(t_e / _T0)


def cascade_noise_figure_db(gains_db, noise_figures_db):
    """Friis cascade noise figure of a chain of stages (dB).

    ``F = F1 + (F2 − 1)/G1 + (F3 − 1)/(G1 G2) + …`` with stages along the last axis (first
    stage first). Passive losses enter as gain −L and noise figure L (at T0).

    Args:
        gains_db: available gains of the stages (dB), shape (..., n), each in [-100, 100].
        noise_figures_db: stage noise figures (dB), shape (..., n), each in [0, 60].

    Source: Friis, H. T. (1944), "Noise figures of radio receivers", Proc. IRE 32, 419–422.

    An LNA (gain 20 dB, NF 1 dB) ahead of a mixer (NF 10 dB): F = 10^0.1 + (10 − 1)/100.

    >>> import math
    >>> got = float(cascade_noise_figure_db([20.0, -6.0], [1.0, 10.0]))
    >>> abs(got - 10 * math.log10(10**0.1 + 9.0 / 100.0)) < 1e-12
    True
    """
    w = "cascade_noise_figure_db"
    check_range("gains_db", gains_db, -100.0, 100.0, where=w)
    check_range("noise_figures_db", noise_figures_db, 0.0, 60.0, where=w)
    gains_db = jnp.asarray(gains_db)
    noise_figures_db = jnp.asarray(noise_figures_db)
    excess = jnp.expm1(noise_figures_db / DB_PER_NEPER)  # F_i - 1
    # gain ahead of stage i: G_1 ... G_{i-1} (dB, cumulative, exclusive)
    ahead_db = jnp.cumsum(gains_db, axis=-1) - gains_db
    total_excess = jnp.sum(excess * from_db10(-ahead_db), axis=-1)
    return DB_PER_NEPER * jnp.log1p(total_excess)


def system_noise_temperature_k(
    antenna_temperature_k_, line_loss_db, receiver_noise_temperature_k, line_temperature_k=_T0
):
    """System noise temperature at the antenna terminals (K).

    ``T_sys = T_a + T_p (L − 1) + L T_rx``: antenna temperature, a lossy line of loss L at
    physical temperature T_p, then a receiver of input noise temperature T_rx.

    Args:
        antenna_temperature_k_: antenna noise temperature T_a (K), in [0, 1e5].
        line_loss_db: line loss 10 log10 L (dB), in [0, 60].
        receiver_noise_temperature_k: receiver T_rx (K), in [0, 1e8].
        line_temperature_k: physical temperature of the line T_p (K), in [0, 1e4].

    Source: Blake, L. V., *Radar Range-Performance Analysis* (1986), ch. 7 (system noise
    temperature referred to the antenna terminals).
    """
    w = "system_noise_temperature_k"
    check_range("antenna_temperature_k", antenna_temperature_k_, 0.0, 1e5, where=w)
    check_range("line_loss_db", line_loss_db, 0.0, 60.0, where=w)
    check_range("receiver_noise_temperature_k", receiver_noise_temperature_k, 0.0, 1e8, where=w)
    check_range("line_temperature_k", line_temperature_k, 0.0, 1e4, where=w)
    loss = from_db10(line_loss_db)
    return antenna_temperature_k_ + line_temperature_k * (loss - 1.0) + loss * receiver_noise_temperature_k


def receiver_noise_power_dbw(bandwidth_hz, noise_figure_db_, *, loss_db=0.0, temperature_k=_T0):
    """Receiver output noise referred to the input: ``N = 10 log10(k T β) + NF + L`` (dBW).

    The book adds the receive-line loss L (dB) to the noise figure (§9.9.1.3).

    Args:
        bandwidth_hz: noise bandwidth β (Hz), in (0, ∞).
        noise_figure_db_: receiver noise figure (dB), in [0, 60].
        loss_db: receive loss ahead of the receiver (dB), in [0, 60].
        temperature_k: T (K), default 290.

    Book: −149 + 4 + 2 = −143 dBW (§9.9.1.3); −127 + 13.7 dB (§8.16.11); −154 dBW (§11.12.4.8).
    The air-surveillance radar of §9.9.1.3 (β = 306 kHz, NF 4 dB, 2 dB receive line):

    >>> round(float(receiver_noise_power_dbw(306e3, 4.0, loss_db=2.0)))  # book: −143 dBW
    -143
    """
    w = "receiver_noise_power_dbw"
    check_range("noise_figure_db", noise_figure_db_, 0.0, 60.0, where=w)
    check_range("loss_db", loss_db, 0.0, 60.0, where=w)
    return thermal_noise_power_dbw(bandwidth_hz, temperature_k) + noise_figure_db_ + loss_db


# ---------------------------------------------------------------------------------------------
# Photodetector noise
# ---------------------------------------------------------------------------------------------


def shot_noise_variance_a2(current_a, bandwidth_hz):
    """Shot-noise current variance ``⟨i²⟩ = 2 q I β`` (A²).

    Args:
        current_a: mean current I (photo plus dark) (A), in [0, ∞).
        bandwidth_hz: noise bandwidth β (Hz), in (0, ∞).

    Source: book §9.1.3.2 (Schottky formula, eq (9.7)).
    """
    w = "shot_noise_variance_a2"
    check_range("current_a", current_a, 0.0, None, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    return 2.0 * _Q * current_a * bandwidth_hz


def johnson_noise_variance_a2(temperature_k, bandwidth_hz, resistance_ohm):
    """Johnson (thermal) noise current variance ``⟨i²⟩ = 4 k T β / R`` (A²), book eq (9.6).

    Args:
        temperature_k: resistor temperature T (K), in [0, 1e4].
        bandwidth_hz: noise bandwidth β (Hz), in (0, ∞).
        resistance_ohm: shunt/load resistance R (Ω), in (0, ∞).
    """
    w = "johnson_noise_variance_a2"
    check_range("temperature_k", temperature_k, 0.0, 1e4, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("resistance_ohm", resistance_ohm, 0.0, None, lo_open=True, where=w)
    return 4.0 * _K * temperature_k * bandwidth_hz / resistance_ohm


def johnson_noise_voltage_v(temperature_k, bandwidth_hz, resistance_ohm):
    """RMS open-circuit Johnson noise voltage ``v = sqrt(4 k T R β)`` (V), book eq (9.9).

    Args:
        temperature_k: T (K), in (0, 1e4].
        bandwidth_hz: β (Hz), in (0, ∞).
        resistance_ohm: R (Ω), in (0, ∞).
    """
    w = "johnson_noise_voltage_v"
    check_range("temperature_k", temperature_k, 0.0, 1e4, lo_open=True, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("resistance_ohm", resistance_ohm, 0.0, None, lo_open=True, where=w)
    return jnp.sqrt(4.0 * _K * temperature_k * resistance_ohm * bandwidth_hz)


def apd_excess_noise_factor(gain, ionization_ratio):
    """McIntyre's APD excess noise factor ``F = k M + (1 − k)(2 − 1/M)``.

    Args:
        gain: mean avalanche gain M, in [1, 1e4].
        ionization_ratio: k = β/α, ratio of the ionization coefficients of the less to the more
            ionizing carrier (injection of the more ionizing carrier), in [0, 1].

    Source: McIntyre, R. J. (1966), "Multiplication noise in uniform avalanche diodes",
    IEEE Trans. Electron Devices ED-13, 164–168, eq. for electron injection.
    """
    w = "apd_excess_noise_factor"
    check_range("gain", gain, 1.0, 1e4, where=w)
    check_range("ionization_ratio", ionization_ratio, 0.0, 1.0, where=w)
    return ionization_ratio * gain + (1.0 - ionization_ratio) * (2.0 - 1.0 / gain)


def photodetector_noise_current_a(
    signal_current_a,
    dark_current_a,
    bandwidth_hz,
    temperature_k,
    shunt_resistance_ohm,
    *,
    gain=1.0,
    ionization_ratio=0.0,
):
    """Total RMS noise current of a (avalanche) photodiode receiver (A).

    ``i_n² = 2 q (I_s + I_d) M² F(M) β + 4 k T β / R``: shot noise of the primary signal and
    dark currents multiplied by M² and the excess noise factor F, plus Johnson noise of the
    shunt/load resistance. ``gain=1`` gives a PIN diode (F = 1). All dark current is taken as
    multiplied (bulk dark current); a surface leakage term would add unmultiplied 2 q I β.

    Args:
        signal_current_a: primary (unmultiplied) photocurrent I_s (A), in [0, ∞).
        dark_current_a: primary dark current I_d (A), in [0, ∞).
        bandwidth_hz: noise bandwidth β (Hz), in (0, ∞).
        temperature_k: resistor temperature T (K), in (0, 1e4].
        shunt_resistance_ohm: R (Ω), in (0, ∞).
        gain: avalanche gain M, in [1, 1e4].
        ionization_ratio: k, in [0, 1].

    Source: book §9.1.3 eqs (9.6)–(9.7) and §9.1.3.5 (sum of the noise currents); McIntyre (1966).
    """
    w = "photodetector_noise_current_a"
    check_range("temperature_k", temperature_k, 0.0, 1e4, lo_open=True, where=w)
    excess = apd_excess_noise_factor(gain, ionization_ratio)
    shot = shot_noise_variance_a2(signal_current_a + dark_current_a, bandwidth_hz) * gain**2 * excess
    thermal = johnson_noise_variance_a2(temperature_k, bandwidth_hz, shunt_resistance_ohm)
    return jnp.sqrt(shot + thermal)


def nep_from_detectivity_w(detector_area_m2, bandwidth_hz, d_star_jones):
    """Noise-equivalent power from specific detectivity: ``NEP = sqrt(A_d Δf) / D*`` (W).

    A_d in cm² inside the square root (D* is quoted in Jones, cm·Hz^½/W); the argument is m²
    and converted here. Book eq (9.8).

    Args:
        detector_area_m2: detector area (m²), in (0, ∞).
        bandwidth_hz: bandwidth Δf (Hz), in (0, ∞).
        d_star_jones: D* (cm·Hz^½/W), in (0, ∞).
    """
    w = "nep_from_detectivity_w"
    check_range("detector_area_m2", detector_area_m2, 0.0, None, lo_open=True, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("d_star_jones", d_star_jones, 0.0, None, lo_open=True, where=w)
    return jnp.sqrt(detector_area_m2 * 1e4 * bandwidth_hz) / d_star_jones


def detectivity_from_nep_jones(detector_area_m2, bandwidth_hz, nep_w):
    """Specific detectivity ``D* = sqrt(A_d Δf) / NEP`` (Jones, cm·Hz^½/W), A_d in cm².

    Args:
        detector_area_m2: detector area (m²), in (0, ∞).
        bandwidth_hz: bandwidth Δf (Hz), in (0, ∞).
        nep_w: noise-equivalent power in that bandwidth (W), in (0, ∞).
    """
    w = "detectivity_from_nep_jones"
    check_range("detector_area_m2", detector_area_m2, 0.0, None, lo_open=True, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("nep_w", nep_w, 0.0, None, lo_open=True, where=w)
    return jnp.sqrt(detector_area_m2 * 1e4 * bandwidth_hz) / nep_w


def nep_from_noise_current_w(noise_current_a, responsivity_a_w):
    """NEP = RMS noise current / responsivity (W): the optical power giving unity SNR.

    Args:
        noise_current_a: RMS noise current in the bandwidth (A), in (0, ∞).
        responsivity_a_w: responsivity ℜ (A/W), in (0, ∞).
    """
    w = "nep_from_noise_current_w"
    check_range("noise_current_a", noise_current_a, 0.0, None, lo_open=True, where=w)
    check_range("responsivity_a_w", responsivity_a_w, 0.0, None, lo_open=True, where=w)
    return noise_current_a / responsivity_a_w


# ---------------------------------------------------------------------------------------------
# Voltage noise
# ---------------------------------------------------------------------------------------------


def voltage_noise_rms_v(noise_density_v_rthz, bandwidth_hz):
    """RMS noise voltage of a white voltage-noise density ``e_n sqrt(β)`` (V).

    Args:
        noise_density_v_rthz: e_n (V/√Hz), in [0, ∞).
        bandwidth_hz: β (Hz), in (0, ∞).

    Book §12.8: 1.2 nV/√Hz in 3 kHz → 66 nV:

    >>> round(float(voltage_noise_rms_v(1.2e-9, 3e3)) * 1e9)
    66
    """
    w = "voltage_noise_rms_v"
    check_range("noise_density_v_rthz", noise_density_v_rthz, 0.0, None, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    return noise_density_v_rthz * jnp.sqrt(bandwidth_hz)


def add_uncorrelated_rms(a, b):
    """RMS sum of two uncorrelated noise amplitudes ``sqrt(a² + b²)`` (same unit as a, b).

    Args:
        a, b: RMS amplitudes, in (0, ∞) (the gradient of the root is singular at a = b = 0).

    Book §12.8: 79 nV and 66 nV → 102.9 nV (the book prints 102 nV):

    >>> round(float(add_uncorrelated_rms(79e-9, 66e-9)) * 1e9, 1)
    102.9
    """
    w = "add_uncorrelated_rms"
    check_range("a", a, 0.0, None, lo_open=True, where=w)
    check_range("b", b, 0.0, None, lo_open=True, where=w)
    return jnp.sqrt(a * a + b * b)


# ---------------------------------------------------------------------------------------------
# Radiometer sensitivity
# ---------------------------------------------------------------------------------------------


def total_power_radiometer_delta_t_k(system_temperature_k, bandwidth_hz, integration_time_s, gain_variation=0.0):
    """Total-power radiometer sensitivity ``ΔT = T_sys sqrt(1/(βτ) + (ΔG/G)²)`` (K).

    Args:
        system_temperature_k: T_sys = T_A + T_rec (K), in (0, 1e6].
        bandwidth_hz: predetection bandwidth β (Hz), in (0, ∞).
        integration_time_s: integration time τ (s), in (0, ∞).
        gain_variation: RMS relative gain fluctuation ΔG/G in the integration time, in [0, 1].

    Source: Ulaby, Moore & Fung, *Microwave Remote Sensing* Vol. I (1981), ch. 6 (radiometer
    sensitivity); Skou, *Microwave Radiometer Systems* (1989), ch. 3.
    """
    w = "total_power_radiometer_delta_t_k"
    check_range("system_temperature_k", system_temperature_k, 0.0, 1e6, lo_open=True, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("integration_time_s", integration_time_s, 0.0, None, lo_open=True, where=w)
    check_range("gain_variation", gain_variation, 0.0, 1.0, where=w)
    return system_temperature_k * jnp.sqrt(1.0 / (bandwidth_hz * integration_time_s) + gain_variation**2)


def dicke_radiometer_delta_t_k(system_temperature_k, bandwidth_hz, integration_time_s):
    """Balanced Dicke radiometer sensitivity ``ΔT = 2 T_sys / sqrt(βτ)`` (K).

    Square-wave switching between antenna and a reference at the antenna temperature; gain
    fluctuations are suppressed.

    Args: as :func:`total_power_radiometer_delta_t_k`.
    Source: Ulaby, Moore & Fung (1981) Vol. I ch. 6; Skou (1989) ch. 3: the Dicke radiometer
    looks at the antenna half the time and differences two noisy halves, so its ΔT is twice that
    of a stable total-power radiometer.

    >>> round(float(dicke_radiometer_delta_t_k(500.0, 1e8, 1.0)
    ...             / total_power_radiometer_delta_t_k(500.0, 1e8, 1.0)), 12)
    2.0
    """
    w = "dicke_radiometer_delta_t_k"
    check_range("system_temperature_k", system_temperature_k, 0.0, 1e6, lo_open=True, where=w)
    check_range("bandwidth_hz", bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("integration_time_s", integration_time_s, 0.0, None, lo_open=True, where=w)
    return 2.0 * system_temperature_k / jnp.sqrt(bandwidth_hz * integration_time_s)


def antenna_temperature_k(
    main_beam_brightness_k,
    sidelobe_brightness_k,
    beam_efficiency,
    *,
    radiation_efficiency=1.0,
    physical_temperature_k=_T0,
):
    """Antenna temperature from scene brightness ``T_A = η_l[η_M T_ML + (1 − η_M) T_SL] + (1 − η_l) T_p``.

    η_M is the main-beam efficiency, T_ML and T_SL the mean brightness temperatures seen by the
    main beam and by the sidelobes, η_l the antenna radiation (ohmic) efficiency and T_p its
    physical temperature.

    Args:
        main_beam_brightness_k: T_ML (K), in [0, 1e5].
        sidelobe_brightness_k: T_SL (K), in [0, 1e5].
        beam_efficiency: η_M, in [0, 1].
        radiation_efficiency: η_l, in (0, 1].
        physical_temperature_k: T_p (K), in [0, 1e4].

    Source: Ulaby, Moore & Fung (1981) Vol. I ch. 4 (antenna temperature, beam efficiency).
    """
    w = "antenna_temperature_k"
    check_range("main_beam_brightness_k", main_beam_brightness_k, 0.0, 1e5, where=w)
    check_range("sidelobe_brightness_k", sidelobe_brightness_k, 0.0, 1e5, where=w)
    check_range("beam_efficiency", beam_efficiency, 0.0, 1.0, where=w)
    check_range("radiation_efficiency", radiation_efficiency, 0.0, 1.0, lo_open=True, where=w)
    check_range("physical_temperature_k", physical_temperature_k, 0.0, 1e4, where=w)
    apparent = beam_efficiency * main_beam_brightness_k + (1.0 - beam_efficiency) * sidelobe_brightness_k
    return radiation_efficiency * apparent + (1.0 - radiation_efficiency) * physical_temperature_k


# ---------------------------------------------------------------------------------------------
# Noise jamming
# ---------------------------------------------------------------------------------------------


def jammer_noise_density_w_hz(jammer_power_w, jammer_gain_db, radar_gain_db, wavelength_m, range_m, jammer_bandwidth_hz):
    """Jammer noise power density at the radar ``N_j = P_j G_j G_r λ² / ((4π)² R² β_j)`` (W/Hz).

    Args:
        jammer_power_w: jammer power P_j (W), in (0, ∞).
        jammer_gain_db: jammer antenna gain towards the radar (dB), in [-50, 80].
        radar_gain_db: radar antenna gain towards the jammer (dB; sidelobe for stand-off), in [-50, 80].
        wavelength_m: λ (m), in (0, ∞).
        range_m: jammer range R (m), in (0, ∞).
        jammer_bandwidth_hz: β_j (Hz), in (0, ∞).

    Source: book §9.10 eq (9.31) (after Skolnik 1980).
    """
    w = "jammer_noise_density_w_hz"
    check_range("jammer_power_w", jammer_power_w, 0.0, None, lo_open=True, where=w)
    check_range("jammer_gain_db", jammer_gain_db, -50.0, 80.0, where=w)
    check_range("radar_gain_db", radar_gain_db, -50.0, 80.0, where=w)
    check_range("wavelength_m", wavelength_m, 0.0, None, lo_open=True, where=w)
    check_range("range_m", range_m, 0.0, None, lo_open=True, where=w)
    check_range("jammer_bandwidth_hz", jammer_bandwidth_hz, 0.0, None, lo_open=True, where=w)
    gains = from_db10(jammer_gain_db + radar_gain_db)
    return jammer_power_w * gains * wavelength_m**2 / ((4.0 * np.pi) ** 2 * range_m**2 * jammer_bandwidth_hz)


def self_screening_burn_through_range_m(
    peak_power_w,
    radar_gain_db,
    rcs_m2,
    jammer_power_w,
    jammer_gain_db,
    jammer_bandwidth_hz,
    receiver_bandwidth_hz,
    required_sjr_db,
):
    """Burn-through range against a self-screening (main-lobe) noise jammer (m).

    Echo ``S = P_t G² λ² σ / ((4π)³ R⁴)`` against jamming ``J = N_j β_r`` (:func:`jammer_noise_density_w_hz`
    with G_r = G, the jammer filling the receiver band, β_r ≤ β_j). S/J = P_t G σ β_j /
    (4π P_j G_j β_r R²), so

        ``R_bt = sqrt(P_t G σ β_j / (4π P_j G_j β_r · SJR))``.

    λ cancels. Receiver noise is neglected (J ≫ kT0Fβ_r). Source: book §9.10 (substitute N_j
    for the receiver noise density in the radar equation), Skolnik, *Introduction to Radar
    Systems* (1980), §14.

    Args:
        peak_power_w: radar peak power P_t (W), in (0, ∞).
        radar_gain_db: radar antenna gain G (dB), in [-50, 80].
        rcs_m2: target RCS σ (m²), in (0, ∞).
        jammer_power_w: P_j (W), in (0, ∞).
        jammer_gain_db: G_j (dB), in [-50, 80].
        jammer_bandwidth_hz: β_j (Hz), in (0, ∞).
        receiver_bandwidth_hz: β_r (Hz), in (0, ∞), ≤ β_j.
        required_sjr_db: required signal-to-jamming ratio (dB), in [-50, 100].
    """
    w = "self_screening_burn_through_range_m"
    check_range("peak_power_w", peak_power_w, 0.0, None, lo_open=True, where=w)
    check_range("radar_gain_db", radar_gain_db, -50.0, 80.0, where=w)
    check_range("rcs_m2", rcs_m2, 0.0, None, lo_open=True, where=w)
    check_range("jammer_power_w", jammer_power_w, 0.0, None, lo_open=True, where=w)
    check_range("jammer_gain_db", jammer_gain_db, -50.0, 80.0, where=w)
    check_range("jammer_bandwidth_hz", jammer_bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("receiver_bandwidth_hz", receiver_bandwidth_hz, 0.0, None, lo_open=True, where=w)
    check_range("required_sjr_db", required_sjr_db, -50.0, 100.0, where=w)
    if is_concrete(jammer_bandwidth_hz) and is_concrete(receiver_bandwidth_hz):
        excess = np.asarray(receiver_bandwidth_hz, dtype=float) - np.asarray(jammer_bandwidth_hz, dtype=float)
        check_range("receiver_bandwidth_hz - jammer_bandwidth_hz", excess, None, 0.0, where=w)
    num = peak_power_w * from_db10(radar_gain_db) * rcs_m2 * jammer_bandwidth_hz
    den = 4.0 * np.pi * jammer_power_w * from_db10(jammer_gain_db) * receiver_bandwidth_hz * from_db10(required_sjr_db)
    return jnp.sqrt(num / den)
