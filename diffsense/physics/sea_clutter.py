"""Sea-clutter reflectivity σ° of the sea surface, down to the grazing angles of a ship radar.

Two models, chosen by name (:func:`sea_clutter_sigma0`):

* ``"nrl"`` — the NRL empirical model (Gregers-Hansen & Mital 2012), fitted to Nathanson's
  tables of measured apparent reflectivity (60 sources)::

      σ°(dB) = c1 + c2 log10 sin ψ + (27.5 + c3 ψ) log10 f / (1 + 0.95 ψ)
               + c4 (1 + SS)^(1 / (2 + 0.085 ψ + 0.033 SS)) + c5 ψ²

  with ψ the grazing angle in degrees, f the frequency in GHz and SS the sea state (continuous
  values allowed), and the coefficients of :data:`NRL_COEFFICIENTS` for horizontal and vertical
  polarization. Validity (the fitted data): 0.5-35 GHz, sea state 0-6, ψ 0.1°-60°; average
  absolute deviation from the data 2.2-2.3 dB for ψ 0.1°-10° and 2.6 dB for 10°-60°. "Apparent":
  the data, and so the model, include the propagation and shadowing effects near the surface.

  **Below 0.1°** (outside the fitted data) the model is continued into the deep interference
  region, where the multipath null at the surface makes the clutter fall as ψ⁴ (Katzin 1957;
  Barton 2013 §9.2: σ° ∝ ψ⁴ below the critical angle ψ_c = λ/(4π σ_h), which lies above 0.1°
  for all but the longest waves of this domain). With L the model in dB, u = ln(ψ / 0.1°) < 0 and
  s0 = dL/du at 0.1° (the NRL slope there)::

      L(u) = L(0) + A u − (A − s0) (exp(u) − 1),    A = 40/ln 10 dB per neper (σ° ∝ ψ⁴)

  continuous with its first derivative at 0.1°, with a log-slope that moves from s0 to the ψ⁴
  slope over about one neper of ψ (half way at 0.069°). The grazing angle of a ship radar
  (8 m mast, 5 km: 0.075° over the 4/3 earth) is inside this continuation; it is a model choice
  with that source, not a fit to data.
* ``"constant_gamma"`` — the book's constant-γ model σ° = γ sin ψ with Barton's sea γ
  (book §8.12.4 eq (8.29), :func:`diffsense.physics.clutter.sea_clutter_gamma_db`; Beaufort
  force from the sea state by book Table 12.2). It omits the near-grazing fall-off, so it is
  valid only in the plateau region: ψ in [1°, 60°] is enforced.

Sources: V. Gregers-Hansen and R. Mital, "An Improved Empirical Model for Radar Sea Clutter
Reflectivity", NRL/MR/5310--12-9346, Naval Research Laboratory, 27 April 2012; also IEEE Trans.
AES 48(4):3512-3524, 2012 (model, validity, deviations). Coefficients to the digits of the NRL
implementation of the model (V. Gregers-Hansen, NRL, 2010), which reproduce the published
example value of MATLAB's ``seareflectivity`` (2.1555e-4 at sea state 2, 10°, 30 GHz, H).
H. Katzin, "On the mechanisms of radar sea clutter", Proc. IRE 45(1):44-54,
1957; D. K. Barton, *Radar Equations for Modern Radar*, Artech House 2013, §9.2.
"""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp

from diffsense.numerics.checks import check_choice, check_range
from diffsense.numerics.db import db10, from_db10
from diffsense.physics.clutter import sea_clutter_gamma_db
from diffsense.physics.constants import SPEED_OF_LIGHT_M_S
from diffsense.physics.sea_state import beaufort_from_sea_state

__all__ = [
    "SEA_CLUTTER_MODELS",
    "NRL_COEFFICIENTS",
    "NRL_FREQ_RANGE_HZ",
    "NRL_GRAZING_RANGE_RAD",
    "CONSTANT_GAMMA_GRAZING_RANGE_RAD",
    "nrl_sea_clutter_sigma0_db",
    "sea_clutter_sigma0_db",
    "sea_clutter_sigma0",
]

#: Sea-clutter reflectivity models of :func:`sea_clutter_sigma0`.
SEA_CLUTTER_MODELS = ("nrl", "constant_gamma")
#: NRL model coefficients (c1, c2, c3, c4, c5) by polarization (Gregers-Hansen & Mital 2012).
NRL_COEFFICIENTS = {
    "horizontal": (-73.0, 20.781, 7.351, 25.65, 0.0054),
    "vertical": (-50.796, 25.93, 0.7093, 21.588, 0.00211),
}
#: Frequencies (Hz), grazing angles (rad) and sea states of the NRL model's data.
NRL_FREQ_RANGE_HZ = (0.5e9, 35e9)
NRL_GRAZING_RANGE_RAD = (math.radians(0.1), math.radians(60.0))
NRL_SEA_STATE_RANGE = (0.0, 6.0)
#: Plateau region where the constant-γ model holds (book §8.12).
CONSTANT_GAMMA_GRAZING_RANGE_RAD = (math.radians(1.0), math.radians(60.0))

_PSI0_DEG = 0.1
_PSI4_SLOPE_DB_PER_NEPER = 40.0 / math.log(10.0)
_POLARIZATIONS = tuple(NRL_COEFFICIENTS)
_WHERE = "sea clutter"


def _nrl_db(freq_ghz, sea_state, psi_deg, coefficients):
    c1, c2, c3, c4, c5 = coefficients
    return (c1 + c2 * jnp.log10(jnp.sin(jnp.deg2rad(psi_deg)))
            + (27.5 + c3 * psi_deg) * jnp.log10(freq_ghz) / (1.0 + 0.95 * psi_deg)
            + c4 * (1.0 + sea_state) ** (1.0 / (2.0 + 0.085 * psi_deg + 0.033 * sea_state))
            + c5 * psi_deg**2)


def _check_nrl_inputs(freq_hz, sea_state, polarization):
    check_choice("polarization", polarization, _POLARIZATIONS, where=_WHERE)
    check_range("freq_hz", freq_hz, *NRL_FREQ_RANGE_HZ, where=f"{_WHERE}, NRL model")
    check_range("sea_state", sea_state, *NRL_SEA_STATE_RANGE, where=f"{_WHERE}, NRL model")


def nrl_sea_clutter_sigma0_db(freq_hz, sea_state, grazing_rad, polarization="horizontal"):
    """The NRL sea-clutter reflectivity σ° (dB re 1 m²/m²) inside its fitted domain.

    Formula and coefficients in the module docstring.

    Args:
        freq_hz: radar frequency f (Hz), in [0.5e9, 35e9].
        sea_state: sea state SS (continuous), in [0, 6].
        grazing_rad: grazing angle ψ (rad), in [0.1°, 60°].
        polarization: ``"horizontal"`` or ``"vertical"`` (static).

    Average absolute deviation from the measured data 2.2-2.6 dB (Gregers-Hansen & Mital 2012).
    MATLAB's documented example of ``seareflectivity`` (NRL model, sea state 2, 10°, 30 GHz,
    horizontal) prints 2.1555e-04:

    >>> import math
    >>> 10 ** (float(nrl_sea_clutter_sigma0_db(30e9, 2.0, math.radians(10.0))) / 10)
    0.00021555
    """
    _check_nrl_inputs(freq_hz, sea_state, polarization)
    check_range("grazing_rad", grazing_rad, *NRL_GRAZING_RANGE_RAD, where=f"{_WHERE}, NRL model")
    psi_deg = jnp.rad2deg(jnp.asarray(grazing_rad, dtype=float))
    return _nrl_db(jnp.asarray(freq_hz, dtype=float) / 1e9, jnp.asarray(sea_state, dtype=float), psi_deg,
                   NRL_COEFFICIENTS[polarization])


def _nrl_extended_db(freq_ghz, sea_state, psi_deg, coefficients):
    """NRL above 0.1°, its C¹ continuation towards σ° ∝ ψ⁴ below (module docstring)."""
    at_psi0 = lambda p: _nrl_db(freq_ghz, sea_state, p, coefficients)
    l0, dl_dpsi = jax.jvp(at_psi0, (jnp.full_like(freq_ghz * sea_state, _PSI0_DEG),),
                          (jnp.ones_like(freq_ghz * sea_state),))
    s0 = _PSI0_DEG * dl_dpsi  # dL/d ln ψ at 0.1°
    low = psi_deg < _PSI0_DEG
    u = jnp.log(jnp.where(low, psi_deg, _PSI0_DEG) / _PSI0_DEG)
    below = l0 + _PSI4_SLOPE_DB_PER_NEPER * u - (_PSI4_SLOPE_DB_PER_NEPER - s0) * jnp.expm1(u)
    above = _nrl_db(freq_ghz, sea_state, jnp.where(low, _PSI0_DEG, psi_deg), coefficients)
    return jnp.where(low, below, above)


def sea_clutter_sigma0_db(grazing_rad, freq_hz, sea_state, model="nrl", polarization="horizontal"):
    """Sea-clutter reflectivity σ° (dB re 1 m²/m²) of model ``"nrl"`` (with its ψ⁴ continuation
    below 0.1°) or ``"constant_gamma"`` (module docstring).

    Args:
        grazing_rad: grazing angle ψ (rad): (0, 60°] for ``"nrl"``, [1°, 60°] for
            ``"constant_gamma"``.
        freq_hz: radar frequency (Hz): [0.5e9, 35e9] for ``"nrl"``; λ = c/f in [1 mm, 1 m] for
            ``"constant_gamma"``.
        sea_state: sea state (continuous): [0, 6] for ``"nrl"``, (0, 6] for ``"constant_gamma"``
            (book Table 12.2).
        model: ``"nrl"`` or ``"constant_gamma"`` (static).
        polarization: ``"horizontal"`` or ``"vertical"`` (static; NRL only, Barton's γ is
            polarization-free).

    Smooth in every continuous argument (C¹ at 0.1° for ``"nrl"``). The constant-γ model at
    30°, sea state 3 (Beaufort force from the book's Table 12.2), against γ sin ψ:

    >>> import math
    >>> from diffsense.physics.sea_state import beaufort_from_sea_state
    >>> kb = float(beaufort_from_sea_state(3.0))
    >>> g = 6 * kb - 10 * math.log10(0.03) - 64 + 10 * math.log10(0.5)
    >>> float(sea_clutter_sigma0_db(math.radians(30.0), 299792458.0 / 0.03, 3.0, "constant_gamma")), g
    (-25.3797, -25.3797)
    """
    check_choice("model", model, SEA_CLUTTER_MODELS, where=_WHERE)
    psi = jnp.asarray(grazing_rad, dtype=float)
    if model == "constant_gamma":
        check_range("grazing_rad", grazing_rad, *CONSTANT_GAMMA_GRAZING_RANGE_RAD,
                    where=f"{_WHERE}, constant-gamma model (plateau region)")
        check_range("freq_hz", freq_hz, 0.0, None, lo_open=True, where=_WHERE)
        lam = SPEED_OF_LIGHT_M_S / jnp.asarray(freq_hz, dtype=float)
        gamma_db = sea_clutter_gamma_db(beaufort_from_sea_state(sea_state), lam)
        return gamma_db + db10(jnp.sin(psi))
    _check_nrl_inputs(freq_hz, sea_state, polarization)
    check_range("grazing_rad", grazing_rad, 0.0, NRL_GRAZING_RANGE_RAD[1], lo_open=True,
                where=f"{_WHERE}, NRL model (with its continuation below 0.1 deg)")
    f_ghz = jnp.asarray(freq_hz, dtype=float) / 1e9
    ss = jnp.asarray(sea_state, dtype=float)
    f_ghz, ss, psi = jnp.broadcast_arrays(f_ghz, ss, psi)
    return _nrl_extended_db(f_ghz, ss, jnp.rad2deg(psi), NRL_COEFFICIENTS[polarization])


def sea_clutter_sigma0(grazing_rad, freq_hz, sea_state, model="nrl", polarization="horizontal"):
    """:func:`sea_clutter_sigma0_db` as a linear reflectivity σ° (m²/m²)."""
    return from_db10(sea_clutter_sigma0_db(grazing_rad, freq_hz, sea_state, model, polarization))
