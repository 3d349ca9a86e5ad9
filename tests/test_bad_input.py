"""Bad input never gets a traceback: every example file, mutated the ways users get files wrong, runs
to finite results or exits with status 2 and a message naming the file (issue: hardening).

The default suite runs one mutation of each kind on one file of each model type, in process; the
whole set (every example, every kind, on the first numbers of each file, in subprocesses with a
time limit, so that a hang shows) runs with ``pytest -m slow``.
"""

from __future__ import annotations

import json
import math
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import EXAMPLES
from mechdyn.cli.main import main

COMMAND = {
    "drivetrain": ["modal"],
    "mechanism": ["mechanism", "--angles", "24"],
    "planting_mechanism": ["mechanism", "--angles", "24"],
    "support": ["support", "--cycles", "1"],
    "mount": ["mount"],
    "gear_pair": ["gear"],
    "tooth_pair": ["gear"],
    "drive": ["drive", "--angles", "72", "--no-startup"],
}
NUMBER = re.compile(r'^(\s*[A-Za-z_]+\s*=\s*)"([-+0-9.eE]+)\s+([^"]+)"\s*$')
KINDS = ("negative", "zero", "nan", "inf", "huge", "wrong unit", "misspelt unit", "text", "deleted")


def _mutate(text: str, line: int, kind: str) -> str:
    lines = text.splitlines()
    m = NUMBER.match(lines[line])
    assert m, lines[line]
    head, number, unit = m.groups()
    value = {
        "negative": f'"-{number.lstrip("-+")} {unit}"',
        "zero": f'"0 {unit}"',
        "nan": f'"nan {unit}"',
        "inf": f'"inf {unit}"',
        "huge": f'"1e300 {unit}"',
        "wrong unit": f'"{number} furlong"',
        "misspelt unit": f'"{number} {unit}x"',
        "text": '"abc"',
    }.get(kind)
    if value is None:
        del lines[line]
    else:
        lines[line] = head + value
    return "\n".join(lines) + "\n"


def _numbers(text: str) -> list[int]:
    return [i for i, ln in enumerate(text.splitlines()) if NUMBER.match(ln)]


def _finite(doc) -> bool:
    if isinstance(doc, float):
        return math.isfinite(doc)
    if isinstance(doc, dict):
        return all(_finite(v) for v in doc.values())
    if isinstance(doc, list):
        return all(_finite(v) for v in doc)
    return True


def _one_per_type() -> list[Path]:
    seen, out = set(), []
    for p in sorted(EXAMPLES.glob("*.toml")):
        kind = tomllib.loads(p.read_text())["model"]["type"]
        if kind not in seen:
            seen.add(kind)
            out.append(p)
    return out


def _check(path: Path, kind_of_model: str, capsys, tmp_path: Path) -> None:
    code = main(
        [
            *COMMAND[kind_of_model][:1],
            str(path),
            *COMMAND[kind_of_model][1:],
            "--json",
            "--db",
            str(tmp_path / "r.db"),
        ]
    )
    out, err = capsys.readouterr()
    assert code in (0, 2), err
    if code == 2:
        assert str(path) in err, err
    else:
        doc = json.loads(out)
        assert _finite({k: v for k, v in doc.items() if k != "warnings"}), "a non-finite result"


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("example", _one_per_type(), ids=lambda p: p.stem)
def test_a_mutated_example_is_accepted_or_refused_with_its_file_named(example, kind, tmp_path, capsys):
    work = tmp_path / "files"
    shutil.copytree(EXAMPLES, work, ignore=shutil.ignore_patterns("studies"))
    text = example.read_text()
    model = tomllib.loads(text)["model"]["type"]
    line = _numbers(text)[len(_numbers(text)) // 2]  # a value in the middle of the file
    target = work / example.name
    target.write_text(_mutate(text, line, kind))
    _check(target, model, capsys, tmp_path)


def test_a_truncated_file_is_refused_with_its_name(tmp_path, capsys):
    for example in _one_per_type():
        target = tmp_path / example.name
        text = example.read_text()
        target.write_text(text[: len(text) // 2])
        model = tomllib.loads(text)["model"]["type"]
        _check(target, model, capsys, tmp_path)


@pytest.mark.slow
@pytest.mark.timeout(1800)  # up to 55 runs of 60 s at most each (a hang fails the run, not the suite)
@pytest.mark.parametrize("example", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.stem)
def test_every_example_mutated_every_way_in_subprocesses(example, tmp_path):
    """The whole set, an example per test (the workers share them): 9 kinds on the first six numbers
    of the example, and truncation; a run may take at most 60 s (a hang fails)."""
    failures = []
    text = example.read_text()
    model = tomllib.loads(text)["model"]["type"]
    cases = [(f"{k}@{i + 1}", _mutate(text, i, k)) for i in _numbers(text)[:6] for k in KINDS]
    cases.append(("truncated", text[: len(text) // 2]))
    for label, mutated in cases:
        work = tmp_path / "files"
        shutil.rmtree(work, ignore_errors=True)
        shutil.copytree(EXAMPLES, work, ignore=shutil.ignore_patterns("studies"))
        target = work / example.name
        target.write_text(mutated)
        argv = [sys.executable, "-m", "mechdyn", *COMMAND[model][:1], str(target), *COMMAND[model][1:]]
        argv += ["--json", "--db", str(tmp_path / "r.db")]
        try:
            p = subprocess.run(argv, capture_output=True, text=True, timeout=60)
        except subprocess.TimeoutExpired:
            failures.append(f"{example.name} {label}: hangs")
            continue
        if "Traceback" in p.stderr or p.returncode not in (0, 2):
            failures.append(f"{example.name} {label}: {p.stderr.strip().splitlines()[-1:]}")
        elif p.returncode == 2 and str(target) not in p.stderr:
            failures.append(f"{example.name} {label}: the error does not name the file: {p.stderr[:120]}")
        elif p.returncode == 0 and not _finite(json.loads(p.stdout)):
            failures.append(f"{example.name} {label}: a non-finite result")
    assert not failures, "\n".join(failures)


# -- property: any one mutation of any example file loads or is refused naming the file and the field --

ALL_EXAMPLES = sorted(EXAMPLES.glob("*.toml"))
NAME = re.compile(r'^(\s*name\s*=\s*)"([^"]+)"\s*$')
REFERENCE = re.compile(
    r"^(\s*(?:disks|disk|bodies|body|joints|points|gear_pair|mechanism|mount)\s*=\s*)(.+)$"
)
HEADER = re.compile(r"^\s*\[\[?([A-Za-z_.]+)\]\]?\s*$")
UNITS = ("mm", "kg", "N", "N/m", "Pa", "Hz", "rpm", "deg", "s", "kg*m^2", "N*m/rad", "furlong", "m/s^2", "")


def _structural(text: str, kind: str, pick: int) -> str | None:
    lines = text.splitlines()
    if kind == "duplicate name":
        names = [i for i, ln in enumerate(lines) if NAME.match(ln)]
        if len(names) < 2:
            return None
        a, b = names[pick % len(names)], names[(pick + 1) % len(names)]
        lines[b] = NAME.match(lines[b]).group(1) + f'"{NAME.match(lines[a]).group(2)}"'
    elif kind == "unknown reference":
        refs = [i for i, ln in enumerate(lines) if REFERENCE.match(ln)]
        if not refs:
            return None
        i = refs[pick % len(refs)]
        head, value = REFERENCE.match(lines[i]).groups()
        lines[i] = head + ('["nowhere", "nothing"]' if value.startswith("[") else '"nowhere"')
    elif kind == "empty table":
        headers = [i for i, ln in enumerate(lines) if HEADER.match(ln) and "model" not in ln]
        if not headers:
            return None
        i = headers[pick % len(headers)]
        j = next((k for k in range(i + 1, len(lines)) if HEADER.match(lines[k])), len(lines))
        del lines[i + 1 : j]
    return "\n".join(lines) + "\n"


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_any_mutation_loads_or_is_refused_naming_the_file_and_field(data, tmp_path):
    import warnings

    from mechdyn.errors import MechdynError, ModelWarning
    from mechdyn.io import load_model

    example = data.draw(st.sampled_from(ALL_EXAMPLES), label="example")
    text = example.read_text()
    structural = ("duplicate name", "unknown reference", "empty table")
    kind = data.draw(st.sampled_from((*KINDS, "number", *structural)), label="kind")
    pick = data.draw(st.integers(0, 1000), label="pick")
    field = None
    if kind in structural:
        mutated = _structural(text, kind, pick)
        if mutated is None:
            return
    else:
        numbers = _numbers(text)
        line = numbers[pick % len(numbers)]
        field = NUMBER.match(text.splitlines()[line]).group(1).split("=")[0].strip()
        if kind == "number":  # any float, with any unit (or none)
            value = data.draw(st.floats(allow_nan=True, allow_infinity=True), label="value")
            unit = data.draw(st.sampled_from(UNITS), label="unit")
            lines = text.splitlines()
            lines[line] = NUMBER.match(lines[line]).group(1) + f'"{value!r} {unit}"'.replace(' "', '"')
            mutated = "\n".join(lines) + "\n"
        else:
            mutated = _mutate(text, line, kind)
    work = tmp_path / f"w{pick}"
    shutil.copytree(EXAMPLES, work, ignore=shutil.ignore_patterns("studies", "gallery"), dirs_exist_ok=True)
    target = work / example.name
    target.write_text(mutated)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ModelWarning)
            load_model(target)
    except MechdynError as exc:
        message = str(exc)
        assert str(target) in message or target.name in message, message
        if field is not None and kind != "deleted":  # a check across fields may name the field in words
            assert field in message or field.replace("_", " ") in message, f"{kind} of {field!r}: {message}"


# -- outputs that cannot be written, and a database that is not one ---------------------------------


@pytest.mark.parametrize("option", ["--plots", "--csv", "--report"])
def test_an_output_that_cannot_be_written_is_one_line_and_the_run_is_kept(option, tmp_path, capsys):
    from mechdyn.store import ResultStore

    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    target = blocker / ("plots" if option == "--plots" else "out.csv" if option == "--csv" else "r.html")
    db = tmp_path / "r.db"
    code = main(["modal", str(EXAMPLES / "turret_milling.toml"), option, str(target), "--db", str(db)])
    err = capsys.readouterr().err
    assert code == 2
    assert err.strip().count("\n") == 0 and "Traceback" not in err, err
    assert str(target) in err and "is a file, not a folder" in err and "stored as run 1" in err
    with ResultStore(str(db)) as store:
        assert [r.id for r in store.runs()] == [1]


def test_a_database_path_that_is_not_a_database_is_one_line(tmp_path, capsys):
    text = tmp_path / "notes.txt"
    text.write_text("these are my notes\n" * 100)
    code = main(["modal", str(EXAMPLES / "turret_milling.toml"), "--db", str(text)])
    err = capsys.readouterr().err
    assert code == 2
    assert err.startswith("error: ") and err.strip().count("\n") == 0, err
    assert f"{text} is not a results database" in err
    assert text.read_text() == "these are my notes\n" * 100  # untouched


@pytest.mark.parametrize(
    ("example", "line", "replacement", "field"),
    [
        ("anchor_concrete.toml", "concrete_radius = ", 'concrete_radius = "0 mm"', "concrete_radius"),
        ("turret_milling.toml", "shaft_orders = ", "shaft_orders = [1, inf]", "shaft_orders"),
        ("turret_milling.toml", "mesh_orders = ", "mesh_orders = [-1]", "mesh_orders"),
    ],
)
def test_nonsense_values_once_accepted_are_refused_at_the_field(example, line, replacement, field, tmp_path):
    """A concrete block of radius 0 (taken as "not given") and an infinite or negative excitation
    order (silently dropped) were accepted."""
    from mechdyn.errors import ModelFileError
    from mechdyn.io import load_model

    lines = (EXAMPLES / example).read_text().splitlines()
    lines = [replacement if ln.startswith(line) else ln for ln in lines]
    target = tmp_path / example
    target.write_text("\n".join(lines) + "\n")
    with pytest.raises(ModelFileError, match=field):
        load_model(target)


# -- requests out of proportion ----------------------------------------------------------------------


def _chain(path: Path, n: int, shaft_field: str = "disks") -> Path:
    lines = ["[model]", 'type = "drivetrain"', 'name = "chain"']
    for i in range(n):
        lines += ["[[disks]]", f'name = "d{i}"', 'inertia = "1 kg*m^2"']
    for i in range(n - 1):
        lines += [
            "[[shafts]]",
            f'name = "s{i}"',
            f'{shaft_field} = ["d{i}", "d{i + 1}"]',
            'stiffness = "1e5 N*m/rad"',
        ]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_more_mode_shapes_than_a_run_can_keep_are_refused_before_the_work(tmp_path, capsys):
    path = _chain(tmp_path / "chain.toml", 2000)
    assert main(["modal", str(path), "--modes", "1000", "--db", str(tmp_path / "r.db")]) == 2
    out, err = capsys.readouterr()
    assert "1000 modes of a 2000-disk model are 2,000,000 shape values" in err and "at most 500" in err
    assert out == ""


@pytest.mark.slow  # CI's heavy step: 500 modes of 2000 disks solved and stored (issue 48)
def test_as_many_mode_shapes_as_a_run_can_keep_are_solved_and_stored(tmp_path, capsys):
    path = _chain(tmp_path / "chain.toml", 2000)
    assert main(["modal", str(path), "--modes", "500", "--db", str(tmp_path / "r.db"), "--json"]) == 0
    assert len(json.loads(capsys.readouterr().out)["frequencies_hz"]) == 500


def test_a_file_with_thousands_of_problems_lists_the_first_and_counts_the_rest(tmp_path, capsys):
    from mechdyn.errors import SHOWN_PROBLEMS

    path = _chain(tmp_path / "chain.toml", 300, shaft_field="between")
    assert main(["modal", str(path), "--db", str(tmp_path / "r.db")]) == 2
    err = capsys.readouterr().err
    assert f"{2 * 299} problems" in err and err.count("\n  - ") == SHOWN_PROBLEMS
    assert err.rstrip().endswith(f"… and {2 * 299 - SHOWN_PROBLEMS} more")


def test_a_module_whose_gear_is_beyond_any_machine_is_refused_at_the_module(tmp_path):
    """A module in a wrong unit can pass its own bound while the gear it makes does not: the error
    names the module the user wrote, not a radius derived from it (found by the mutation test above)."""
    from mechdyn.errors import MechdynError
    from mechdyn.io import load_model

    work = tmp_path / "w"
    shutil.copytree(EXAMPLES, work, ignore=shutil.ignore_patterns("studies", "gallery"))
    target = work / "spur_pair.toml"
    target.write_text(target.read_text().replace('module = "2 mm"', 'module = "100 m"', 1))
    with pytest.raises(MechdynError) as caught:
        load_model(target)
    message = str(caught.value)
    assert "spur_pair.toml" in message and "module" in message and "tip radius of 1100 m" in message
