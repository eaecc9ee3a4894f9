"""The sonar chain's scene parts: each is a named sub-program (:func:`diffsense.sensors.parts.scene_part`)
traced only when the scene holds its part.

The relations themselves live in physics: sea-surface and thermal noise in
:mod:`diffsense.physics.sea_noise`, amplifier noise in :mod:`diffsense.physics.noise`,
reverberation and scattering strengths in :mod:`diffsense.physics.clutter` (book eqs (8.47)–(8.48),
§12.8; Urick, *Principles of Underwater Sound*, 1983, ch. 8).
"""

from __future__ import annotations

from diffsense.physics import clutter, noise, sea_noise
from diffsense.sensors.parts import scene_part
from diffsense.sensors.sonar.levels import equivalent_pressure_level_db

__all__ = [
    "sea_noise_spectrum_level_db",
    "thermal_noise_spectrum_level_db",
    "receiver_noise_level_db",
    "surface_reverberation_level_db",
    "surface_chapman_harris_strength_db",
    "bottom_reverberation_level_db",
    "bottom_lambert_strength_db",
    "volume_reverberation_level_db",
]

#: Knudsen sea-surface noise spectrum level, dB re 1 µPa²/Hz (book eq (12.61), Table 12.2).
sea_noise_spectrum_level_db = scene_part("sea_noise")(sea_noise.sea_surface_noise_spectrum_level_db)

#: Mellen's thermal noise of sea water, dB re 1 µPa²/Hz (book eq (9.10)).
thermal_noise_spectrum_level_db = scene_part("thermal_noise")(sea_noise.thermal_sea_noise_spectrum_level_db)

#: Chapman-Harris sea-surface scattering strength, dB.
surface_chapman_harris_strength_db = scene_part("surface_reverberation")(
    clutter.chapman_harris_surface_scattering_strength_db)

#: Lambert's-law bottom scattering strength, dB.
bottom_lambert_strength_db = scene_part("bottom_reverberation")(clutter.lambert_scattering_strength_db)


@scene_part("receiver_noise")
def receiver_noise_level_db(noise_density_v_rthz, bandwidth_hz, receive_sensitivity_db):
    """Amplifier voltage noise e_n √B in the band referred to the water, dB re 1 µPa (book §12.8)."""
    v = noise.voltage_noise_rms_v(noise_density_v_rthz, bandwidth_hz)
    return equivalent_pressure_level_db(v, receive_sensitivity_db)


@scene_part("surface_reverberation")
def surface_reverberation_level_db(sl_db, tl_db, strength_db, range_m, az_rad, tau_s, propagation_speed_m_s):
    """Sea-surface reverberation level, A = (cτ/2) R θ_az (book eq (8.47)), dB re 1 µPa."""
    return clutter.surface_reverberation_level_db(sl_db, tl_db, strength_db, range_m, az_rad, tau_s,
                                                  speed_m_s=propagation_speed_m_s)


@scene_part("bottom_reverberation")
def bottom_reverberation_level_db(sl_db, tl_db, strength_db, range_m, az_rad, tau_s, propagation_speed_m_s):
    """Sea-floor reverberation level, A = (cτ/2) R θ_az (book eq (8.47)), dB re 1 µPa."""
    return clutter.surface_reverberation_level_db(sl_db, tl_db, strength_db, range_m, az_rad, tau_s,
                                                  speed_m_s=propagation_speed_m_s)


@scene_part("volume_reverberation")
def volume_reverberation_level_db(sl_db, tl_db, strength_db, range_m, az_rad, el_rad, tau_s, propagation_speed_m_s):
    """Volume reverberation level, V = (cτ/2) π R² θ_az θ_el / 4 (book eq (8.48)), dB re 1 µPa."""
    return clutter.volume_reverberation_level_db(sl_db, tl_db, strength_db, range_m, az_rad, el_rad, tau_s,
                                                 speed_m_s=propagation_speed_m_s)
