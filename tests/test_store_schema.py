"""The results database's schema: its version row, upgrades from older mechdyn, refusal of newer
and foreign databases, read-only opening, database faults as one line, nothing computed lost."""

from __future__ import annotations

import hashlib
import json
import re
from collections.abc import Iterator
from contextlib import contextmanager
from datetime import UTC, datetime
from pathlib import Path

import pytest
import sqlalchemy as sa

from conftest import EXAMPLES
from mechdyn.cli.main import main
from mechdyn.store import SCHEMA_VERSION, ResultStore, StoreError
from mechdyn.store.schema import NAME_LENGTH, VERSION_TABLE
from mechdyn.studies.storage import StudyStore

TURRET = str(EXAMPLES / "turret_milling.toml")


@contextmanager
def _engine(url: str) -> Iterator[sa.Engine]:
    from mechdyn.store import resolve_url

    engine = sa.create_engine(resolve_url(url))
    try:
        yield engine
    finally:
        engine.dispose()


def _version(url: str) -> str:
    with _engine(url) as engine, engine.connect() as conn:
        return conn.execute(sa.text(f"SELECT version_num FROM {VERSION_TABLE}")).scalar_one()


def _legacy_database(url: str) -> None:
    """A database as mechdyn wrote it before schema versions and before study columns: no version
    row, no records table, a study whose variants keep their values as name → value objects."""
    md = sa.MetaData()
    runs = sa.Table(
        "mechdyn_runs",
        md,
        sa.Column("id", sa.Integer, primary_key=True),
        sa.Column("created_at", sa.DateTime(timezone=True)),
        sa.Column("analysis", sa.String(64)),
        sa.Column("model_name", sa.String(256)),
        sa.Column("model_path", sa.Text),
        sa.Column("model_sha256", sa.String(64)),
        sa.Column("model_text", sa.Text),
        sa.Column("parameters", sa.JSON),
        sa.Column("scalars", sa.JSON),
        sa.Column("package_version", sa.String(64)),
    )
    sa.Table(
        "mechdyn_arrays",
        md,
        sa.Column("id", sa.Integer, primary_key=True),
        sa.Column("run_id", sa.ForeignKey("mechdyn_runs.id")),
        sa.Column("name", sa.String(256)),
        sa.Column("unit", sa.String(64)),
        sa.Column("data", sa.LargeBinary),
    )
    studies = sa.Table(
        "mechdyn_studies",
        md,
        sa.Column("id", sa.Integer, primary_key=True),
        sa.Column("name", sa.String(256), unique=True),
        sa.Column("kind", sa.String(32)),
        sa.Column("analysis", sa.String(64)),
        sa.Column("definition", sa.JSON),
        sa.Column("definition_sha256", sa.String(64)),
        sa.Column("model_path", sa.Text),
        sa.Column("model_sha256", sa.String(64)),
        sa.Column("model_files", sa.JSON),
        sa.Column("package_version", sa.String(64)),
        sa.Column("created_at", sa.DateTime(timezone=True)),
    )
    variants = sa.Table(
        "mechdyn_variants",
        md,
        sa.Column("id", sa.Integer, primary_key=True),
        sa.Column("study_id", sa.ForeignKey("mechdyn_studies.id")),
        sa.Column("key", sa.String(64)),
        sa.Column("position", sa.Integer),
        sa.Column("parameters", sa.JSON),
        sa.Column("given", sa.JSON),
        sa.Column("outputs", sa.JSON),
        sa.Column("status", sa.String(16)),
        sa.Column("error", sa.Text),
        sa.Column("objective", sa.Float),
        sa.Column("model_sha256", sa.String(64)),
        sa.Column("package_version", sa.String(64)),
        sa.Column("created_at", sa.DateTime(timezone=True)),
        sa.UniqueConstraint("study_id", "key"),
    )
    sa.Table(
        "mechdyn_variant_curves",
        md,
        sa.Column("id", sa.Integer, primary_key=True),
        sa.Column("variant_id", sa.ForeignKey("mechdyn_variants.id")),
        sa.Column("name", sa.String(256)),
        sa.Column("unit", sa.String(64)),
        sa.Column("data", sa.LargeBinary),
        sa.UniqueConstraint("variant_id", "name"),
    )
    now = datetime.now(UTC)
    with _engine(url) as engine, engine.begin() as conn:
        md.create_all(conn)
        conn.execute(
            runs.insert().values(
                id=1,
                created_at=now,
                analysis="modal",
                model_name="old turret",
                model_path="t.toml",
                model_sha256="c" * 64,
                model_text="[model]",
                parameters={},
                scalars={"x_m": 2.5},
                package_version="0.0.9",
            )
        )
        conn.execute(
            studies.insert().values(
                id=1,
                name="old-study",
                kind="oat",
                analysis="support",
                definition={},
                definition_sha256="d" * 64,
                model_path="p.toml",
                model_sha256="e" * 64,
                model_files={},
                package_version="0.0.9",
                created_at=now,
            )
        )
        for i, (k, y) in enumerate([(1.0e6, 3.0), (2.0e6, 1.5)]):
            conn.execute(
                variants.insert().values(
                    study_id=1,
                    key=f"k{i}",
                    position=i,
                    parameters={"support.stiffness": k},
                    given={"support.stiffness": f"{k / 1e6:g} MN/m"},
                    outputs={"force_N": y, "disp_m": y / k},
                    status="ok",
                    error=None,
                    objective=None,
                    model_sha256="e" * 64,
                    package_version="0.0.9",
                    created_at=now,
                )
            )


def test_a_new_database_carries_the_schema_version(store_url):
    with ResultStore(store_url) as store:
        store.record(
            analysis="modal",
            model_name="m",
            model_path="p",
            model_text="t",
            model_sha256="a" * 64,
            parameters={},
            scalars={},
        )
    assert _version(store_url) == SCHEMA_VERSION
    with ResultStore(store_url, read_only=True) as store:  # and reads back as it is
        assert len(store.runs()) == 1


def test_an_older_database_is_refused_until_upgraded_and_loses_nothing(store_url, capsys):
    _legacy_database(store_url)
    with pytest.raises(StoreError, match=r"older mechdyn .*`mechdyn results upgrade --db"):
        ResultStore(store_url)
    assert main(["results", "list", "--db", store_url]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "results upgrade" in err and "Traceback" not in err
    assert main(["results", "upgrade", "--db", store_url]) == 0
    assert f"to {SCHEMA_VERSION}" in capsys.readouterr().out
    assert _version(store_url) == SCHEMA_VERSION
    with ResultStore(store_url) as store:
        assert store.get(1).scalars == {"x_m": 2.5}
        assert store.records("material") == []  # the table it lacked is there
        studies = StudyStore(store)
        old = studies.variants("old-study")
        assert [v.parameters for v in old] == [{"support.stiffness": 1.0e6}, {"support.stiffness": 2.0e6}]
        assert [v.outputs for v in old] == [
            {"force_N": 3.0, "disp_m": 3e-6},
            {"force_N": 1.5, "disp_m": 7.5e-7},
        ]
        assert old[0].given == {"support.stiffness": "1 MN/m"} and old[0].warnings == ()
    assert main(["results", "upgrade", "--db", store_url]) == 0  # a second time: nothing to do
    assert "nothing to do" in capsys.readouterr().out


def test_a_database_of_schema_0001_gets_the_variant_warnings_column(tmp_path):
    url = str(tmp_path / "v1.db")
    from mechdyn.store import database

    engine = database.open_engine(f"sqlite:///{url}", read_only=False)
    with engine.begin() as conn:  # schema 0001 is the legacy shape with study columns, stamped 0001
        from alembic import command
        from alembic.config import Config

        cfg = Config()
        cfg.set_main_option("script_location", str(Path(database.__file__).with_name("migrations")))
        cfg.attributes["connection"] = conn
        command.upgrade(cfg, "0001")
    engine.dispose()
    assert _version(url) == "0001"
    with pytest.raises(StoreError, match=r"schema 0001, older than this mechdyn's"):
        ResultStore(url)
    assert ResultStore.upgrade(url) == ("0001", SCHEMA_VERSION)
    with ResultStore(url) as store:
        st, _ = StudyStore(store).open(
            "s",
            kind="oat",
            analysis="modal",
            definition={},
            model_path="p",
            model_sha256="b" * 64,
            model_files={},
            parameters=["p"],
            outputs=["y"],
        )
        StudyStore(store).add(
            st.id,
            [
                {
                    "key": "k",
                    "position": 0,
                    "parameters": {"p": 1.0},
                    "outputs": {"y": 2.0},
                    "status": "ok",
                    "model_sha256": "b" * 64,
                    "warnings": ["near a toggle"],
                }
            ],
        )
        assert StudyStore(store).variants("s")[0].warnings == ("near a toggle",)


def test_a_newer_database_is_refused_with_the_advice_to_upgrade_mechdyn(store_url, capsys):
    ResultStore(store_url).close()
    with _engine(store_url) as engine, engine.begin() as conn:
        conn.execute(sa.text(f"UPDATE {VERSION_TABLE} SET version_num = '0099'"))
    for read_only in (False, True):
        with pytest.raises(
            StoreError, match=r"schema 0099, written by a newer mechdyn .*pip install -U mechdyn"
        ):
            ResultStore(store_url, read_only=read_only)
    with pytest.raises(StoreError, match="newer mechdyn"):
        ResultStore.upgrade(store_url)
    assert main(["modal", TURRET, "--db", store_url]) == 2  # refused before the work, in one line
    out, err = capsys.readouterr()
    assert "newer mechdyn" in err and err.count("\n") == 1 and out == ""


def test_another_applications_sqlite_file_is_refused_and_left_untouched(tmp_path, capsys):
    import sqlite3

    path = tmp_path / "app.db"
    with sqlite3.connect(path) as conn:
        conn.execute("CREATE TABLE customers (id INTEGER PRIMARY KEY, name TEXT)")
        conn.execute("INSERT INTO customers (name) VALUES ('ACME')")
    conn.close()
    before = hashlib.sha256(path.read_bytes()).hexdigest()
    for argv in (["modal", TURRET, "--db", str(path)], ["results", "list", "--db", str(path)]):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert "another application's database (tables customers)" in err and err.count("\n") == 1
    with pytest.raises(StoreError, match="another application"):
        ResultStore(path)
    assert hashlib.sha256(path.read_bytes()).hexdigest() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["app.db"]  # no journal, no unsaved file


def test_a_file_that_is_no_database_is_refused(tmp_path, capsys):
    path = tmp_path / "notes.db"
    path.write_text("these are my notes, not a database\n" * 100)
    assert main(["results", "list", "--db", str(path)]) == 2
    assert main(["modal", TURRET, "--db", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("is not a results database") == 2 and "Traceback" not in err
    assert path.read_text().startswith("these are my notes")


def test_a_damaged_sqlite_file_is_refused_before_the_work(tmp_path, capsys):
    """SQLite goes on appending to a file with a broken page; mechdyn checks the pages when it opens
    a file to write, so nothing is computed for a file that a later read could not give back."""
    path = tmp_path / "results.db"
    store = ResultStore(path)
    for i in range(60):
        store.record(
            analysis="modal",
            model_name=f"m{i}",
            model_path="m.toml",
            model_text="x" * 2000,
            model_sha256="0" * 64,
            parameters={},
            scalars={"x_m": float(i)},
        )
    store.close()
    data = bytearray(path.read_bytes())
    middle = len(data) // 2 // 4096 * 4096
    data[middle : middle + 4096] = b"\xff" * 4096
    path.write_bytes(bytes(data))
    assert main(["modal", TURRET, "--db", str(path)]) == 2
    err = capsys.readouterr().err
    assert "is damaged" in err and ".recover" in err and str(path) in err and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["results.db"]  # refused at open: nothing kept
    with pytest.raises(StoreError, match="is damaged"):
        ResultStore(path)
    assert main(["results", "list", "--db", str(path)]) == 2
    assert "damaged" in capsys.readouterr().err


@pytest.mark.parametrize(
    "argv",
    [
        ["results", "list"],
        ["results", "show", "1"],
        ["results", "studies"],
        ["results", "list", "--study", "s"],
        ["results", "export", "--study", "s", "--csv", "x.csv"],
        ["results", "compare", "1", "2"],
    ],
)
def test_reading_commands_never_create_a_database(tmp_path, monkeypatch, capsys, argv):
    monkeypatch.chdir(tmp_path)
    assert main([*argv, "--db", "typo.db"]) == 2
    assert "no results database at" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_reading_commands_open_read_only(tmp_path, capsys):
    url = str(tmp_path / "r.db")
    assert main(["modal", TURRET, "--db", url, "--json"]) == 0
    capsys.readouterr()
    with ResultStore(url, read_only=True) as store, pytest.raises(StoreError, match=r"readonly|read-only"):
        store.record(
            analysis="x",
            model_name="m",
            model_path="p",
            model_text="t",
            model_sha256="a" * 64,
            parameters={},
            scalars={},
        )


def _refuse_inserts(url: str, table: str, message: str) -> None:
    """Make the database itself refuse every new row of a table (a trigger): a real fault of the
    backend, at the moment a result is stored."""
    with _engine(url) as engine, engine.begin() as conn:
        if conn.dialect.name == "sqlite":
            conn.execute(
                sa.text(
                    f"CREATE TRIGGER refuse BEFORE INSERT ON {table} "
                    f"BEGIN SELECT RAISE(ABORT, '{message}'); END"
                )
            )
        else:
            conn.execute(
                sa.text(
                    "CREATE FUNCTION refuse() RETURNS trigger AS "
                    f"$$ BEGIN RAISE EXCEPTION '{message}'; END $$ LANGUAGE plpgsql"
                )
            )
            conn.execute(
                sa.text(
                    f"CREATE TRIGGER refuse BEFORE INSERT ON {table} FOR EACH ROW EXECUTE FUNCTION refuse()"
                )
            )


def _accept_inserts(url: str, table: str) -> None:
    with _engine(url) as engine, engine.begin() as conn:
        conn.execute(
            sa.text("DROP TRIGGER refuse" + ("" if conn.dialect.name == "sqlite" else f" ON {table}"))
        )


def test_a_run_the_database_refuses_is_kept_in_a_file_and_imported_later(
    store_url, tmp_path, monkeypatch, capsys
):
    monkeypatch.chdir(tmp_path)
    assert main(["modal", TURRET, "--db", store_url, "--json"]) == 0
    first = json.loads(capsys.readouterr().out)
    _refuse_inserts(store_url, "mechdyn_runs", "database or disk is full")
    assert main(["modal", TURRET, "--db", store_url, "--json"]) == 2
    out, err = capsys.readouterr()
    assert json.loads(out)["run_id"] is None  # the result is still printed
    assert "the disk is full" in err and "mechdyn results import" in err and "Traceback" not in err
    (kept,) = (
        tmp_path.glob("mechdyn-unsaved-*-run.json")
        if "://" in store_url
        else Path(store_url).parent.glob("mechdyn-unsaved-*-run.json")
    )
    _accept_inserts(store_url, "mechdyn_runs")
    assert main(["results", "import", str(kept), "--db", store_url]) == 0
    imported = int(re.search(r"stored run (\d+) in", capsys.readouterr().out).group(1))
    with ResultStore(store_url, read_only=True) as store:
        a, b = store.get(first["run_id"]), store.get(imported)
    assert a.scalars == b.scalars and a.model_text == b.model_text and a.parameters == b.parameters
    assert a.arrays.keys() == b.arrays.keys()
    for k, (arr, unit) in a.arrays.items():
        assert b.arrays[k][1] == unit and (b.arrays[k][0] == arr).all()  # bit for bit


STUDY = """
[study]
name = "refused"
kind = "lhs"
model = "press_on_support.toml"
analysis = "support"
samples = 12
chunk = 4
seed = 3

[[parameters]]
path = "support.stiffness"
range = "±30 %"

[[outputs]]
output = "transmitted_force_range_N"
"""


@pytest.mark.parametrize(  # the same path on PostgreSQL in CI's heavy step
    "store_url", ["sqlite", pytest.param("postgresql", marks=pytest.mark.slow)], indirect=True
)
def test_a_block_of_variants_the_database_refuses_is_kept_and_imported(store_url, tmp_path, monkeypatch):
    from mechdyn.studies import load_study, run_study

    monkeypatch.chdir(tmp_path)
    for f in ("press_on_support.toml", "press_link_drive.toml"):
        (tmp_path / f).write_text((EXAMPLES / f).read_text())
    (tmp_path / "s.toml").write_text(STUDY)
    study = load_study(tmp_path / "s.toml")
    ResultStore(store_url).close()
    _refuse_inserts(store_url, "mechdyn_variants", "could not extend file: No space left on device")
    with pytest.raises(StoreError, match=r"disk is full.*variants just computed are kept in (\S+) "):
        run_study(study, store_url)
    folder = tmp_path if "://" in store_url else Path(store_url).parent
    (kept,) = folder.glob("mechdyn-unsaved-*-variants.json")
    _accept_inserts(store_url, "mechdyn_variants")
    assert main(["results", "import", str(kept), "--db", store_url]) == 0
    resumed = run_study(study, store_url)
    assert resumed.reused == 4 and resumed.evaluated == 9  # the imported block is not computed again


def test_names_longer_than_the_database_holds_are_refused_before_the_work(store_url, tmp_path, capsys):
    model = tmp_path / "long.toml"
    text = (EXAMPLES / "turret_milling.toml").read_text()
    model.write_text(text.replace('name = "', f'name = "{"x" * NAME_LENGTH}', 1))
    assert main(["modal", str(model), "--db", store_url]) == 2
    out, err = capsys.readouterr()
    assert "[model] name is 2" in err and "shorten it" in err and out == ""
    with (
        ResultStore(store_url) as store,
        pytest.raises(StoreError, match="the study's name is 257 characters"),
    ):
        StudyStore(store).open(
            "s" * 257,
            kind="oat",
            analysis="modal",
            definition={},
            model_path="p",
            model_sha256="b" * 64,
            model_files={},
            parameters=[],
            outputs=[],
        )


def test_an_unreachable_server_is_one_line(capsys):
    assert main(["modal", TURRET, "--db", "postgresql://nobody@127.0.0.1:1/none"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: cannot open the results database postgresql") and err.count("\n") == 1


def test_a_server_that_drops_the_connection_is_one_line_and_the_next_call_reconnects(postgres_url):
    with ResultStore(postgres_url) as store:
        assert store.runs() == []
        with _engine(postgres_url) as engine, engine.connect() as conn:  # as a server restart does
            conn.execute(
                sa.text(
                    "SELECT pg_terminate_backend(pid) FROM pg_stat_activity "
                    "WHERE datname = current_database() AND pid <> pg_backend_pid()"
                )
            )
        with pytest.raises(StoreError) as info:
            store.runs()
        message = str(info.value)
        assert message.startswith(f"the results database {store.where}:") and "\n" not in message
        assert "the server cannot be reached" in message
        assert store.runs() == []  # the pool has let the dead connection go
