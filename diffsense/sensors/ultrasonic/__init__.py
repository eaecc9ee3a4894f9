"""Ultrasound in air: transducer and receiver levels (:mod:`.levels`) and the ``"ultrasonic"``
chain (:mod:`.chain`)."""

from diffsense.sensors.ultrasonic import levels
from diffsense.sensors.ultrasonic.chain import UltrasonicChain
from diffsense.sensors.ultrasonic.levels import *  # noqa: F403 (the names listed in levels.__all__)

__all__ = [*levels.__all__, "UltrasonicChain"]
