"""mechdyn: dynamic analysis of machines at the design stage.

Subpackages, one per capability: :mod:`mechdyn.drivetrain` (torsional vibration of geared
drivetrains). Shared: :mod:`mechdyn.units` (one pint registry), :mod:`mechdyn.io` (model files),
:mod:`mechdyn.store` (results database), :mod:`mechdyn.cli`.
"""

from importlib.metadata import PackageNotFoundError, version

from mechdyn.errors import MechdynError, ModelCheckError, ModelError, ModelFileError, ModelWarning
from mechdyn.io import load
from mechdyn.units import Q_, ureg

try:
    __version__ = version("mechdyn")
except PackageNotFoundError:  # pragma: no cover - running from a source tree without install
    __version__ = "0+unknown"

__all__ = [
    "Q_",
    "MechdynError",
    "ModelCheckError",
    "ModelError",
    "ModelFileError",
    "ModelWarning",
    "__version__",
    "load",
    "ureg",
]
