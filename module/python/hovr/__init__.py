"""hovr: higher-order volume rendering for VTK.

The wrapped VTK classes of hovr (mappers, tables, the reference integrator, error metrics,
test sources, the gradient exaggeration filter) are importable from here, next to the Python
tools behind ``hovr render`` and ``hovr bench``.
"""

from .hovrRenderingCore import *  # noqa: F401,F403
from .hovrRenderingOpenGL import *  # noqa: F401,F403
from .hovrFiltersSources import *  # noqa: F401,F403
from .hovrFiltersImaging import *  # noqa: F401,F403

__version__ = "0.1.0"
