"""Results database (SQLite by default, PostgreSQL or any SQLAlchemy URL), with a versioned schema."""

from mechdyn.store.database import StoreError
from mechdyn.store.schema import SCHEMA_VERSION
from mechdyn.store.store import (
    DEFAULT_DB,
    ENV_VAR,
    ResultStore,
    StoredRecord,
    StoredRun,
    resolve_url,
)

__all__ = [
    "DEFAULT_DB",
    "ENV_VAR",
    "SCHEMA_VERSION",
    "ResultStore",
    "StoreError",
    "StoredRecord",
    "StoredRun",
    "resolve_url",
]
