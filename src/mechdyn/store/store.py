"""The results database: every analysis run with its model, parameters, scalars and arrays.

SQLite by default (``mechdyn.db`` in the working directory, nothing to start); any SQLAlchemy URL
otherwise, e.g. ``postgresql://user@host/db``. The location is, in order: the ``url`` argument (the
CLI's ``--db``), the ``MECHDYN_DB`` environment variable, ``mechdyn.db``.
"""

from __future__ import annotations

import io
import math
import os
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from datetime import UTC, date, datetime, time, timedelta
from functools import wraps
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
from sqlalchemy import func, or_, select
from sqlalchemy.engine import make_url
from sqlalchemy.exc import ArgumentError, DatabaseError
from sqlalchemy.orm import Session

from mechdyn.store import database
from mechdyn.store.database import StoreError, database_errors
from mechdyn.store.schema import NAME_LENGTH
from mechdyn.store.schema import Array as _Array
from mechdyn.store.schema import Record as _Record
from mechdyn.store.schema import Run as _Run

__all__ = [
    "DEFAULT_DB",
    "ENV_VAR",
    "ResultStore",
    "StoreError",
    "StoredRecord",
    "StoredRun",
    "check_name",
    "pack_array",
    "resolve_url",
    "unpack_array",
]

ENV_VAR = "MECHDYN_DB"
DEFAULT_DB = "mechdyn.db"
F = TypeVar("F", bound=Callable[..., Any])


def guarded(method: F) -> F:
    """A store method whose database errors become one line naming the database and the fix."""

    @wraps(method)
    def wrapper(self: Any, *args: Any, **kwargs: Any) -> Any:
        with database_errors(self.url):
            return method(self, *args, **kwargs)

    return wrapper  # type: ignore[return-value]


def check_name(what: str, name: str, where: str = "") -> None:
    """Refuse a name the database cannot hold (on every backend alike), before any work is done.

    Parameters
    ----------
    what : str
        What is named (``"[model] name"``, ``"[study] name"``).
    name : str
        The name.
    where : str
        The file it comes from, for the message.
    """
    if len(name) > NAME_LENGTH:
        raise StoreError(
            f"{where + ': ' if where else ''}{what} is {len(name)} characters long "
            f"({name[:40]!r}…); the results database keeps names of up to {NAME_LENGTH}: shorten it"
        )


@dataclass(frozen=True)
class StoredRecord:
    """A named record as read back: what it is, its data and where it came from.

    Attributes
    ----------
    id : int
        The record's id in the database.
    created_at : datetime
        When it was stored (UTC).
    kind : str
        What it is (``"material"``, ``"calibration"``, …).
    name : str
        Its name within the kind.
    data : dict
        Its content, SI values.
    provenance : str
        Where it came from.
    package_version : str
        The mechdyn version that stored it.
    """

    id: int
    created_at: datetime
    kind: str
    name: str
    data: dict[str, Any]
    provenance: str
    package_version: str


def resolve_url(value: str | os.PathLike[str] | None = None) -> str:
    """The SQLAlchemy URL for a ``--db`` value, the environment, or the default file.

    A value with ``://`` is a URL (``postgresql://`` is given the psycopg 3 driver); anything else
    is the path of a SQLite file.

    Parameters
    ----------
    value : str or path, optional
        A ``--db`` value; default: ``$MECHDYN_DB``, else ``mechdyn.db`` in the working directory.
    """
    raw = os.fspath(value) if value is not None else os.environ.get(ENV_VAR) or DEFAULT_DB
    if "://" not in raw:
        return f"sqlite:///{Path(raw).expanduser().resolve()}"
    try:
        url = make_url(raw)
    except ArgumentError as exc:
        raise StoreError(f"database URL {raw!r} is not valid: {exc}") from None
    if url.drivername in ("postgresql", "postgres"):
        url = url.set(drivername="postgresql+psycopg")
    return url.render_as_string(hide_password=False)


def jsonable(value: Any) -> Any:
    """Plain JSON values (NaN and infinities become None, which every backend stores)."""
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return v if math.isfinite(v) else None
    if isinstance(value, complex):
        return {"re": value.real, "im": value.imag}
    if value is None or isinstance(value, (str, int, bool)):
        return value
    return str(value)


def pack_array(a: np.ndarray) -> bytes:
    """An array as the bytes the database keeps: NumPy's ``.npy`` format, no pickles.

    Parameters
    ----------
    a : ndarray
        Any numeric array (its unit is kept beside it, not in it).
    """
    buf = io.BytesIO()
    np.save(buf, np.asarray(a), allow_pickle=False)
    return buf.getvalue()


def unpack_array(b: bytes) -> np.ndarray:
    """The array back from :func:`pack_array`'s bytes (no pickles are loaded).

    Parameters
    ----------
    b : bytes
        ``.npy`` bytes.
    """
    return np.load(io.BytesIO(b), allow_pickle=False)


@dataclass(frozen=True)
class StoredRun:
    """One recorded run as read back from the database.

    Attributes
    ----------
    id : int
        The run's id.
    created_at : datetime
        When it ran (UTC).
    analysis : str
        The registered analysis.
    model_name, model_path, model_sha256, model_text : str
        The model file: its name, path, SHA-256 and full text.
    parameters : dict
        The analysis' options.
    scalars : dict
        The summary (SI, keys ending with their unit) and the warnings.
    package_version : str
        The mechdyn version that ran it.
    arrays : dict of str to (ndarray, str)
        The result's arrays with their units, bit for bit (empty when listed without them).
    """

    id: int
    created_at: datetime
    analysis: str
    model_name: str
    model_path: str
    model_sha256: str
    model_text: str
    parameters: dict[str, Any]
    scalars: dict[str, Any]
    package_version: str
    arrays: dict[str, tuple[np.ndarray, str]] = field(default_factory=dict)


class ResultStore:
    """A results database (SQLite file or server URL).

    Opening checks the schema's version (:mod:`mechdyn.store.database`): a new database is created
    (safely when several processes start together), an older one is refused with the command that
    upgrades it, a newer one with the advice to upgrade mechdyn, another application's SQLite file
    is refused and left untouched.

    Parameters
    ----------
    url : str or path, optional
        See :func:`resolve_url`.
    read_only : bool
        Open an existing database for reading only (listing, showing, exporting, a dashboard):
        nothing is created or written, and a database that is not there is an error.
    """

    def __init__(self, url: str | os.PathLike[str] | None = None, *, read_only: bool = False):
        self.url = resolve_url(url)
        self.read_only = read_only
        if read_only and database.is_sqlite(self.url):
            path = database.sqlite_path(self.url)
            if not path or not Path(path).is_file():
                raise StoreError(f"no results database at {path!r}; run an analysis or a study first")
        try:
            self._engine = database.open_engine(self.url, read_only=read_only)
            database.ensure_schema(self._engine, self.url, read_only=read_only)
        except StoreError:
            self._dispose()
            raise
        except ModuleNotFoundError as exc:
            raise StoreError(
                f"the database driver for {self.url.split(':')[0]} is not installed ({exc})"
            ) from None
        except ArgumentError as exc:
            raise StoreError(f"cannot open the results database {self.where}: {exc}") from None
        except DatabaseError as exc:
            self._dispose()
            text = str(getattr(exc, "orig", exc))
            if database.is_sqlite(self.url) and "not a database" in text:
                raise StoreError(
                    f"{database.sqlite_path(self.url)} is not a results database ({text}); give the path "
                    "of a new or existing results database (--db, or MECHDYN_DB)"
                ) from None
            raise StoreError(f"cannot open {database.describe(exc, self.url)}") from exc

    def _dispose(self) -> None:
        engine = getattr(self, "_engine", None)
        if engine is not None:
            engine.dispose()

    @classmethod
    def upgrade(cls, url: str | os.PathLike[str] | None = None) -> tuple[str | None, str]:
        """Bring a database written by an older mechdyn to this one's schema (Alembic migrations).

        Parameters
        ----------
        url : str or path, optional
            See :func:`resolve_url`.

        Returns
        -------
        (str or None, str)
            The schema version before (None: older than schema versions) and after.
        """
        resolved = resolve_url(url)
        if database.is_sqlite(resolved) and not Path(database.sqlite_path(resolved)).is_file():
            raise StoreError(f"no results database at {database.sqlite_path(resolved)!r} to upgrade")
        engine = database.open_engine(resolved, read_only=False)
        try:
            with database_errors(resolved):
                return database.upgrade(engine, resolved)
        finally:
            engine.dispose()

    @property
    def engine(self) -> Any:
        """The SQLAlchemy engine (read-only where the store is): for the queries of other parts of
        mechdyn over the same database (a study's variants sorted and paged by the dashboard)."""
        return self._engine

    @property
    def where(self) -> str:
        """The database as it may be shown: a SQLite file's path, a server's URL (no password)."""
        return database.shown(self.url)

    @property
    def label(self) -> str:
        """A short name for reports and pages: a SQLite file's name, a server database's name (never
        its host or user: pages and reports travel)."""
        url = make_url(self.url)
        if url.get_backend_name() == "sqlite":
            return f"SQLite file {Path(url.database or '').name}"
        return f"{url.get_backend_name()} database {url.database or ''}".strip()  # no host, no user

    @contextmanager
    def schema_lock(self) -> Iterator[None]:
        """Hold the database's schema lock while a library creates its own tables through
        connections of its own (Optuna's storage), so that processes starting together on one
        database do not create them twice."""
        with database_errors(self.url), database.file_lock(self.url, self._engine):
            yield

    def close(self) -> None:
        """Release the database connections (a ``with`` block does it on leaving)."""
        self._dispose()

    def __enter__(self) -> ResultStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    @guarded
    def record(
        self,
        *,
        analysis: str,
        model_name: str,
        model_path: str,
        model_text: str,
        model_sha256: str,
        parameters: Mapping[str, Any],
        scalars: Mapping[str, Any],
        arrays: Mapping[str, tuple[np.ndarray, str]] | None = None,
    ) -> int:
        """Store one run in a single transaction and return its id.

        ``arrays`` maps a name to ``(array, unit)``; arrays are kept bit for bit (NumPy ``.npy``).

        Parameters
        ----------
        analysis : str
            The registered analysis.
        model_name, model_path, model_text, model_sha256 : str
            The model file: name, path, full text and its SHA-256.
        parameters : mapping
            The analysis' options.
        scalars : mapping
            The summary (SI, keys ending with their unit) and the warnings.
        arrays : mapping of str to (ndarray, str)
            Named arrays with their units (SI, the unit given beside each).
        """
        from mechdyn import __version__

        run = _Run(
            created_at=datetime.now(UTC),
            analysis=analysis,
            model_name=model_name,
            model_path=model_path,
            model_sha256=model_sha256,
            model_text=model_text,
            parameters=jsonable(parameters),
            scalars=jsonable(scalars),
            package_version=__version__,
            arrays=[_Array(name=k, unit=u, data=pack_array(a)) for k, (a, u) in (arrays or {}).items()],
        )
        with Session(self._engine) as s, s.begin():
            s.add(run)
            s.flush()
            return int(run.id)

    @guarded
    def runs(
        self,
        *,
        analysis: str | None = None,
        model: str | None = None,
        since: date | None = None,
        until: date | None = None,
        limit: int | None = None,
        offset: int = 0,
    ) -> list[StoredRun]:
        """Recorded runs, newest first, without their arrays, filtered in the database query.

        Parameters
        ----------
        analysis : str, optional
            Only runs of this analysis.
        model : str, optional
            Only runs whose model name or file contains this text (any case).
        since, until : datetime.date, optional
            Only runs made on or after ``since`` and on or before ``until`` (UTC days).
        limit : int, optional
            At most this many.
        offset : int
            Skip this many of the newest that match (a page of a long list).
        """
        q = self._matching(select(_Run), analysis, model, since, until).order_by(_Run.id.desc())
        if offset:
            q = q.offset(offset)
        if limit:
            q = q.limit(limit)
        with Session(self._engine) as s:
            return [self._summary(r) for r in s.scalars(q)]

    @guarded
    def count_runs(
        self,
        *,
        analysis: str | None = None,
        model: str | None = None,
        since: date | None = None,
        until: date | None = None,
    ) -> int:
        """How many recorded runs match (the filters of :meth:`runs`).

        Parameters
        ----------
        analysis, model, since, until
            As for :meth:`runs`.
        """
        q = self._matching(select(func.count(_Run.id)), analysis, model, since, until)
        with Session(self._engine) as s:
            return int(s.scalar(q) or 0)

    @staticmethod
    def _matching(q: Any, analysis: str | None, model: str | None, since: Any, until: Any) -> Any:
        """``q`` with the runs filters as SQL conditions."""
        if analysis:
            q = q.where(_Run.analysis == analysis)
        if model:
            text = model.lower()
            q = q.where(
                or_(
                    func.lower(_Run.model_name).contains(text, autoescape=True),
                    func.lower(_Run.model_path).contains(text, autoescape=True),
                )
            )
        if since is not None:
            q = q.where(_Run.created_at >= datetime.combine(since, time.min, tzinfo=UTC))
        if until is not None:
            q = q.where(_Run.created_at < datetime.combine(until + timedelta(days=1), time.min, tzinfo=UTC))
        return q

    @guarded
    def get(self, run_id: int) -> StoredRun:
        """One run with its arrays.

        Parameters
        ----------
        run_id : int
            The run's id (``mechdyn results list``).
        """
        with Session(self._engine) as s:
            r = s.get(_Run, run_id)
            if r is None:
                raise StoreError(
                    f"no run with id {run_id} in {self.where}; `mechdyn results list` shows the ids"
                )
            base = self._summary(r)
            arrays = {a.name: (unpack_array(a.data), a.unit) for a in r.arrays}
        return StoredRun(**{**base.__dict__, "arrays": arrays})

    @guarded
    def put_record(self, kind: str, name: str, data: Mapping[str, Any], provenance: str) -> int:
        """Store a named record (e.g. ``kind="material"`` or ``"calibration"``); returns its id.

        Records are never overwritten: a new one of the same kind and name supersedes the old for
        :meth:`latest_record`, and the history stays.

        Parameters
        ----------
        kind : str
            What it is.
        name : str
            Its name within the kind.
        data : mapping
            Its content, JSON-ready (SI values).
        provenance : str
            Where it came from.
        """
        from mechdyn import __version__

        if not provenance.strip():
            raise StoreError(f"record {kind}/{name}: say where it comes from (provenance is empty)")
        rec = _Record(
            created_at=datetime.now(UTC),
            kind=kind,
            name=name,
            data=jsonable(dict(data)),
            provenance=provenance,
            package_version=__version__,
        )
        with Session(self._engine) as s, s.begin():
            s.add(rec)
            s.flush()
            return int(rec.id)

    @guarded
    def records(self, kind: str, name: str | None = None) -> list[StoredRecord]:
        """Records of a kind (and name), newest first.

        Parameters
        ----------
        kind : str
            The records' kind.
        name : str, optional
            Only those of this name.
        """
        q = select(_Record).where(_Record.kind == kind).order_by(_Record.id.desc())
        if name is not None:
            q = q.where(_Record.name == name)
        with Session(self._engine) as s:
            return [
                StoredRecord(
                    r.id,
                    r.created_at if r.created_at.tzinfo else r.created_at.replace(tzinfo=UTC),
                    r.kind,
                    r.name,
                    dict(r.data),
                    r.provenance,
                    r.package_version,
                )
                for r in s.scalars(q)
            ]

    def latest_record(self, kind: str, name: str) -> StoredRecord:
        """The newest record of a kind and name.

        Parameters
        ----------
        kind : str
            The record's kind.
        name : str
            Its name.
        """
        found = self.records(kind, name)
        if not found:
            raise StoreError(f"no {kind} record named {name!r} in the results database")
        return found[0]

    @staticmethod
    def _summary(r: _Run) -> StoredRun:
        created = r.created_at if r.created_at.tzinfo else r.created_at.replace(tzinfo=UTC)
        return StoredRun(
            r.id,
            created,
            r.analysis,
            r.model_name,
            r.model_path,
            r.model_sha256,
            r.model_text,
            dict(r.parameters or {}),
            dict(r.scalars or {}),
            r.package_version,
        )
