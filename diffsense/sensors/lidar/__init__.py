"""Lidar / laser rangefinder: laser range equation, optical receivers, pulse-detection
statistics and the ``"lidar"`` sensor chain.

* :mod:`.range_equation` — extended and point Lambertian targets, cross-over, beam footprint,
  solar background, photon energy, ASTM G173 solar irradiance at laser wavelengths.
* :mod:`.receiver` — PIN/APD direct detection (SNR, noise, NEP, optimum APD gain),
  heterodyne detection, single-pole pulse response.
* :mod:`.statistics` — threshold detection of a steady pulse in Gaussian noise.
* :mod:`.chain` — :class:`LidarChain`, registered as ``Scene("lidar", ...)``.
"""

from diffsense.sensors.lidar.range_equation import *  # noqa: F401,F403
from diffsense.sensors.lidar.receiver import *  # noqa: F401,F403
from diffsense.sensors.lidar.statistics import *  # noqa: F401,F403
from diffsense.sensors.lidar.chain import *  # noqa: F401,F403
