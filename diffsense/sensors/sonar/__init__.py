"""Sonar: source level, the sonar equations, detection threshold, side-scan geometry and the
``"sonar"`` chain (:mod:`.chain`)."""

from diffsense.sensors.sonar.chain import *  # noqa: F401,F403
from diffsense.sensors.sonar.chain import __all__  # noqa: F401
