"""Passive infrared point-target detection (IRST): point-target radiometry (:mod:`.radiometry`),
detectors — D*, BLIP, NETD (:mod:`.detector`) — and the ``"infrared"`` chain (:mod:`.chain`).
Blackbody band radiances, also in photon units, are in :mod:`diffsense.physics.radiance`."""

from diffsense.sensors.infrared.chain import InfraredChain
from diffsense.sensors.infrared.detector import (
    NOISE_GAIN,
    background_photon_irradiance,
    blip_detectivity_jones,
    blip_netd_k,
    irst_snr,
    netd_k,
)
from diffsense.sensors.infrared.radiometry import contrast_intensity_w_sr, point_target_irradiance_w_m2

__all__ = [
    "NOISE_GAIN",
    "background_photon_irradiance",
    "blip_detectivity_jones",
    "contrast_intensity_w_sr",
    "point_target_irradiance_w_m2",
    "irst_snr",
    "netd_k",
    "blip_netd_k",
    "InfraredChain",
]
