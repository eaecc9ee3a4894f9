"""Passive infrared point-target detection (IRST): radiometry, detectivity, NETD, range and the
``"infrared"`` chain (:mod:`.chain`)."""

from diffsense.sensors.infrared.chain import *  # noqa: F401,F403
from diffsense.sensors.infrared.chain import __all__  # noqa: F401
