"""Propagation models: atmospheric gases, rain, cloud/fog, dust, optical extinction,
refraction, sea multipath, free-space spreading (electromagnetic) and acoustics."""

from diffsense.physics.propagation.cloud import *  # noqa: F401,F403
from diffsense.physics.propagation.dust import *  # noqa: F401,F403
from diffsense.physics.propagation.free_space import *  # noqa: F401,F403
from diffsense.physics.propagation.gas import *  # noqa: F401,F403
from diffsense.physics.propagation.multipath import *  # noqa: F401,F403
from diffsense.physics.propagation.optical import *  # noqa: F401,F403
from diffsense.physics.propagation.rain import *  # noqa: F401,F403
from diffsense.physics.propagation.refraction import *  # noqa: F401,F403
from diffsense.physics.propagation.acoustic import *  # noqa
