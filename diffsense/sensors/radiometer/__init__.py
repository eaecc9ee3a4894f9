"""Passive millimetre-wave radiometer: brightness temperatures, sensitivity, detection and the
``"radiometer"`` chain (:mod:`.chain`)."""

from diffsense.sensors.radiometer.chain import *  # noqa: F401,F403
from diffsense.sensors.radiometer.chain import __all__  # noqa: F401
