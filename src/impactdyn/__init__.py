"""impactdyn: impact dynamics for flexible mechanisms and hypervelocity shields.

Subpackages are imported on demand (``import impactdyn.beam``) so that the CLI
and light users do not pay for numba compilation or plotting they do not use.
"""

from impactdyn._errors import InputError, SimulationError
from impactdyn._jitcache import install_on_numba_import

install_on_numba_import()   # cached kernels stamped with the whole package's sources (_jitcache)

__version__ = "0.1.0"

__all__ = ["InputError", "SimulationError", "__version__"]
