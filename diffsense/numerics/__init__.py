"""Numerical building blocks that know no physics: domain checks at the API edge
(:mod:`.checks`), decibel conversions (:mod:`.db`) and differentiable root finding
(:mod:`.rootfind`)."""
