"""Design studies in the results database (the tables of :mod:`mechdyn.store.schema`): each study,
every variant it evaluated, their curves.

A variant is stored once: its key (a hash of its parameter values, or an optimizer's trial number)
is unique within its study, and a block of variants is written in one transaction, so a study
killed at any moment keeps every block it finished and a second run reuses them. The same tables
live in SQLite and PostgreSQL.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from types import SimpleNamespace
from typing import Any

import numpy as np
from sqlalchemy import delete, func, inspect, select
from sqlalchemy.dialects.postgresql import insert as pg_insert
from sqlalchemy.dialects.sqlite import insert as sqlite_insert
from sqlalchemy.orm import Session

from mechdyn.store.schema import Curve as _Curve
from mechdyn.store.schema import Study as _Study
from mechdyn.store.schema import Variant as _Variant
from mechdyn.store.store import (
    ResultStore,
    StoreError,
    check_name,
    guarded,
    jsonable,
    pack_array,
    unpack_array,
)

__all__ = ["StoredStudy", "StoredVariant", "StudyStore", "import_unsaved", "optuna_name", "variant_key"]


def optuna_name(study: str) -> str:
    """The name of an optimization study's Optuna study (its trials), in the same database."""
    return f"mechdyn:{study}"


def variant_key(values: Sequence[float] | np.ndarray) -> str:
    """The key of a variant: a hash of its parameter values (SI, exactly as evaluated)."""
    return hashlib.sha256(json.dumps([float(v).hex() for v in values]).encode()).hexdigest()[:40]


@dataclass(frozen=True)
class StoredStudy:
    """A study as stored: its definition and the model it varies."""

    id: int
    name: str
    kind: str
    analysis: str
    definition: dict[str, Any]
    model_path: str
    model_sha256: str
    model_files: dict[str, str]
    package_version: str
    created_at: datetime
    parameter_names: tuple[str, ...] = ()
    output_names: tuple[str, ...] = ()


@dataclass(frozen=True)
class StoredVariant:
    """A variant as stored: parameters (SI and as given), outputs (SI), status and error."""

    id: int
    study: str
    key: str
    position: int
    parameters: dict[str, float]
    given: dict[str, str]
    outputs: dict[str, float | None]
    status: str
    error: str | None
    objective: float | None
    model_sha256: str
    package_version: str
    created_at: datetime
    curves: dict[str, tuple[np.ndarray, str]] = field(default_factory=dict)
    warnings: tuple[str, ...] = ()

    def describe(self) -> dict[str, Any]:
        """JSON-ready: ``id``, ``status``, ``parameters`` in SI, ``outputs`` in SI, and the rest."""
        return {
            "id": self.id,
            "study": self.study,
            "position": self.position,
            "status": self.status,
            "error": self.error,
            "parameters": self.parameters,
            "given": self.given,
            "outputs": self.outputs,
            "objective": self.objective,
            "model_sha256": self.model_sha256,
            "package_version": self.package_version,
            "created_at": self.created_at.isoformat(),
            "warnings": list(self.warnings),
            "curves": sorted(self.curves),
        }


def _flat(d: Mapping[str, Any], names: Sequence[str]) -> list[Any]:
    """The values of a mapping in the order of ``names``, as JSON values (floats, text, None: the
    common case, fast; anything else through :func:`jsonable`)."""
    out: list[Any] = []
    for k in names:
        v = d.get(k)
        if type(v) is float:
            out.append(v if math.isfinite(v) else None)
        elif v is None or type(v) is str:
            out.append(v)
        else:
            out.append(jsonable(v))
    return out


def _utc(t: datetime) -> datetime:
    return t if t.tzinfo else t.replace(tzinfo=UTC)


_VARIANT_COLUMNS = (
    "id",
    "study_id",
    "key",
    "position",
    "parameters",
    "given",
    "outputs",
    "status",
    "error",
    "objective",
    "model_sha256",
    "package_version",
    "created_at",
    "warnings",
)  # what a StoredVariant is made of


class StudyStore:
    """The studies of a results database.

    Parameters
    ----------
    store : ResultStore
        The database (SQLite file or server URL).
    """

    def __init__(self, store: ResultStore):
        self.store = store
        self._engine = store._engine
        self._names: dict[int, tuple[str, tuple[str, ...], tuple[str, ...]]] = {}

    # -- studies ------------------------------------------------------------------------------
    def open(
        self,
        name: str,
        *,
        kind: str,
        analysis: str,
        definition: Mapping[str, Any],
        model_path: str,
        model_sha256: str,
        model_files: Mapping[str, str],
        parameters: Sequence[str],
        outputs: Sequence[str],
    ) -> tuple[StoredStudy, bool]:
        """The study called ``name``: created, or found (then its definition and model must match).

        Returns
        -------
        (StoredStudy, bool)
            The study and whether it already existed (a resumed study).

        Raises
        ------
        StoreError
            When a study of that name exists with another definition or model.
        """
        from mechdyn import __version__

        check_name("the study's name", name)
        plain = jsonable(dict(definition))
        digest = hashlib.sha256(json.dumps(plain, sort_keys=True).encode()).hexdigest()
        row = {
            "name": name,
            "kind": kind,
            "analysis": analysis,
            "definition": plain,
            "definition_sha256": digest,
            "model_path": model_path,
            "model_sha256": model_sha256,
            "model_files": dict(model_files),
            "columns": {"parameters": list(parameters), "outputs": list(outputs)},
            "package_version": __version__,
            "created_at": datetime.now(UTC),
        }
        # insert-or-read: processes that open one new study together create it once, and each
        # learns whether it was there before
        stmt = (
            self._insert(_Study.__table__)
            .values(**row)
            .on_conflict_do_nothing(index_elements=["name"])
            .returning(_Study.__table__.c.id)
        )
        with Session(self._engine) as s, s.begin():
            created = s.execute(stmt).scalar()
            found = s.scalars(select(_Study).where(_Study.name == name)).one()
            if created is None and (found.definition_sha256 != digest or found.model_sha256 != model_sha256):
                what = "definition" if found.definition_sha256 != digest else "model files"
                raise StoreError(
                    f"a study named {name!r} is already stored with other {what} "
                    f"({self.where}); give this one another name ([study] name), or remove the "
                    f"old one with `mechdyn results delete --study {name}`"
                )
            return self._study(found), created is None

    @guarded
    def study(self, name: str) -> StoredStudy:
        with Session(self._engine) as s:
            row = s.scalars(select(_Study).where(_Study.name == name)).first()
            if row is None:
                known = [r for (r,) in s.execute(select(_Study.name).order_by(_Study.id))]
                raise StoreError(
                    f"no study named {name!r} in {self.where}; stored: {', '.join(known) or 'none'}"
                )
            return self._study(row)

    @guarded
    def study_by_id(self, study_id: int) -> StoredStudy | None:
        """The study with this id, or None."""
        with Session(self._engine) as s:
            row = s.get(_Study, study_id)
            return None if row is None else self._study(row)

    @guarded
    def counts(self, study_id: int) -> dict[str, int]:
        """How many variants a study holds, and how many of them failed."""
        with Session(self._engine) as s:
            q = (
                select(_Variant.status, func.count())
                .where(_Variant.study_id == study_id)
                .group_by(_Variant.status)
            )
            by = dict(s.execute(q).all())
        return {"variants": int(sum(by.values())), "failed": int(sum(n for k, n in by.items() if k != "ok"))}

    @guarded
    def studies(self) -> list[StoredStudy]:
        with Session(self._engine) as s:
            return [self._study(r) for r in s.scalars(select(_Study).order_by(_Study.id))]

    @guarded
    def delete(self, name: str) -> int:
        """Remove a study with all of it: its variants, their curves and, for an optimization, its
        Optuna trials; returns how many variants went."""
        study = self.study(name)
        with Session(self._engine) as s, s.begin():
            ids = [v for (v,) in s.execute(select(_Variant.id).where(_Variant.study_id == study.id))]
            for i in range(0, len(ids), 500):
                s.execute(delete(_Curve).where(_Curve.variant_id.in_(ids[i : i + 500])))
            s.execute(delete(_Variant).where(_Variant.study_id == study.id))
            s.execute(delete(_Study).where(_Study.id == study.id))
        if study.kind == "optimize":
            self._delete_trials(name)
        self._names.pop(study.id, None)
        return len(ids)

    def _delete_trials(self, name: str) -> None:
        import optuna

        if not inspect(self._engine).has_table("studies"):  # no optimization ever ran here
            return
        storage = optuna.storages.RDBStorage(self.store.url, skip_table_creation=True)
        try:
            optuna.delete_study(study_name=optuna_name(name), storage=storage)
        except KeyError:  # never asked a trial
            pass
        finally:
            storage.remove_session()
            storage.engine.dispose()

    @property
    def where(self) -> str:
        return self.store.where

    @property
    def url(self) -> str:
        return self.store.url

    @staticmethod
    def _study(r: _Study) -> StoredStudy:
        return StoredStudy(
            r.id,
            r.name,
            r.kind,
            r.analysis,
            dict(r.definition),
            r.model_path,
            r.model_sha256,
            dict(r.model_files),
            r.package_version,
            _utc(r.created_at),
            tuple(r.columns["parameters"]),
            tuple(r.columns["outputs"]),
        )

    # -- variants -----------------------------------------------------------------------------
    @guarded
    def stored(self, study_id: int) -> dict[str, StoredVariant]:
        """Every stored variant of a study by key (without curves)."""
        with Session(self._engine) as s:
            rows = s.scalars(select(_Variant).where(_Variant.study_id == study_id).order_by(_Variant.id))
            return {r.key: self._variant(r) for r in rows}

    @guarded
    def by_ids(self, ids: Sequence[int]) -> list[StoredVariant]:
        """Stored variants by id, in the order given (without curves)."""
        found: dict[int, StoredVariant] = {}
        with Session(self._engine) as s:
            for i in range(0, len(ids), 500):
                for r in s.scalars(select(_Variant).where(_Variant.id.in_(ids[i : i + 500]))):
                    found[r.id] = self._variant(r)
        return [found[i] for i in ids if i in found]

    @guarded
    def ids(self, study_id: int, keys: Sequence[str]) -> dict[str, int]:
        """The ids of a study's stored variants with these keys."""
        out: dict[str, int] = {}
        with Session(self._engine) as s:
            for i in range(0, len(keys), 500):
                q = select(_Variant.key, _Variant.id).where(
                    _Variant.study_id == study_id, _Variant.key.in_(keys[i : i + 500])
                )
                out.update(dict(s.execute(q).all()))
        return out

    @guarded
    def next_position(self, study_id: int) -> int:
        """The place of a variant added after every stored one of the study."""
        with Session(self._engine) as s:
            last = s.execute(
                select(func.max(_Variant.position)).where(_Variant.study_id == study_id)
            ).scalar()
        return 0 if last is None else int(last) + 1

    @guarded
    def add(self, study_id: int, rows: Iterable[Mapping[str, Any]]) -> None:
        """Store a block of variants in one transaction; a key already stored (by another process
        on the same study) is left as it is.

        Each row holds ``key``, ``position``, ``parameters``, ``given``, ``outputs``, ``status``,
        ``error``, ``objective``, ``model_sha256`` and optionally ``curves`` (name → (array, unit)).
        """
        from mechdyn import __version__

        now = datetime.now(UTC)
        rows = list(rows)
        if not rows:
            return
        _, pn, on = self._columns(study_id)
        values = [
            {
                "study_id": study_id,
                "key": r["key"],
                "position": int(r["position"]),
                "parameters": _flat(r["parameters"], pn),
                "given": _flat(r.get("given", {}), pn),
                "outputs": _flat(r["outputs"], on),
                "status": r["status"],
                "error": r.get("error"),
                "objective": jsonable(r.get("objective")),
                "model_sha256": r["model_sha256"],
                "package_version": __version__,
                "created_at": now,
                "warnings": list(r.get("warnings") or ()) or None,
            }
            for r in rows
        ]
        stmt = self._insert(_Variant.__table__).on_conflict_do_nothing(index_elements=["study_id", "key"])
        with Session(self._engine) as s, s.begin():
            s.execute(stmt, values)
            with_curves = [r for r in rows if r.get("curves")]
            if with_curves:
                keys = [r["key"] for r in with_curves]
                ids = dict(
                    s.execute(
                        select(_Variant.key, _Variant.id).where(
                            _Variant.study_id == study_id, _Variant.key.in_(keys)
                        )
                    ).all()
                )
                self._put_curves(s, [(ids[r["key"]], r["curves"]) for r in with_curves])

    @guarded
    def with_curves(self, study_id: int) -> set[int]:
        """Ids of the study's variants that have curves kept."""
        q = (
            select(_Curve.variant_id)
            .join(_Variant, _Variant.id == _Curve.variant_id)
            .where(_Variant.study_id == study_id)
            .distinct()
        )
        with Session(self._engine) as s:
            return {i for (i,) in s.execute(q)}

    @guarded
    def add_curves(self, variant_id: int, curves: Mapping[str, tuple[np.ndarray, str]]) -> None:
        """Keep a stored variant's curves (those it already has are left)."""
        with Session(self._engine) as s, s.begin():
            self._put_curves(s, [(variant_id, curves)])

    def _insert(self, table: Any) -> Any:
        """INSERT that leaves a row whose unique key is already stored (SQLite and PostgreSQL)."""
        insert = pg_insert if self._engine.dialect.name == "postgresql" else sqlite_insert
        return insert(table)

    def _put_curves(
        self, s: Session, items: Sequence[tuple[int, Mapping[str, tuple[np.ndarray, str]]]]
    ) -> None:
        rows = [
            {"variant_id": vid, "name": name, "unit": unit, "data": pack_array(np.asarray(arr))}
            for vid, curves in items
            for name, (arr, unit) in curves.items()
        ]
        if rows:
            stmt = self._insert(_Curve.__table__).on_conflict_do_nothing(
                index_elements=["variant_id", "name"]
            )
            s.execute(stmt, rows)

    @guarded
    def variants(
        self, study: str, *, status: str | None = None, limit: int | None = None, curves: bool = False
    ) -> list[StoredVariant]:
        """A study's variants in the order they were stored."""
        st = self.study(study)
        # the columns, not ORM objects: a study of 10⁵ variants is read several times faster
        q = select(*(getattr(_Variant, c) for c in _VARIANT_COLUMNS)).where(_Variant.study_id == st.id)
        q = q.order_by(_Variant.id)
        if status:
            q = q.where(_Variant.status == status)
        if limit:
            q = q.limit(limit)
        with Session(self._engine) as s:
            out = [self._variant(SimpleNamespace(**r._mapping)) for r in s.execute(q)]
        return [self.variant(v.id) for v in out] if curves else out

    @guarded
    def variant(self, variant_id: int) -> StoredVariant:
        """One variant with its curves."""
        with Session(self._engine) as s:
            r = s.get(_Variant, variant_id)
            if r is None:
                raise StoreError(
                    f"no variant with id {variant_id} in {self.where}; `mechdyn results list --study NAME` "
                    "shows the ids"
                )
            v = self._variant(r)
            curves = {
                c.name: (unpack_array(c.data), c.unit)
                for c in s.scalars(select(_Curve).where(_Curve.variant_id == variant_id))
            }
        return StoredVariant(**{**v.__dict__, "curves": curves})

    def _columns(self, study_id: int) -> tuple[str, tuple[str, ...], tuple[str, ...]]:
        """A study's name and its parameter and output names (read once)."""
        if study_id not in self._names:
            with Session(self._engine) as s:
                name, cols = s.execute(select(_Study.name, _Study.columns).where(_Study.id == study_id)).one()
            self._names[study_id] = (name, tuple(cols["parameters"]), tuple(cols["outputs"]))
        return self._names[study_id]

    def _variant(self, r: Any) -> StoredVariant:
        study, pn, on = self._columns(r.study_id)
        return StoredVariant(
            r.id,
            study,
            r.key,
            r.position,
            dict(zip(pn, r.parameters or (), strict=False)),
            dict(zip(pn, r.given or (), strict=False)),
            dict(zip(on, r.outputs or (), strict=False)),
            r.status,
            r.error,
            r.objective,
            r.model_sha256,
            r.package_version,
            _utc(r.created_at),
            warnings=tuple(r.warnings or ()),
        )


def import_unsaved(store: Any, path: Any) -> str:
    """Store what :func:`mechdyn.store.unsaved.keep_unsaved` kept (a run, or a block of a study's
    variants); returns what was stored, in words.

    Parameters
    ----------
    store : ResultStore
        The database to store it in.
    path : str or path
        The file.
    """
    from mechdyn.store.unsaved import read_unsaved

    doc = read_unsaved(path)
    if doc["kind"] == "run":
        return f"run {store.record(**doc['run'])}"
    studies = StudyStore(store)
    study = studies.study(doc["study"])
    studies.add(study.id, doc["rows"])
    return f"{len(doc['rows'])} variants of study {study.name!r}"
