"""Every table of the results database, in one place, and the schema's version.

The tables are SQLAlchemy declarative classes; the version row lives in ``mechdyn_schema_version``
(Alembic's version table under mechdyn's own name, so that it never meets the ``alembic_version``
table that Optuna keeps in the same database). A new database is created at :data:`SCHEMA_VERSION`;
an older one is brought to it by the migrations in :mod:`mechdyn.store.migrations`
(``mechdyn results upgrade``).

Changing a table means: a new revision under ``migrations/versions`` that makes the change,
:data:`SCHEMA_VERSION` set to it, and a line in the CHANGELOG.
"""

from __future__ import annotations

from datetime import datetime
from typing import Any

from sqlalchemy import (
    JSON,
    DateTime,
    Float,
    ForeignKey,
    Integer,
    LargeBinary,
    String,
    Text,
    UniqueConstraint,
)
from sqlalchemy.orm import DeclarativeBase, Mapped, mapped_column, relationship

__all__ = ["NAME_LENGTH", "SCHEMA_VERSION", "VERSION_TABLE", "Base"]

SCHEMA_VERSION = "0002"
"""The schema this mechdyn writes and reads (an Alembic revision id)."""

VERSION_TABLE = "mechdyn_schema_version"
TABLE_PREFIX = "mechdyn_"
NAME_LENGTH = 256
"""The longest model, study, record or array name the database holds (on every backend)."""


class Base(DeclarativeBase):
    pass


class Run(Base):
    __tablename__ = "mechdyn_runs"
    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True))
    analysis: Mapped[str] = mapped_column(String(64), index=True)
    model_name: Mapped[str] = mapped_column(String(NAME_LENGTH))
    model_path: Mapped[str] = mapped_column(Text)
    model_sha256: Mapped[str] = mapped_column(String(64), index=True)
    model_text: Mapped[str] = mapped_column(Text)
    parameters: Mapped[dict[str, Any]] = mapped_column(JSON)
    scalars: Mapped[dict[str, Any]] = mapped_column(JSON)
    package_version: Mapped[str] = mapped_column(String(64))
    arrays: Mapped[list[Array]] = relationship(back_populates="run", cascade="all, delete-orphan")


class Array(Base):
    __tablename__ = "mechdyn_arrays"
    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    run_id: Mapped[int] = mapped_column(ForeignKey("mechdyn_runs.id", ondelete="CASCADE"), index=True)
    name: Mapped[str] = mapped_column(String(NAME_LENGTH))
    unit: Mapped[str] = mapped_column(String(64))
    data: Mapped[bytes] = mapped_column(LargeBinary)
    run: Mapped[Run] = relationship(back_populates="arrays")


class Record(Base):
    """A named, reusable value with its provenance: a material, a calibrated parameter."""

    __tablename__ = "mechdyn_records"
    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True))
    kind: Mapped[str] = mapped_column(String(64), index=True)
    name: Mapped[str] = mapped_column(String(NAME_LENGTH), index=True)
    data: Mapped[dict[str, Any]] = mapped_column(JSON)
    provenance: Mapped[str] = mapped_column(Text)
    package_version: Mapped[str] = mapped_column(String(64))


class Study(Base):
    __tablename__ = "mechdyn_studies"
    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    name: Mapped[str] = mapped_column(String(NAME_LENGTH), unique=True)
    kind: Mapped[str] = mapped_column(String(32))
    analysis: Mapped[str] = mapped_column(String(64))
    definition: Mapped[dict[str, Any]] = mapped_column(JSON)
    definition_sha256: Mapped[str] = mapped_column(String(64))
    model_path: Mapped[str] = mapped_column(Text)
    model_sha256: Mapped[str] = mapped_column(String(64))
    model_files: Mapped[dict[str, Any]] = mapped_column(JSON)
    columns: Mapped[dict[str, Any]] = mapped_column(JSON)  # parameter and output names, in order
    package_version: Mapped[str] = mapped_column(String(64))
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True))


class Variant(Base):
    __tablename__ = "mechdyn_variants"
    __table_args__ = (UniqueConstraint("study_id", "key", name="uq_mechdyn_variant_key"),)
    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    study_id: Mapped[int] = mapped_column(ForeignKey("mechdyn_studies.id", ondelete="CASCADE"), index=True)
    key: Mapped[str] = mapped_column(String(64))
    position: Mapped[int] = mapped_column(Integer)
    # values in the order of the study's columns (names are stored once, with the study)
    parameters: Mapped[list[Any]] = mapped_column(JSON)
    given: Mapped[list[Any]] = mapped_column(JSON)
    outputs: Mapped[list[Any]] = mapped_column(JSON)
    status: Mapped[str] = mapped_column(String(16), index=True)
    error: Mapped[str | None] = mapped_column(Text, nullable=True)
    objective: Mapped[float | None] = mapped_column(Float, nullable=True)
    model_sha256: Mapped[str] = mapped_column(String(64))
    package_version: Mapped[str] = mapped_column(String(64))
    created_at: Mapped[datetime] = mapped_column(DateTime(timezone=True))
    warnings: Mapped[list[str] | None] = mapped_column(JSON, nullable=True)  # schema 0002


class Curve(Base):
    __tablename__ = "mechdyn_variant_curves"
    __table_args__ = (UniqueConstraint("variant_id", "name", name="uq_mechdyn_curve_name"),)
    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    variant_id: Mapped[int] = mapped_column(ForeignKey("mechdyn_variants.id", ondelete="CASCADE"), index=True)
    name: Mapped[str] = mapped_column(String(NAME_LENGTH))
    unit: Mapped[str] = mapped_column(String(64))
    data: Mapped[bytes] = mapped_column(LargeBinary)
