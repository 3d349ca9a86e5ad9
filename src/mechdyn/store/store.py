"""The results database: every analysis run with its model, parameters, scalars and arrays.

SQLite by default (``mechdyn.db`` in the working directory, nothing to start); any SQLAlchemy URL
otherwise, e.g. ``postgresql://user@host/db``. The location is, in order: the ``url`` argument (the
CLI's ``--db``), the ``MECHDYN_DB`` environment variable, ``mechdyn.db``.
"""

from __future__ import annotations

import io
import math
import os
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np
from sqlalchemy import (
    JSON,
    DateTime,
    ForeignKey,
    Integer,
    LargeBinary,
    String,
    Text,
    create_engine,
    event,
    select,
    text,
)
from sqlalchemy.engine import make_url
from sqlalchemy.exc import ArgumentError, DatabaseError, OperationalError
from sqlalchemy.orm import DeclarativeBase, Mapped, Session, mapped_column, relationship

from mechdyn.errors import MechdynError

__all__ = ["DEFAULT_DB", "ENV_VAR", "ResultStore", "StoredRecord", "StoredRun", "resolve_url"]

ENV_VAR = "MECHDYN_DB"
_SCHEMA_LOCK = 0x6D656368  # "mech": the advisory lock held while tables are created
DEFAULT_DB = "mechdyn.db"


class StoreError(MechdynError):
    """The results database cannot be opened or does not hold what was asked for."""


class _Base(DeclarativeBase):
    pass


class _Run(_Base):
    __tablename__ = "mechdyn_runs"
    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True))
    analysis: Mapped[str] = mapped_column(String(64), index=True)
    model_name: Mapped[str] = mapped_column(String(256))
    model_path: Mapped[str] = mapped_column(Text)
    model_sha256: Mapped[str] = mapped_column(String(64), index=True)
    model_text: Mapped[str] = mapped_column(Text)
    parameters: Mapped[dict[str, Any]] = mapped_column(JSON)
    scalars: Mapped[dict[str, Any]] = mapped_column(JSON)
    package_version: Mapped[str] = mapped_column(String(64))
    arrays: Mapped[list[_Array]] = relationship(back_populates="run", cascade="all, delete-orphan")


class _Array(_Base):
    __tablename__ = "mechdyn_arrays"
    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    run_id: Mapped[int] = mapped_column(ForeignKey("mechdyn_runs.id", ondelete="CASCADE"), index=True)
    name: Mapped[str] = mapped_column(String(256))
    unit: Mapped[str] = mapped_column(String(64))
    data: Mapped[bytes] = mapped_column(LargeBinary)
    run: Mapped[_Run] = relationship(back_populates="arrays")


class _Record(_Base):
    """A named, reusable value with its provenance: a material, a calibrated parameter."""

    __tablename__ = "mechdyn_records"
    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True))
    kind: Mapped[str] = mapped_column(String(64), index=True)
    name: Mapped[str] = mapped_column(String(256), index=True)
    data: Mapped[dict[str, Any]] = mapped_column(JSON)
    provenance: Mapped[str] = mapped_column(Text)
    package_version: Mapped[str] = mapped_column(String(64))


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


def _sqlite_pragmas(conn: Any, _record: Any) -> None:
    """Write-ahead log: readers (a report, a dashboard) do not block a running study, and a commit
    costs no full sync; a committed transaction survives the process being killed (SQLite's WAL with
    synchronous = NORMAL loses at most the last commits on a power cut, never a process kill)."""
    cur = conn.cursor()
    cur.execute("PRAGMA journal_mode=WAL")
    cur.execute("PRAGMA synchronous=NORMAL")
    cur.close()


def _pack(a: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.save(buf, np.asarray(a), allow_pickle=False)
    return buf.getvalue()


def _unpack(b: bytes) -> np.ndarray:
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

    Parameters
    ----------
    url : str or path, optional
        See :func:`resolve_url`.
    read_only : bool
        Open an existing database for reading only (a dashboard): nothing is created or written.
    """

    def __init__(self, url: str | os.PathLike[str] | None = None, *, read_only: bool = False):
        self.url = resolve_url(url)
        self.read_only = read_only
        if read_only:
            self._open_read_only()
            return
        import mechdyn.store.studies  # noqa: F401  (its tables live in the same database)

        try:
            self._engine = create_engine(self.url)
            if self._engine.dialect.name == "sqlite":
                event.listen(self._engine, "connect", _sqlite_pragmas)
            with self.schema_lock():
                _Base.metadata.create_all(self._engine)
        except (OperationalError, ArgumentError) as exc:
            shown = self.where
            raise StoreError(
                f"cannot open the results database {shown}: {exc.__class__.__name__}: {exc.args[0]}"
            ) from None
        except DatabaseError as exc:  # e.g. a text file given as the SQLite file
            parsed = make_url(self.url)
            shown = (parsed.database or "") if parsed.get_backend_name() == "sqlite" else self.where
            raise StoreError(
                f"{shown} is not a results database ({getattr(exc, 'orig', exc)}); give the path of a "
                "new or existing results database (--db, or MECHDYN_DB)"
            ) from None
        except ModuleNotFoundError as exc:
            raise StoreError(
                f"the database driver for {self.url.split(':')[0]} is not installed ({exc})"
            ) from None

    def _open_read_only(self) -> None:
        """Open for reading only: SQLite by a read-only URI (the file must exist), PostgreSQL with
        read-only transactions; no table is created."""
        url = make_url(self.url)
        if url.get_backend_name() == "sqlite":
            path = url.database or ""
            if not path or not Path(path).is_file():
                raise StoreError(f"no results database at {path!r}; run an analysis or a study first")
            self._engine = create_engine(
                f"sqlite:///file:{path}?mode=ro&uri=true", connect_args={"check_same_thread": False}
            )
        else:
            self._engine = create_engine(
                self.url, connect_args={"options": "-c default_transaction_read_only=on"}
            )
        try:
            with self._engine.connect() as conn:
                conn.execute(text("SELECT 1"))
        except OperationalError as exc:
            raise StoreError(f"cannot open the results database {self.where}: {exc.args[0]}") from None

    @property
    def where(self) -> str:
        """The database's URL as it may be shown (without a password)."""
        return make_url(self.url).render_as_string(hide_password=True)

    @property
    def label(self) -> str:
        """A short name for reports and pages: a SQLite file's name, a server's URL (no password)."""
        url = make_url(self.url)
        if url.get_backend_name() == "sqlite":
            return f"SQLite file {Path(url.database or '').name}"
        return self.where

    @contextmanager
    def schema_lock(self) -> Iterator[None]:
        """Hold the database's schema lock (PostgreSQL: an advisory lock) while tables are created,
        so that processes starting together on one server do not create them twice."""
        if self._engine.dialect.name != "postgresql":
            yield
            return
        with self._engine.connect() as conn:
            conn.execute(text("SELECT pg_advisory_lock(:k)"), {"k": _SCHEMA_LOCK})
            try:
                yield
            finally:
                conn.execute(text("SELECT pg_advisory_unlock(:k)"), {"k": _SCHEMA_LOCK})
                conn.commit()

    def close(self) -> None:
        """Release the database connections (a ``with`` block does it on leaving)."""
        self._engine.dispose()

    def __enter__(self) -> ResultStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

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
            arrays=[_Array(name=k, unit=u, data=_pack(a)) for k, (a, u) in (arrays or {}).items()],
        )
        with Session(self._engine) as s, s.begin():
            s.add(run)
            s.flush()
            return int(run.id)

    def runs(self, *, analysis: str | None = None, limit: int | None = None) -> list[StoredRun]:
        """Recorded runs, newest first, without their arrays.

        Parameters
        ----------
        analysis : str, optional
            Only runs of this analysis.
        limit : int, optional
            At most this many.
        """
        q = select(_Run).order_by(_Run.id.desc())
        if analysis:
            q = q.where(_Run.analysis == analysis)
        if limit:
            q = q.limit(limit)
        with Session(self._engine) as s:
            return [self._summary(r) for r in s.scalars(q)]

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
            arrays = {a.name: (_unpack(a.data), a.unit) for a in r.arrays}
        return StoredRun(**{**base.__dict__, "arrays": arrays})

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
