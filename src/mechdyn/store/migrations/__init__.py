"""Alembic migrations of the results database (``mechdyn results upgrade``).

Revision ids are the schema versions, numbered in order (``0001``, ``0002``, …). The version row
lives in ``mechdyn_schema_version``; Optuna keeps its own ``alembic_version`` in the same database.
"""
