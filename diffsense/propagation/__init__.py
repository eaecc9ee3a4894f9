"""Propagation models: atmospheric gases, rain, cloud/fog, dust, optical extinction,
refraction, sea multipath, free-space spreading (electromagnetic) and acoustics."""

from .cloud import *  # noqa: F401,F403
from .dust import *  # noqa: F401,F403
from .free_space import *  # noqa: F401,F403
from .gas import *  # noqa: F401,F403
from .multipath import *  # noqa: F401,F403
from .optical import *  # noqa: F401,F403
from .rain import *  # noqa: F401,F403
from .refraction import *  # noqa: F401,F403
from .acoustic import *  # noqa
