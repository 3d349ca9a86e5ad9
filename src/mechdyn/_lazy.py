"""Lazy exports for a package ``__init__`` (PEP 562), so that importing a package is cheap.

The command line imports each capability's registration module (``mechdyn.drivetrain.analyses``)
to list and run analyses; with lazy exports that imports the package ``__init__`` without SciPy,
numba or matplotlib, and a name such as ``mechdyn.drivetrain.modal`` loads its module on first use.

Several packages export a function named like the module that defines it (``modal`` in
``modal.py``). Importing such a submodule would make the package attribute the module; the package
keeps the exported function instead, as an eager ``from .modal import modal`` would.
"""

from __future__ import annotations

import importlib
import sys
import types
from collections.abc import Mapping
from typing import Any

__all__ = ["attach"]


class _LazyPackage(types.ModuleType):
    _lazy_exports: Mapping[str, str]

    def __getattr__(self, name: str) -> Any:
        exports = self.__dict__.get("_lazy_exports", {})
        if name in exports:
            where = exports[name]
            module = where if where.startswith("mechdyn.") else f"{self.__name__}.{where}"
            value = getattr(importlib.import_module(module), name)
            self.__dict__[name] = value  # later look-ups find it directly
            return value
        raise AttributeError(f"module {self.__name__!r} has no attribute {name!r}")

    def __setattr__(self, name: str, value: Any) -> None:
        if isinstance(value, types.ModuleType) and name in self.__dict__.get("_lazy_exports", {}):
            return  # the import system binding a submodule over an exported name of its own
        super().__setattr__(name, value)

    def __dir__(self) -> list[str]:
        return sorted({*self.__dict__, *self.__dict__.get("_lazy_exports", {})})


def attach(package: str, exports: Mapping[str, str]) -> list[str]:
    """Make ``package`` export each name from its submodule on first use; returns ``__all__``.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    exports : mapping of str to str
        Each public name and the submodule (relative to ``package``, or an absolute ``mechdyn.``
        module for a name re-exported from the shared core) that defines it.
    """
    module = sys.modules[package]
    module.__class__ = _LazyPackage
    module.__dict__["_lazy_exports"] = dict(exports)
    return sorted(exports)
