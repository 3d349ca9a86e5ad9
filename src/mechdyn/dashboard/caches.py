"""What the dashboard keeps between requests, bounded: a least-recently-used map with a limit on its
number of entries and, where its values carry byte payloads (a study's pictures, recomputed curves),
on their bytes too.

A dashboard may serve for weeks over a database that keeps growing (studies added, running studies
adding variants); what it keeps in memory must not grow with it.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Generic, TypeVar

__all__ = ["BoundedCache"]

K = TypeVar("K", bound=Hashable)
V = TypeVar("V")


class BoundedCache(Generic[K, V]):
    """A least-recently-used map of at most ``max_entries`` entries and ``max_bytes`` bytes.

    Parameters
    ----------
    max_entries : int
        Entries kept at most (a count, at least 1); the least recently used one goes first.
    max_bytes : int, optional
        Bytes kept at most over all entries, as ``weigh`` counts them; None: no limit in bytes.
        An entry heavier than this by itself is not kept (its caller still has its value), and
        drops nothing else.
    weigh : callable, optional
        An entry's size in bytes from its value (default: every entry weighs 0 bytes). Asked again
        by :meth:`reweigh`, for a value that fills in later (a future's result).

    Notes
    -----
    Safe to share between threads (the dashboard's handlers run in a thread pool): every operation
    holds one re-entrant lock, ``weigh`` included, so ``weigh`` must be cheap.
    """

    def __init__(
        self, max_entries: int, max_bytes: int | None = None, weigh: Callable[[V], int] | None = None
    ) -> None:
        if max_entries < 1:
            raise ValueError(f"a cache keeps at least one entry, not {max_entries}")
        self.max_entries = max_entries
        self.max_bytes = max_bytes
        self._weigh = weigh
        self._values: OrderedDict[K, V] = OrderedDict()
        self._sizes: dict[K, int] = {}
        self._bytes = 0
        self._lock = threading.RLock()  # re-entrant: a future's done-callback may reweigh at once

    def __len__(self) -> int:
        with self._lock:
            return len(self._values)

    def __contains__(self, key: object) -> bool:
        """Whether ``key`` is kept (without counting as a use)."""
        with self._lock:
            return key in self._values

    @property
    def nbytes(self) -> int:
        """The bytes kept over all entries, as ``weigh`` counts them (bytes)."""
        with self._lock:
            return self._bytes

    def get(self, key: K) -> V | None:
        """The value kept for ``key`` (now the most recently used), else None.

        Parameters
        ----------
        key : hashable
            The entry's key.
        """
        with self._lock:
            if key not in self._values:
                return None
            self._values.move_to_end(key)
            return self._values[key]

    def put(self, key: K, value: V) -> None:
        """Keep ``value`` for ``key`` (replacing any), as the most recently used; then drop the least
        recently used entries until the cache is within its bounds. A value that alone weighs more
        than ``max_bytes`` is not kept (nor is any earlier value for ``key``), and drops nothing else.

        Parameters
        ----------
        key : hashable
            The entry's key.
        value : any
            What to keep.
        """
        with self._lock:
            self._drop(key)
            size = self._size(value)
            if self.max_bytes is not None and size > self.max_bytes:
                return
            self._values[key] = value
            self._sizes[key] = size
            self._bytes += size
            self._shrink()

    def pop(self, key: K) -> None:
        """Forget the entry for ``key``, if kept.

        Parameters
        ----------
        key : hashable
            The entry's key.
        """
        with self._lock:
            self._drop(key)

    def reweigh(self, key: K) -> None:
        """Weigh the entry for ``key`` again (its value filled in since it was kept), then drop the
        least recently used entries until the cache is within its bounds (it alone, if it now weighs
        more than ``max_bytes``); nothing if it is not kept.

        Parameters
        ----------
        key : hashable
            The entry's key.
        """
        with self._lock:
            if key not in self._values:
                return
            size = self._size(self._values[key])
            if self.max_bytes is not None and size > self.max_bytes:
                self._drop(key)
                return
            self._bytes += size - self._sizes[key]
            self._sizes[key] = size
            self._shrink()

    def _size(self, value: V) -> int:
        return int(self._weigh(value)) if self._weigh is not None else 0

    def _drop(self, key: K) -> None:
        if key in self._values:
            del self._values[key]
            self._bytes -= self._sizes.pop(key)

    def _shrink(self) -> None:
        while self._values and (
            len(self._values) > self.max_entries
            or (self.max_bytes is not None and self._bytes > self.max_bytes)
        ):
            self._drop(next(iter(self._values)))
