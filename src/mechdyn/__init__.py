"""mechdyn: dynamic analysis of machines at the design stage.

Subpackages, one per capability: :mod:`mechdyn.mechanism` (planar mechanisms),
:mod:`mechdyn.support` (the machine on its supports), :mod:`mechdyn.drivetrain` (torsional vibration
of geared drivetrains), :mod:`mechdyn.gears` (tooth and mesh stiffness), :mod:`mechdyn.mounts` (mount
stiffness from the drawing). Shared: :mod:`mechdyn.units` (one pint registry), :mod:`mechdyn.io`
(model files), :mod:`mechdyn.results` (the result protocol), :mod:`mechdyn.registry` (the analyses),
:mod:`mechdyn.store` (results database), :mod:`mechdyn.cli`.

Names are imported on first use, so ``import mechdyn`` (and the command line's start-up) stays light.
"""

from importlib.metadata import PackageNotFoundError as _NotInstalled
from importlib.metadata import version as _version
from typing import Any as _Any

from mechdyn.errors import MechdynError, ModelCheckError, ModelError, ModelFileError, ModelWarning

try:
    __version__ = _version("mechdyn")
except _NotInstalled:  # pragma: no cover - running from a source tree without install
    __version__ = "0+unknown"

_SUBPACKAGES = (
    "drivetrain",
    "gears",
    "io",
    "mechanism",
    "mounts",
    "registry",
    "results",
    "store",
    "studies",
    "support",
    "units",
)

__all__ = [
    "Q_",
    "MechdynError",
    "ModelCheckError",
    "ModelError",
    "ModelFileError",
    "ModelWarning",
    "__version__",
    "load",
    "save",
    "ureg",
]


def __getattr__(name: str) -> _Any:
    if name in ("Q_", "ureg"):
        from mechdyn import units

        return getattr(units, name)
    if name == "load":
        from mechdyn.io.modelfile import load

        return load
    if name == "save":
        from mechdyn.io.save import save

        return save
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    """What a user reaches from ``mechdyn.``: the public names and the capabilities' subpackages."""
    return sorted({*__all__, *_SUBPACKAGES})
