"""A stored study's variants as the dashboard reads them: counted, sorted, paged and sampled by the
database, so that a page of a study of 10⁵ variants reads a page, not the study.

A variant's parameters and outputs are JSON lists in the order of the study's column names; a value
is taken out of them in SQL (SQLite's ``json_extract``, PostgreSQL's ``->>``, both written by
SQLAlchemy's JSON index) to sort by it or to read just the columns a view draws. Values come back in
SI and are shown through the study's :class:`~mechdyn.reports.columns.Column` (the study file's
units).
"""

from __future__ import annotations

import json
import math
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from sqlalchemy import Text, func, select, type_coerce
from sqlalchemy.orm import Session

from mechdyn.store.schema import Variant as _Variant

__all__ = ["PAGE_SIZE", "SAMPLE_SIZE", "StudyData"]

_WHOLE: dict[tuple[int, int, int], tuple[np.ndarray, np.ndarray]] = {}
_WHOLE_LOCK = threading.Lock()
_WHOLE_KEPT = 4  # studies whose every value is kept in memory (10⁵ variants × 10 columns: 8 MB)

PAGE_SIZE = 100
"""Variants in one page of a study's table."""

SAMPLE_SIZE = 20_000
"""Variants drawn at most in a study's scatter plots (an evenly spread sample of a larger study)."""


def _matrix(texts: Sequence[Any], width: int) -> np.ndarray:
    """Rows of JSON lists of numbers (as stored) as a float matrix ``(len(texts), width)``, NaN where a
    value is missing or not a number; parsed as one JSON document."""
    out = np.full((len(texts), width), np.nan)
    if not texts or not width:
        return out
    if all(isinstance(t, str) or t is None for t in texts):  # SQLite gives the text as stored
        rows = json.loads("[" + ",".join(t or "[]" for t in texts) + "]")
    else:  # PostgreSQL's driver decodes a JSON column itself
        rows = [t or [] for t in texts]
    for k, row in enumerate(rows):
        for j, v in enumerate(row[:width]):
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                out[k, j] = v
    return out


def _json_numbers(values: np.ndarray) -> str:
    """Numbers as the inside of a JSON list: seven significant digits, null for NaN."""
    a = np.asarray(values, dtype=float)
    text = np.char.mod("%.7g", np.where(np.isfinite(a), a, 0.0))
    return ",".join(np.where(np.isfinite(a), text, "null").tolist())


def _finite(x: Any) -> float | None:
    try:
        v = float(x)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


@dataclass
class StudyData:
    """The variants of one stored study, read through the database.

    Parameters
    ----------
    engine : sqlalchemy.engine.Engine
        The results database (read-only is enough).
    study_id : int
        The study's id.
    columns : list of Column
        Its parameters, then its outputs, as shown (:func:`mechdyn.reports.columns.stored_columns`),
        in the order the database stores them.
    """

    engine: Any
    study_id: int
    columns: list[Any]

    def _value(self, index: int) -> Any:
        """SQL for the SI value of column ``index`` of each variant (NULL where missing)."""
        if self.columns[index].role == "parameter":
            return _Variant.parameters[index].as_float()
        return _Variant.outputs[index - self._n_parameters].as_float()

    def _where(self, status: str | None = None) -> list[Any]:
        clauses = [_Variant.study_id == self.study_id]
        if status:
            clauses.append(_Variant.status == status)
        return clauses

    def page(
        self, *, sort: str = "id", descending: bool = False, offset: int = 0, limit: int = PAGE_SIZE
    ) -> list[dict[str, Any]]:
        """One page of the table, sorted by the database.

        Parameters
        ----------
        sort : str
            ``"id"``, ``"status"``, or a column's index (``"0"``, ``"1"``, …) in :attr:`columns`.
            A variant without that value (failed) comes last either way.
        descending : bool
            Largest first.
        offset, limit : int
            Which rows: ``limit`` of them from row ``offset`` of the sorted table.

        Returns
        -------
        list of dict
            ``id``, ``status``, ``error`` and ``values`` (each column's value in its shown unit, or
            None) per variant.
        """
        key: Any
        if sort == "status":
            key = _Variant.status
        elif sort.isdigit() and int(sort) < len(self.columns):
            key = self._value(int(sort))
        else:
            key = _Variant.id
        order = key.desc() if descending else key.asc()
        q = (
            select(_Variant.id, _Variant.status, _Variant.error, _Variant.parameters, _Variant.outputs)
            .where(*self._where())
            .order_by(order.nulls_last(), _Variant.id)
            .offset(max(0, offset))
            .limit(max(1, min(limit, 1000)))
        )
        with Session(self.engine) as s:
            rows = s.execute(q).all()
        return [
            {"id": i, "status": status, "error": error or "", "values": self._shown(p or [], o or [])}
            for i, status, error, p, o in rows
        ]

    def _shown(self, parameters: Sequence[Any], outputs: Sequence[Any]) -> list[Any]:
        values = [*parameters, *([None] * (self._n_parameters - len(parameters))), *outputs]
        out = []
        for c, v in zip(self.columns, values, strict=False):
            if c.levels:
                x = _finite(v)
                out.append(c.levels[int(x)] if x is not None and 0 <= x < len(c.levels) else None)
            else:
                out.append(c.shown(v))
        return out

    @property
    def _n_parameters(self) -> int:
        return sum(1 for c in self.columns if c.role == "parameter")

    def numbers(self, indices: Sequence[int], *, sample: int | None = SAMPLE_SIZE) -> dict[str, Any]:
        """The values of some columns for the variants that succeeded, as plot axes read them (a
        choice by the index of its level), in the order they were evaluated.

        Parameters
        ----------
        indices : sequence of int
            Columns of :attr:`columns`.
        sample : int, optional
            At most this many variants: every k-th by its place in the study (evenly spread over it);
            None reads every one.

        Returns
        -------
        dict
            ``ids`` (list of int), ``values`` (one array per column, in its shown unit, NaN where
            missing), ``total`` (variants that succeeded) and ``sampled`` (whether this is a sample).
        """
        total = self._ok_count()
        step = 1 if sample is None or total <= sample else math.ceil(total / sample)
        if step > 1 and not self._cached():  # a sample of a study not read whole: by the database
            ids, table = self._read(step)
        else:
            ids, table = self._whole()
            if step > 1:  # every step-th by place in the study, from the kept table
                ids, table = ids[::step], table[::step]
        values = []
        for i in indices:
            c = self.columns[i]
            values.append(table[:, i] if c.levels else c.shown_array(table[:, i]))
        return {"ids": ids.tolist(), "values": values, "total": total, "sampled": step > 1}

    def _ok_count(self) -> int:
        with Session(self.engine) as s:
            return int(s.execute(select(func.count()).where(*self._where("ok"))).scalar_one())

    def _read(self, step: int = 1) -> tuple[np.ndarray, np.ndarray]:
        """(ids, SI values) of the succeeded variants, every ``step``-th by place in the study: the
        two JSON lists read as text and parsed here in one go (cheaper than extracting each value
        in SQL, or decoding row by row)."""
        q = select(_Variant.id, type_coerce(_Variant.parameters, Text), type_coerce(_Variant.outputs, Text))
        q = q.where(*self._where("ok"))
        if step > 1:
            q = q.where(_Variant.position % step == 0)
        with Session(self.engine) as s:
            rows = s.execute(q.order_by(_Variant.position, _Variant.id)).all()
        n, m = self._n_parameters, len(self.columns) - self._n_parameters
        table = np.hstack([_matrix([r[1] for r in rows], n), _matrix([r[2] for r in rows], m)])
        return np.array([r[0] for r in rows], dtype=np.int64), table

    def _key(self) -> tuple[int, int, int]:
        return (id(self.engine), self.study_id, self._ok_count())

    def _cached(self) -> bool:
        return self._key() in _WHOLE

    def _whole(self) -> tuple[np.ndarray, np.ndarray]:
        """Every succeeded variant's values, SI, read once per number of such variants and kept (a
        few studies at a time): the views over every variant then cost no query."""
        key = self._key()
        with _WHOLE_LOCK:
            if key not in _WHOLE:
                _WHOLE[key] = self._read()
                while len(_WHOLE) > _WHOLE_KEPT:
                    _WHOLE.pop(next(iter(_WHOLE)))
            return _WHOLE[key]

    def numbers_json(self, indices: Sequence[int], *, sample: int | None = SAMPLE_SIZE) -> str:
        """:meth:`numbers` as JSON text, each value to seven significant digits (a plot shows three;
        the page stays small), a missing one as null."""
        d = self.numbers(indices, sample=sample)
        values = ",".join(f"[{_json_numbers(v)}]" for v in d["values"])
        ids = ",".join(map(str, d["ids"]))
        return (
            f'{{"ids":[{ids}],"values":[{values}],"total":{d["total"]},"sampled":{json.dumps(d["sampled"])}}}'
        )

    def extremes(self, index: int) -> tuple[float | None, float | None]:
        """The smallest and largest value of one column over the variants that succeeded, in its
        shown unit (None for none), by the database."""
        value = self._value(index)
        with Session(self.engine) as s:
            lo, hi = s.execute(select(func.min(value), func.max(value)).where(*self._where("ok"))).one()
        c = self.columns[index]
        return tuple(None if x is None else c.shown(x) for x in (lo, hi))  # type: ignore[return-value]

    def array(self, index: int) -> tuple[np.ndarray, np.ndarray]:
        """Every succeeded variant's value of one column, SI: (ids, values), NaN where missing, in
        the order they were evaluated (from the kept table, :meth:`warm`)."""
        ids, table = self._whole()
        return ids, table[:, index]

    def warm(self) -> None:
        """Read and keep every succeeded variant's values now (a large study's first view then
        costs no wait)."""
        self._whole()
