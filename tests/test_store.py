"""The results store, on SQLite and on a real PostgreSQL server (see scripts/with-postgres)."""

from __future__ import annotations

import numpy as np
import pytest

from mechdyn.store import ResultStore, StoreError, resolve_url


def _record(store, analysis="modal", **over):
    kw = dict(
        analysis=analysis,
        model_name="turret",
        model_path="examples/turret_milling.toml",
        model_text="[model]\ntype = 'drivetrain'\n",
        model_sha256="ab" * 32,
        parameters={"rigid_gears": False, "modes": None},
        scalars={"frequencies_hz": [1101.3, 2710.0], "rigid_body_modes": 1, "bad": float("nan")},
        arrays={
            "mode_shapes": (np.arange(12.0).reshape(4, 3) / 7, "rad"),
            "angles": (np.array([1 + 2j, np.pi - 1j]), "rad"),
            "counts": (np.array([1, 2, 3], dtype=np.int64), ""),
        },
    )
    kw.update(over)
    return store.record(**kw)


def test_round_trip(store_url):
    with ResultStore(store_url) as store:
        rid = _record(store)
        run = store.get(rid)
    assert run.analysis == "modal" and run.model_name == "turret"
    assert run.model_text.startswith("[model]")
    assert run.scalars["frequencies_hz"] == [1101.3, 2710.0]
    assert run.scalars["bad"] is None  # NaN is stored as null on every backend
    assert run.parameters == {"rigid_gears": False, "modes": None}
    for name, (a, unit) in {
        "mode_shapes": (np.arange(12.0).reshape(4, 3) / 7, "rad"),
        "angles": (np.array([1 + 2j, np.pi - 1j]), "rad"),
        "counts": (np.array([1, 2, 3], dtype=np.int64), ""),
    }.items():
        got, got_unit = run.arrays[name]
        assert got.dtype == a.dtype and got_unit == unit
        np.testing.assert_array_equal(got, a)  # bit for bit
    assert run.package_version
    assert run.created_at.tzinfo is not None


def test_runs_are_listed_newest_first_and_filtered(store_url):
    with ResultStore(store_url) as store:
        ids = [_record(store, analysis=a) for a in ("modal", "campbell", "modal")]
        assert [r.id for r in store.runs()] == ids[::-1]
        assert [r.id for r in store.runs(analysis="modal")] == [ids[2], ids[0]]
        assert [r.id for r in store.runs(limit=1)] == [ids[2]]
        assert store.runs()[0].arrays == {}  # listing does not load arrays


def test_nothing_is_lost_on_reopen(store_url):
    with ResultStore(store_url) as store:
        rid = _record(store)
    with ResultStore(store_url) as store:
        assert store.get(rid).scalars["rigid_body_modes"] == 1


def test_missing_run_is_named(store_url):
    with ResultStore(store_url) as store, pytest.raises(StoreError, match="no run with id 999"):
        store.get(999)


def test_resolve_url(tmp_path, monkeypatch):
    monkeypatch.delenv("MECHDYN_DB", raising=False)
    monkeypatch.chdir(tmp_path)
    assert resolve_url() == f"sqlite:///{tmp_path / 'mechdyn.db'}"
    assert resolve_url("sub/r.db") == f"sqlite:///{tmp_path / 'sub' / 'r.db'}"
    assert resolve_url("postgresql://u:p@h:5/db") == "postgresql+psycopg://u:p@h:5/db"
    assert resolve_url("sqlite:////x/y.db") == "sqlite:////x/y.db"
    monkeypatch.setenv("MECHDYN_DB", "env.db")
    assert resolve_url() == f"sqlite:///{tmp_path / 'env.db'}"
    assert resolve_url("other.db").endswith("other.db")  # the option wins over the environment


def test_unreachable_server_is_a_clear_error():
    with pytest.raises(StoreError, match="cannot open the results database postgresql"):
        ResultStore("postgresql://nobody@127.0.0.1:1/none")
