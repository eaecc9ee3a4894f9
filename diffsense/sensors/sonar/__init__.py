"""Sonar: source levels (:mod:`.levels`), the sonar equations (:mod:`.equations`), detection
thresholds (:mod:`.threshold`), the scene parts (:mod:`.parts`) and the ``"sonar"`` chain
(:mod:`.chain`)."""

from diffsense.sensors.sonar import equations, levels, threshold
from diffsense.sensors.sonar.chain import SonarChain
from diffsense.sensors.sonar.equations import *  # noqa: F403 (names in each module's __all__)
from diffsense.sensors.sonar.levels import *  # noqa: F403
from diffsense.sensors.sonar.threshold import *  # noqa: F403

__all__ = [*levels.__all__, *equations.__all__, *threshold.__all__, "SonarChain"]
