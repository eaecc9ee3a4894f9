"""Radar: the range equation and its relations (:mod:`diffsense.sensors.radar.equation`) and the
registered radar chain, kind ``"radar"`` (:mod:`diffsense.sensors.radar.chain`).

The package, in the order data flows:

* :mod:`.equation` — the radar range equation, clutter, jamming, multipath and detection-range
  relations (pure functions);
* :mod:`.structure` — the parts and options of a radar scene;
* :mod:`.parts` — the scene parts as named sub-programs of a traced evaluation;
* :mod:`.parameters` — the chain's parameter and output tables;
* the chain's stages: :mod:`.link_budget`, :mod:`.interference`, :mod:`.detectability`,
  :mod:`.tracking`;
* :mod:`.chain` — :class:`RadarChain`, which wires the stages.

Public contract: :func:`snr_db` (single-pulse SNR, energy form of the radar equation).
"""

from diffsense.sensors.radar.equation import *  # noqa: F401,F403
from diffsense.sensors.radar.equation import __all__ as _equation_all
from diffsense.sensors.radar.chain import ATTENUATION_PARTS, CLUTTER_PARTS, OPTIONS, PARTS, RadarChain

__all__ = list(_equation_all) + ["RadarChain", "PARTS", "OPTIONS", "ATTENUATION_PARTS", "CLUTTER_PARTS"]
