"""Ultrasound in air: transducer SPL, transmission loss, receiver voltage, pulse-echo ranging
and the ``"ultrasonic"`` chain (:mod:`.chain`)."""

from diffsense.sensors.ultrasonic.chain import *  # noqa: F401,F403
from diffsense.sensors.ultrasonic.chain import __all__  # noqa: F401
