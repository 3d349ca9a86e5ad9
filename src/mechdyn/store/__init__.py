"""Results database (SQLite by default, PostgreSQL or any SQLAlchemy URL)."""

from mechdyn.store.store import (
    DEFAULT_DB,
    ENV_VAR,
    ResultStore,
    StoredRecord,
    StoredRun,
    StoreError,
    resolve_url,
)

__all__ = ["DEFAULT_DB", "ENV_VAR", "ResultStore", "StoreError", "StoredRecord", "StoredRun", "resolve_url"]
