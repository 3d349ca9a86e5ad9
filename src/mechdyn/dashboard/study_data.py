"""A stored study's variants as the dashboard reads them: counted, sorted, paged and sampled by the
database, so that a page of a study of 10⁵ variants reads a page, not the study.

Once a study's every value is read (:meth:`StudyData.warm`, as its page is first shown) it is kept in
memory per stored state of the study (its variants are only ever added: their number and largest id
name the state), and the views and the table are answered from it: a page of the table sorted by any
column is a slice of the sorted order (worked out once per column and order) and a read of its 100
rows by id, whatever its depth.

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
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from sqlalchemy import Text, cast, func, select
from sqlalchemy.orm import Session

from mechdyn.store.schema import Study as _Study
from mechdyn.store.schema import Variant as _Variant

__all__ = ["PAGE_SIZE", "SAMPLE_SIZE", "StudyData"]

State = tuple[str, int, str, int, int]
"""A study's stored state: database, study id, when the study was created, number of variants and
their largest id (variants are only added, so these change with every variant stored)."""


@dataclass
class _Whole:
    """Every variant of a study in one stored state, SI, by place in the study (position, then id)."""

    ids: np.ndarray  # int64 (n,)
    status: np.ndarray  # str (n,)
    positions: np.ndarray  # int64 (n,): each one's place in the study
    table: np.ndarray  # float (n, columns), NaN where missing
    lock: threading.Lock = field(default_factory=threading.Lock)
    orders: dict[tuple[str, bool], np.ndarray] = field(default_factory=dict)  # the table's sorted orders
    texts: dict[tuple[Any, ...], str] = field(default_factory=dict)  # the points' JSON, as sent

    def __post_init__(self) -> None:
        self.ok = self.status == "ok"
        every = bool(self.ok.all())
        self.ok_ids = self.ids if every else self.ids[self.ok]
        self.ok_table = self.table if every else self.table[self.ok]

    def order(self, sort: str, descending: bool) -> np.ndarray:
        """Rows in the order of the table sorted by ``sort`` (``"id"``, ``"status"`` or a column's
        index), ties and missing values as the database sorts them: missing last either way, ties by
        id; worked out once and kept."""
        with self.lock:
            if (sort, descending) not in self.orders:
                primary: np.ndarray
                if sort == "id":
                    primary = self.ids.astype(float)
                elif sort == "status":
                    primary = np.unique(self.status, return_inverse=True)[1].astype(float)
                else:
                    primary = self.table[:, int(sort)]
                # NaN sorts last (numpy), and stays last when negated: missing last either way
                self.orders[(sort, descending)] = np.lexsort((self.ids, -primary if descending else primary))
            return self.orders[(sort, descending)]


_WHOLE: dict[State, _Whole] = {}
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
    if all(isinstance(t, str) or t is None for t in texts):  # JSON text, as stored
        joined = "[" + ",".join(t or "[]" for t in texts) + "]"
        rows = json.loads(joined)
        if not any(w in joined for w in ('"', "true", "false")):  # no text, no flag (both missing)
            try:  # every row as long as the next, of numbers and nulls: numpy reads them at once
                fast = np.array(rows, dtype=float)
            except (TypeError, ValueError):
                fast = None
            if fast is not None and fast.shape == out.shape:
                return fast
    else:  # a driver that decodes a JSON column itself
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

    Notes
    -----
    The study's stored state is read once, by the first question asked: one object answers one
    request, all of it from the same state (a page's rows and its counts agree while the study grows).
    """

    engine: Any
    study_id: int
    columns: list[Any]
    _now: State | None = field(default=None, init=False, repr=False)

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

    def _sort(self, sort: str) -> str:
        """The table's sort as asked (``"id"``, ``"status"`` or a column's index), ``"id"`` for
        anything else."""
        if sort == "status" or (sort.isdigit() and int(sort) < len(self.columns)):
            return str(int(sort)) if sort.isdigit() else sort
        return "id"

    def page(
        self, *, sort: str = "id", descending: bool = False, offset: int = 0, limit: int = PAGE_SIZE
    ) -> list[dict[str, Any]]:
        """One page of the table, sorted over the whole study.

        The order is a slice of the kept sorted order where the study's values are kept
        (:meth:`warm`), else the database's (which sorts only the ids); the page's rows are then read
        by id.

        Parameters
        ----------
        sort : str
            ``"id"``, ``"status"``, or a column's index (``"0"``, ``"1"``, …) in :attr:`columns`.
            A variant without that value (failed) comes last either way; ties by id.
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
        sort = self._sort(sort)
        offset, limit = max(0, offset), max(1, min(limit, 1000))
        whole = self._kept()
        if whole is not None:
            ids = whole.ids[whole.order(sort, descending)[offset : offset + limit]].tolist()
        else:
            key: Any
            if sort == "status":
                key = _Variant.status
            elif sort == "id":
                key = _Variant.id
            else:
                key = self._value(int(sort))
            order = key.desc() if descending else key.asc()
            by = select(_Variant.id).where(*self._where()).order_by(order.nulls_last(), _Variant.id)
            with Session(self.engine) as s:  # the ids alone: the database sorts small rows
                ids = list(s.scalars(by.offset(offset).limit(limit)))
        if not ids:
            return []
        q = select(_Variant.id, _Variant.status, _Variant.error, _Variant.parameters, _Variant.outputs)
        with Session(self.engine) as s:
            rows = {r[0]: tuple(r) for r in s.execute(q.where(*self._where(), _Variant.id.in_(ids)))}
        return [
            {"id": i, "status": status, "error": error or "", "values": self._shown(p or [], o or [])}
            for i, status, error, p, o in (rows[i] for i in ids if i in rows)
        ]

    def counts(self) -> dict[str, int]:
        """How many variants the study holds (``variants``) and how many of them failed
        (``failed``), in the same stored state as :meth:`page` reads."""
        whole = self._kept()
        if whole is not None:
            return {"variants": int(whole.ids.size), "failed": int(whole.ids.size - whole.ok.sum())}
        q = select(_Variant.status, func.count()).where(*self._where()).group_by(_Variant.status)
        with Session(self.engine) as s:
            by = dict(s.execute(q).all())
        return {"variants": int(sum(by.values())), "failed": int(sum(n for k, n in by.items() if k != "ok"))}

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
        ids, values, total, step = self._numbers(indices, sample)
        return {"ids": ids.tolist(), "values": values, "total": total, "sampled": step > 1}

    def _numbers(
        self, indices: Sequence[int], sample: int | None
    ) -> tuple[np.ndarray, list[np.ndarray], int, int]:
        whole = self._kept()
        total = int(whole.ok_ids.size) if whole is not None else self._ok_count()
        step = 1 if sample is None or total <= sample else math.ceil(total / sample)
        if step > 1 and whole is None:  # a sample of a study not read whole: by the database
            ids, table = self._read_ok(step)
        else:
            ids, table = self._whole()
            if step > 1:  # every step-th by place in the study, from the kept table
                ids, table = ids[::step], table[::step]
        values = []
        for i in indices:
            c = self.columns[i]
            values.append(table[:, i] if c.levels else c.shown_array(table[:, i]))
        return ids, values, total, step

    def _ok_count(self) -> int:
        with Session(self.engine) as s:
            return int(s.execute(select(func.count()).where(*self._where("ok"))).scalar_one())

    def _rows(self, *clauses: Any) -> _Whole:
        """The study's variants that meet ``clauses``, by place in the study, as a :class:`_Whole`:
        the two JSON lists read as text and parsed here in one go (cheaper than extracting each value
        in SQL, or decoding row by row)."""
        q = select(
            _Variant.id,
            _Variant.status,
            _Variant.position,
            cast(_Variant.parameters, Text),
            cast(_Variant.outputs, Text),
        ).where(*self._where(), *clauses)
        with self.engine.connect() as connection:
            rows = connection.execute(q.order_by(_Variant.position, _Variant.id)).all()
        n, m = self._n_parameters, len(self.columns) - self._n_parameters
        return _Whole(
            np.array([r[0] for r in rows], dtype=np.int64),
            np.array([r[1] for r in rows], dtype=str),
            np.array([r[2] for r in rows], dtype=np.int64),
            np.hstack([_matrix([r[3] for r in rows], n), _matrix([r[4] for r in rows], m)]),
        )

    def _read_ok(self, step: int) -> tuple[np.ndarray, np.ndarray]:
        """(ids, SI values) of every ``step``-th succeeded variant by place in the study."""
        read = self._rows(_Variant.status == "ok", _Variant.position % step == 0)
        return read.ids, read.table

    def _state(self) -> State:
        """The study's stored state now (read once per :class:`StudyData`, that is per request)."""
        if self._now is None:
            created = select(_Study.created_at).where(_Study.id == self.study_id).scalar_subquery()
            q = select(func.count(), func.max(_Variant.id), created).where(*self._where())
            with Session(self.engine) as s:
                n, last, when = s.execute(q).one()
            url = self.engine.url.render_as_string(hide_password=True)
            self._now = (url, self.study_id, str(when), int(n), int(last or 0))
        return self._now

    def _kept(self) -> _Whole | None:
        """The study's values in its state now, if they are kept."""
        return _WHOLE.get(self._state())

    def _read_whole(self) -> _Whole:
        """Every variant's values in the state now, the ones kept of an earlier state of the study
        reused: variants are only added, so only those past its largest id are read."""
        url, study, when, n, last = self._state()
        earlier = [w for k, w in _WHOLE.items() if k[:3] == (url, study, when) and k[4] <= last]
        if earlier:
            before = max(earlier, key=lambda w: w.ids.size)
            new = self._rows(_Variant.id > int(before.ids.max(initial=0)))
            if before.ids.size + new.ids.size == n:  # none gone: the earlier rows still hold
                ids, positions = np.r_[before.ids, new.ids], np.r_[before.positions, new.positions]
                place = np.lexsort((ids, positions))  # by place in the study again
                status = np.r_[before.status, new.status]
                return _Whole(
                    ids[place], status[place], positions[place], np.vstack([before.table, new.table])[place]
                )
        return self._rows()

    def _whole(self) -> tuple[np.ndarray, np.ndarray]:
        """Every succeeded variant's (ids, SI values), the whole study read once per stored state and
        kept (a few studies at a time): the views over every variant then cost no query."""
        key = self._state()
        with _WHOLE_LOCK:
            if key not in _WHOLE:
                whole = self._read_whole()
                for earlier in [k for k in _WHOLE if k[:2] == key[:2]]:  # the study's earlier states
                    del _WHOLE[earlier]
                _WHOLE[key] = whole
                while len(_WHOLE) > _WHOLE_KEPT:
                    _WHOLE.pop(next(iter(_WHOLE)))
            whole = _WHOLE[key]
        return whole.ok_ids, whole.ok_table

    def numbers_json(self, indices: Sequence[int], *, sample: int | None = SAMPLE_SIZE) -> str:
        """:meth:`numbers` as JSON text, each value to seven significant digits (a plot shows three;
        the page stays small), a missing one as null; kept with the study's values (written once per
        stored state)."""
        whole = self._kept()
        key = (tuple(indices), sample)
        if whole is not None and key in whole.texts:
            return whole.texts[key]
        ids, columns, total, step = self._numbers(indices, sample)
        values = ",".join(f"[{_json_numbers(v)}]" for v in columns)
        text = (
            f'{{"ids":[{",".join(map(str, ids.tolist()))}],"values":[{values}],"total":{total},'
            f'"sampled":{json.dumps(step > 1)}}}'
        )
        whole = self._kept()
        if whole is not None:
            whole.texts[key] = text
        return text

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
        """Read and keep every variant's values now, and write the page's points (a large study's
        first view then costs no wait, and its table is sorted in memory)."""
        self._whole()
        self.numbers_json(range(len(self.columns)))
