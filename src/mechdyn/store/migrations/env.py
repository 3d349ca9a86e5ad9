"""Alembic's environment for mechdyn's migrations: always run on a connection that
:func:`mechdyn.store.database.upgrade` has opened and locked (no URL of its own, no logging setup)."""

from alembic import context

from mechdyn.store.schema import VERSION_TABLE, Base

connection = context.config.attributes["connection"]
context.configure(
    connection=connection,
    target_metadata=Base.metadata,
    version_table=VERSION_TABLE,
    render_as_batch=True,  # SQLite alters a table by copying it
)
with context.begin_transaction():
    context.run_migrations()
