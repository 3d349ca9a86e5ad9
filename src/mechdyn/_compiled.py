"""Say so when numba compiles: the kernels are cached on disk, so only the first run pays.

numba writes each compiled kernel into a cache beside its module (or ``NUMBA_CACHE_DIR``); later
processes load it in milliseconds. The first run after installation compiles for 10–25 s, which
without a word looks like a hang: :func:`announce` prints one line on stderr before that.
"""

from __future__ import annotations

import os
import sys
from typing import Any

__all__ = ["announce", "is_cached"]

_ANNOUNCED = False


def is_cached(dispatcher: Any) -> bool:
    """Whether a numba dispatcher has a compiled version in memory or in its on-disk cache."""
    if dispatcher.overloads:
        return True
    cache = getattr(dispatcher, "_cache", None)
    index = getattr(getattr(cache, "_cache_file", None), "_index_path", None)
    return index is not None and os.path.exists(index)


def announce(*dispatchers: Any) -> None:
    """Print "compiling kernels, first run only" once per process when a kernel is not cached yet."""
    global _ANNOUNCED
    if _ANNOUNCED or all(is_cached(d) for d in dispatchers):
        return
    _ANNOUNCED = True
    print("mechdyn: compiling kernels, first run only (cached on disk afterwards) ...", file=sys.stderr)
