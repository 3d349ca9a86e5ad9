"""Opening a results database safely: the engine, the schema's version, locks and errors.

- **Creating** a database is safe under any number of processes that start together: the check
  and the ``CREATE TABLE`` run in one transaction that holds the database's write lock (SQLite:
  ``BEGIN IMMEDIATE``; PostgreSQL: a transaction-level advisory lock), so the second process
  finds the tables the first one made.
- **The schema's version** is checked at every open: an older database is refused with the command
  that upgrades it, a newer one with the advice to upgrade mechdyn, and a SQLite file that holds
  another application's tables is refused, never written into.
- **Reading** opens SQLite files read-only (``mode=ro``) and PostgreSQL in read-only transactions;
  nothing is created.
- **Errors** of the database library become one line naming the database and the fix
  (:func:`database_errors`).
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from sqlalchemy import Connection, Engine, create_engine, event, inspect, text
from sqlalchemy.engine import make_url
from sqlalchemy.exc import SQLAlchemyError

from mechdyn.errors import MechdynError
from mechdyn.store.schema import SCHEMA_VERSION, TABLE_PREFIX, VERSION_TABLE, Base

__all__ = [
    "StoreError",
    "database_errors",
    "exclusive",
    "file_lock",
    "open_engine",
    "schema_version",
    "upgrade",
]

_LOCK_KEY = 0x6D656368  # "mech": PostgreSQL's advisory lock of mechdyn's schema
SQLITE_BUSY_TIMEOUT = 120.0  # s a writer waits for another one's transaction before it gives up
# tables a mechdyn database may hold besides its own: Optuna's (optimization studies)
_OPTUNA_TABLES = {
    "studies", "version_info", "study_directions", "study_user_attributes", "study_system_attributes",
    "trials", "trial_user_attributes", "trial_system_attributes", "trial_params", "trial_values",
    "trial_intermediate_values", "trial_heartbeats", "alembic_version",
}  # fmt: skip


class StoreError(MechdynError):
    """The results database cannot be opened, read or written, or does not hold what was asked for."""


def is_sqlite(url: str) -> bool:
    return make_url(url).get_backend_name() == "sqlite"


def sqlite_path(url: str) -> str:
    return make_url(url).database or ""


def shown(url: str) -> str:
    """How a database is named in messages: a SQLite file by its path, a server by its URL (no
    password)."""
    return sqlite_path(url) if is_sqlite(url) else make_url(url).render_as_string(hide_password=True)


def _sqlite_on_connect(conn: Any, _record: Any) -> None:
    """A commit costs no full sync in the write-ahead log (SQLite's WAL with synchronous = NORMAL
    loses at most the last commits on a power cut, never a process kill)."""
    conn.execute("PRAGMA synchronous=NORMAL")


def _use_wal(conn: Connection) -> None:
    """Write-ahead log: readers (a report, a dashboard) do not block a running study. The mode is
    kept in the file, so it is set once, when mechdyn creates its tables there (never in a file that
    is not mechdyn's). Changing it answers "locked" at once, without waiting, while another process
    holds the file: it is tried again until it is made, by this process or another."""
    import sqlite3
    import time

    if conn.dialect.name != "sqlite":
        return
    raw = conn.connection.dbapi_connection
    assert raw is not None
    deadline = time.monotonic() + SQLITE_BUSY_TIMEOUT
    while True:
        try:
            if raw.execute("PRAGMA journal_mode").fetchone()[0] != "wal":
                raw.execute("PRAGMA journal_mode=WAL")
            return
        except sqlite3.OperationalError as exc:
            if "locked" not in str(exc) or time.monotonic() > deadline:
                raise
            time.sleep(0.02)


def open_engine(url: str, *, read_only: bool) -> Engine:
    """An engine for the database at ``url``: SQLite with the write-ahead log and a long busy
    timeout (read-only: a ``mode=ro`` URI, so nothing can create or change the file); PostgreSQL in
    read-only transactions when ``read_only``."""
    if is_sqlite(url):
        path = sqlite_path(url)
        if read_only:
            uri = Path(path).resolve().as_uri().replace("file://", "file:", 1)
            return create_engine(
                f"sqlite:///{uri}?mode=ro&uri=true",
                connect_args={"check_same_thread": False, "timeout": SQLITE_BUSY_TIMEOUT},
            )
        engine = create_engine(url, connect_args={"timeout": SQLITE_BUSY_TIMEOUT})
        event.listen(engine, "connect", _sqlite_on_connect)
        return engine
    if read_only:
        return create_engine(url, connect_args={"options": "-c default_transaction_read_only=on"})
    return create_engine(url)


def exclusive(conn: Connection) -> None:
    """Begin the connection's transaction holding the database's schema lock: SQLite's write lock
    (``BEGIN IMMEDIATE``), PostgreSQL's advisory lock (until the transaction ends). Another process
    asking for it waits."""
    if conn.dialect.name == "sqlite":
        conn.exec_driver_sql("BEGIN IMMEDIATE")
    elif conn.dialect.name == "postgresql":
        conn.execute(text("SELECT pg_advisory_xact_lock(:k)"), {"k": _LOCK_KEY})


@contextmanager
def file_lock(url: str, engine: Engine) -> Iterator[None]:
    """Hold an exclusive lock beside SQLite's own (``flock`` on the database file, which SQLite's
    byte-range locks do not see) or PostgreSQL's advisory lock, while a library creates its own
    tables in connections of its own (Optuna's storage)."""
    if is_sqlite(url):
        try:
            import fcntl
        except ImportError:  # no flock (Windows): Optuna's own checks are all there is
            yield
            return
        with open(sqlite_path(url), "rb") as f:
            fcntl.flock(f, fcntl.LOCK_EX)
            try:
                yield
            finally:
                fcntl.flock(f, fcntl.LOCK_UN)
        return
    with engine.connect() as conn:
        conn.execute(text("SELECT pg_advisory_lock(:k)"), {"k": _LOCK_KEY})
        try:
            yield
        finally:
            conn.execute(text("SELECT pg_advisory_unlock(:k)"), {"k": _LOCK_KEY})
            conn.commit()


def schema_version(conn: Connection) -> str | None:
    """The version row of the database, or None when it has none (new, older than versions, or not
    mechdyn's)."""
    if not inspect(conn).has_table(VERSION_TABLE):
        return None
    return conn.execute(text(f"SELECT version_num FROM {VERSION_TABLE}")).scalar()


def _known_revisions() -> list[str]:
    folder = Path(__file__).with_name("migrations") / "versions"
    return sorted(m.group(1) for f in folder.glob("*.py") if (m := re.match(r"(\d{4})_", f.name)))


def _check(conn: Connection, url: str, *, writing: bool) -> bool:
    """Check the database's schema; True when it has none yet and may be created here."""
    tables = set(inspect(conn).get_table_names())  # one look: another process may be creating them
    version = (
        conn.execute(text(f"SELECT version_num FROM {VERSION_TABLE}")).scalar()
        if VERSION_TABLE in tables
        else None
    )
    if version == SCHEMA_VERSION:
        return False
    where = shown(url)
    if version is None:
        ours = {t for t in tables if t.startswith(TABLE_PREFIX)}
        if ours:
            raise StoreError(
                f"{where} was written by an older mechdyn (before schema versions); upgrade it with "
                f"`mechdyn results upgrade --db {where}` (back it up first)"
            )
        foreign = tables - _OPTUNA_TABLES
        if foreign and conn.dialect.name == "sqlite":
            raise StoreError(
                f"{where} is another application's database (tables {', '.join(sorted(foreign)[:4])}"
                f"{', …' if len(foreign) > 4 else ''}), not a mechdyn results database; give the path "
                "of a new or existing results database (--db, or MECHDYN_DB)"
            )
        if not writing:
            raise StoreError(
                f"{where} holds no mechdyn results yet; run an analysis or a study into it first"
            )
        return True
    if version in _known_revisions():
        raise StoreError(
            f"{where} has schema {version}, older than this mechdyn's {SCHEMA_VERSION}; upgrade it with "
            f"`mechdyn results upgrade --db {where}` (back it up first)"
        )
    raise StoreError(
        f"{where} has schema {version}, written by a newer mechdyn than this one (schema "
        f"{SCHEMA_VERSION}); upgrade mechdyn (pip install -U mechdyn) to read it"
    )


def _intact(conn: Connection, url: str) -> None:
    """Refuse a damaged SQLite file before anything is computed for it: SQLite itself goes on
    appending to a file with a broken page, and only a later read fails (``PRAGMA quick_check``
    reads every page once: about a second per few hundred MB)."""
    if conn.dialect.name != "sqlite":
        return
    found = conn.exec_driver_sql("PRAGMA quick_check(1)").scalar()
    if found != "ok":
        first = str(found).replace("*** in database main ***", "").strip().splitlines()[0]
        raise StoreError(
            f"the results database {shown(url)} is damaged ({first}); restore it from a copy, or "
            f"recover what it holds with `sqlite3 {shown(url)} .recover | sqlite3 NEW.db`, or give "
            "another --db"
        )


def ensure_schema(engine: Engine, url: str, *, read_only: bool) -> None:
    """Check the schema and, writing, create it where the database has none: the check is made
    again under the schema lock, so processes that open a new database together create it once."""
    with engine.connect() as conn:
        if not _check(conn, url, writing=not read_only):
            if not read_only:
                _intact(conn, url)
            return
    with engine.connect() as conn:
        _use_wal(conn)
        conn.rollback()
        exclusive(conn)
        if _check(conn, url, writing=True):
            Base.metadata.create_all(conn)
            conn.execute(text(f"CREATE TABLE {VERSION_TABLE} (version_num VARCHAR(32) NOT NULL PRIMARY KEY)"))
            conn.execute(
                text(f"INSERT INTO {VERSION_TABLE} (version_num) VALUES (:v)"), {"v": SCHEMA_VERSION}
            )
        conn.commit()


def upgrade(engine: Engine, url: str) -> tuple[str | None, str]:
    """Bring the database's schema to this mechdyn's (Alembic, under the schema lock).

    Returns
    -------
    (str or None, str)
        The version before (None: a database older than schema versions) and after.
    """
    from alembic import command
    from alembic.config import Config

    with engine.connect() as conn:
        exclusive(conn)
        before = schema_version(conn)
        if before is None and not any(t.startswith(TABLE_PREFIX) for t in inspect(conn).get_table_names()):
            raise StoreError(f"{shown(url)} holds no mechdyn results database to upgrade")
        if before is not None and before not in _known_revisions():
            _check(conn, url, writing=True)  # raises: newer than this mechdyn
        cfg = Config()
        cfg.set_main_option("script_location", str(Path(__file__).with_name("migrations")))
        cfg.attributes["connection"] = conn
        command.upgrade(cfg, "head")
        conn.commit()
    return before, SCHEMA_VERSION


# one-line advice for the database errors a user can do something about
_ADVICE = (
    (r"database or disk is full|No space left|DiskFull", "the disk is full: free some space and run again"),
    (r"readonly database|read-only|ReadOnly", "it cannot be written here: give a writable --db"),
    (r"database is locked|lock timeout", "another process holds it too long: try again when it is done"),
    (
        r"malformed|not a database|file is not a database|DatabaseCorrupt",
        "the file is damaged: restore it from a copy or give another --db",
    ),
    (
        r"Connection refused|server closed|terminating connection|could not connect"
        r"|connection.*(lost|closed)",
        "the server cannot be reached: is it running? try again when it is",
    ),
    (r"no such (table|column)|does not exist|UndefinedColumn|UndefinedTable",
     "its tables are not what this mechdyn expects: `mechdyn results upgrade --db` it, or give another"),
    (r"value too long|StringDataRightTruncation", "a name or value is longer than the database holds"),
)  # fmt: skip


def describe(exc: BaseException, url: str) -> str:
    """One line for a database error: which database, what went wrong, what to do."""
    orig = getattr(exc, "orig", None) or exc
    first = str(orig).strip().splitlines()[0] if str(orig).strip() else type(orig).__name__
    advice = next(
        (a for pat, a in _ADVICE if re.search(pat, f"{type(orig).__name__} {orig}", re.IGNORECASE)),
        "check the database and try again",
    )
    return f"the results database {shown(url)}: {first}; {advice}"


@contextmanager
def database_errors(url: str) -> Iterator[None]:
    """Turn the database library's errors (and the operating system's, for a SQLite file) into a
    :class:`StoreError` of one line that names the database and the fix."""
    try:
        yield
    except StoreError:
        raise
    except (SQLAlchemyError, OSError) as exc:
        raise StoreError(describe(exc, url)) from exc
