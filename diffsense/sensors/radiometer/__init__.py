"""Passive millimetre-wave radiometer: radiative transfer in brightness temperature
(:mod:`.brightness`), the antenna beam (:mod:`.antenna`), sensitivity and detection
(:mod:`.sensitivity`) and the ``"radiometer"`` chain (:mod:`.chain`)."""

from diffsense.sensors.radiometer import antenna, brightness, sensitivity
from diffsense.sensors.radiometer.antenna import *  # noqa: F403 (names in each module's __all__)
from diffsense.sensors.radiometer.brightness import *  # noqa: F403
from diffsense.sensors.radiometer.chain import RadiometerChain
from diffsense.sensors.radiometer.sensitivity import *  # noqa: F403

__all__ = [*brightness.__all__, *antenna.__all__, *sensitivity.__all__, "RadiometerChain"]
