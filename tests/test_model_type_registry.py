"""Model types register themselves (issue 27, point 7): each capability registers its
``[model] type`` (builder, schema, model attribute, settings, writer) next to its analyses, and
:mod:`mechdyn.io` finds every type in :mod:`mechdyn.registry`, naming none.

Every registered type has a builder and a schema and loads its examples; a type registered here, by a
fake capability, loads and saves through :func:`mechdyn.load` and :func:`mechdyn.save` without io
knowing it; the reader and writer of model files import no capability; the former
``mechdyn.io.register_model_type`` still works; listing the types imports nothing numerical.
"""

from __future__ import annotations

import ast
import subprocess
import sys
import tomllib
import warnings
from dataclasses import dataclass
from pathlib import Path

import pytest
from pydantic import BaseModel, ConfigDict

import mechdyn
import mechdyn.io.save as save_module
from conftest import EXAMPLES, ROOT
from mechdyn import registry
from mechdyn.errors import MechdynError, ModelFileError, ModelWarning
from mechdyn.io.modelfile import file_types, read_toml, schema_of, validate
from mechdyn.registry import ModelType, extend_model_type, model_types, register_model_type, resolve

CAPABILITY_PACKAGES = tuple(m.split(".")[1] for m in registry.CAPABILITIES)  # those that register types
TYPES = model_types()
MODEL_TYPES = sorted(name for name, t in TYPES.items() if t.loads)


def _examples(file_type: str) -> list[Path]:
    """The example model files whose ``[model] type`` is ``file_type``."""
    found = []
    # the examples and the measured one (examples/measured: a test with its data and model files)
    for path in sorted([*EXAMPLES.glob("*.toml"), *EXAMPLES.glob("measured/*.toml")]):
        with path.open("rb") as f:
            model = tomllib.load(f).get("model", {})
        if model.get("type") == file_type:
            found.append(path)
    return found


# -- the registered types ---------------------------------------------------------------------------


def test_the_capabilities_register_the_model_types_and_the_study_file():
    assert set(MODEL_TYPES) == {
        "drivetrain",
        "mechanism",
        "planting_mechanism",
        "support",
        "gear_pair",
        "tooth_pair",
        "mount",
        "drive",
        "measurement",
    }
    assert not TYPES["study"].loads and TYPES["study"].schema is not None
    assert file_types() == sorted([*MODEL_TYPES, "study"])


@pytest.mark.parametrize("file_type", MODEL_TYPES)
def test_every_model_type_has_a_builder_and_a_schema_and_loads_its_examples(file_type):
    kind = TYPES[file_type]
    assert kind.builder is not None and kind.schema is not None
    assert callable(resolve(kind.builder))
    schema = schema_of(file_type)
    assert issubclass(schema, BaseModel) and "model" in schema.model_fields
    examples = _examples(file_type)
    assert examples, f"no example of type {file_type!r} under examples/"
    for path in examples:
        validate(schema, read_toml(path))  # the schema takes the whole file
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ModelWarning)  # the published turret data's ratios
            loaded = mechdyn.load(path)
        assert loaded.type == file_type and loaded.source is not None
        assert loaded.model is not None and loaded.settings is not None
        if kind.model_class is not None:
            assert isinstance(loaded.model, resolve(kind.model_class))
        if kind.writer is not None:
            assert callable(resolve(kind.writer))


def test_the_study_file_is_known_by_its_schema_and_loads_its_examples():
    from mechdyn.studies import load_studies

    assert schema_of("study") is resolve("mechdyn.studies.study_file:StudyFile")
    examples = sorted((EXAMPLES / "studies").glob("*.toml"))
    assert examples
    for path in examples:
        assert load_studies(path)


def test_a_study_file_is_not_a_model_file_and_the_error_lists_the_model_types(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('[model]\ntype = "study"\n')
    expected = ", ".join(repr(t) for t in MODEL_TYPES)
    with pytest.raises(ModelFileError, match="is not a model type") as info:
        mechdyn.load(path)
    assert info.value.location == "[model] → type"
    assert str(info.value).endswith(f"'study' is not a model type; expected one of {expected}")


def test_the_drivetrain_settings_come_from_its_registration():
    kind = TYPES["drivetrain"]
    assert kind.settings == "mechdyn.gear_dynamics.file:settings" and kind.model_attribute is None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        loaded = mechdyn.load(EXAMPLES / "turret_milling.toml")
    assert loaded.settings == resolve(kind.settings)(loaded.source, loaded.model)


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"builder": "no_colon"}, "must be written 'module:name'"),
        ({"builder": "m:f", "schema": ":Class"}, "must be written 'module:name'"),
        ({"builder": "m:f", "writer": "m:w"}, "needs the model_class"),
        ({"builder": None, "model_attribute": "x"}, "loads no model"),
        ({"name": "", "builder": "m:f"}, "needs a name"),
    ],
)
def test_a_malformed_registration_is_refused(fields, message):
    with pytest.raises(ValueError, match=message):
        ModelType(**{"name": "x"} | fields)


def test_a_second_type_of_a_registered_name_is_refused():
    drivetrain = TYPES["drivetrain"]
    assert register_model_type(drivetrain) is drivetrain  # the same again: nothing happens
    with pytest.raises(ValueError, match="'drivetrain' is already registered"):
        register_model_type(ModelType("drivetrain", "elsewhere:build"))


def test_the_gear_dynamics_wing_extends_the_drivetrain_file_type():
    from mechdyn.drivetrain.schema import DrivetrainFile as Base
    from mechdyn.gear_dynamics.file import DrivetrainFile
    from mechdyn.io.modelfile import schema_of

    drivetrain = TYPES["drivetrain"]
    assert drivetrain.schema == "mechdyn.gear_dynamics.file:DrivetrainFile"
    assert drivetrain.builder == "mechdyn.drivetrain.schema:build"  # the drivetrain wing's own
    assert schema_of("drivetrain") is DrivetrainFile and issubclass(DrivetrainFile, Base)
    assert {"motor", "loads", "simulation", "speed_sweep"} <= set(DrivetrainFile.model_fields) - set(
        Base.model_fields
    )
    # extending again alike does nothing; otherwise, or an unknown type, is refused
    assert (
        extend_model_type("drivetrain", schema=drivetrain.schema, settings=drivetrain.settings) == drivetrain
    )
    with pytest.raises(ValueError, match="'drivetrain' is extended already"):
        extend_model_type("drivetrain", schema="elsewhere:File")
    with pytest.raises(ValueError, match="'gearbox' is not registered"):
        extend_model_type("gearbox", schema="elsewhere:File")


def test_a_bad_reference_names_itself():
    with pytest.raises(MechdynError, match=r"no module 'mechdyn\.nowhere'"):
        resolve("mechdyn.nowhere:build")
    with pytest.raises(MechdynError, match="has no 'nothing'"):
        resolve("mechdyn.registry:nothing")
    assert resolve("mechdyn.registry:ModelType.loads") is ModelType.loads


# -- a type that io does not know -------------------------------------------------------------------


class _WidgetTable(BaseModel):
    model_config = ConfigDict(extra="forbid")
    teeth: int


class _WidgetFile(BaseModel):
    """Schema of a fake capability's file."""

    model_config = ConfigDict(extra="forbid")
    model: dict[str, str]
    widget: _WidgetTable


@dataclass(frozen=True)
class _Widget:
    name: str
    teeth: int


@dataclass(frozen=True)
class _WidgetSpec:
    widget: _Widget
    path: str


def _build_widget(source):
    f = validate(_WidgetFile, source)
    return _WidgetSpec(_Widget(f.model["name"], f.widget.teeth), source.path)


def _widget_settings(source, record):
    return {"file": Path(source.path).name, "teeth": record.widget.teeth}


def _write_widget(model, settings, *, path, source=None):
    return f'[model]\ntype = "widget"\nname = "{model.name}"\n\n[widget]\nteeth = {model.teeth}\n'


@pytest.fixture
def own_registry(monkeypatch):
    """The registries as they are, restored after the test (the capabilities registered first, so
    that none registers into the copy and is lost)."""
    model_types()
    monkeypatch.setattr(registry, "_MODEL_TYPES", dict(registry._MODEL_TYPES))
    monkeypatch.setattr(registry, "_REGISTERED", dict(registry._REGISTERED))
    monkeypatch.setattr(save_module, "_EXTRA_WRITERS", dict(save_module._EXTRA_WRITERS))


def test_a_type_registered_outside_io_loads_and_saves_through_mechdyn(own_registry, tmp_path):
    here = __name__
    register_model_type(
        ModelType(
            "widget",
            builder=f"{here}:_build_widget",
            schema=f"{here}:_WidgetFile",
            model_attribute="widget",
            settings=f"{here}:_widget_settings",
            model_class=f"{here}:_Widget",
            writer=f"{here}:_write_widget",
        )
    )
    path = tmp_path / "w.toml"
    path.write_text('[model]\ntype = "widget"\nname = "w1"\n\n[widget]\nteeth = 12\n')
    loaded = mechdyn.load(path)
    assert loaded.type == "widget" and loaded.model == _Widget("w1", 12)
    assert loaded.settings == {"file": "w.toml", "teeth": 12} and loaded.name == "w1"
    assert schema_of("widget") is _WidgetFile and "widget" in file_types()
    # its schema's errors come back as every model file's do
    path.write_text('[model]\ntype = "widget"\nname = "w1"\n\n[widget]\nteth = 12\n')
    with pytest.raises(ModelFileError, match="did you mean 'teeth'"):
        mechdyn.load(path)
    # saved by its registered writer, and read back equal
    again = mechdyn.load(mechdyn.save(_Widget("w2", 7), tmp_path / "w2.toml"))
    assert again.model == _Widget("w2", 7)
    assert "_Widget" in save_module.writable_types()
    # the unknown-type error lists it while it is registered
    bad = tmp_path / "bad.toml"
    bad.write_text('[model]\ntype = "gadget"\n')
    with pytest.raises(ModelFileError, match=r"'gadget' is not a model type; expected one of .*'widget'"):
        mechdyn.load(bad)


def test_a_removed_type_is_no_longer_known(own_registry, tmp_path):
    register_model_type(ModelType("widget", f"{__name__}:_build_widget"))
    path = tmp_path / "w.toml"
    path.write_text('[model]\ntype = "widget"\nname = "w1"\n\n[widget]\nteeth = 12\n')
    assert mechdyn.load(path).model == _WidgetSpec(_Widget("w1", 12), str(path))
    del registry._MODEL_TYPES["widget"]
    with pytest.raises(ModelFileError, match="'widget' is not a model type"):
        mechdyn.load(path)
    with pytest.raises(KeyError, match="no schema for file type 'widget'"):
        schema_of("widget")


def test_the_former_register_model_type_still_works(own_registry, tmp_path):
    mechdyn.io.register_model_type("widget", f"{__name__}:_build_widget", f"{__name__}:_WidgetFile")
    kind = model_types()["widget"]
    assert kind == ModelType("widget", f"{__name__}:_build_widget", f"{__name__}:_WidgetFile")
    path = tmp_path / "w.toml"
    path.write_text('[model]\ntype = "widget"\nname = "w1"\n\n[widget]\nteeth = 3\n')
    loaded = mechdyn.load(path)
    # the builder's record is the model and the settings, as before
    assert loaded.model is loaded.settings and loaded.model.widget == _Widget("w1", 3)
    assert schema_of("widget") is _WidgetFile
    # without a schema: loaded, but not documented
    mechdyn.io.register_model_type("gizmo", f"{__name__}:_build_widget")
    assert "gizmo" not in file_types()
    with pytest.raises(KeyError, match="no schema for file type 'gizmo'"):
        schema_of("gizmo")
    with pytest.raises(ValueError, match="already registered"):
        mechdyn.io.register_model_type("drivetrain", f"{__name__}:_build_widget")


def test_the_former_register_writer_still_works(own_registry, tmp_path):
    register_model_type(ModelType("widget", f"{__name__}:_build_widget"))
    mechdyn.io.register_writer(f"{__name__}._Widget", f"{__name__}:_write_widget")
    assert "_Widget" in save_module.writable_types()
    assert "teeth = 5" in save_module.dumps(_Widget("w5", 5))


# -- io names no capability, and listing the types stays light --------------------------------------


def _capability_imports_and_names(path: Path) -> list[str]:
    """The capabilities a module imports (at any depth), and the non-docstring strings naming one."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    prefixes = tuple(f"mechdyn.{c}" for c in CAPABILITY_PACKAGES)
    docstrings = {
        id(node.body[0].value)
        for node in ast.walk(tree)
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef)
        and node.body
        and isinstance(node.body[0], ast.Expr)
        and isinstance(node.body[0].value, ast.Constant)
    }
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [a.name for a in node.names if a.name.startswith(prefixes)]
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ""
            if module.startswith(prefixes) or (
                module == "mechdyn" and any(a.name in CAPABILITY_PACKAGES for a in node.names)
            ):
                found.append(module)
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docstrings:
            if any(p in node.value for p in prefixes):
                found.append(repr(node.value))
    return found


IO_MODULES = sorted(p.name for p in (ROOT / "src" / "mechdyn" / "io").glob("*.py"))


@pytest.mark.parametrize("module", IO_MODULES)
def test_io_imports_and_names_no_capability(module):
    path = ROOT / "src" / "mechdyn" / "io" / module
    assert _capability_imports_and_names(path) == []


def test_the_import_check_sees_an_import_inside_a_function(tmp_path):
    path = tmp_path / "m.py"
    path.write_text(
        '"""Names mechdyn.drivetrain in its docstring only."""\n'
        "def f():\n    from mechdyn.drivetrain.schema import settings\n"
        "    import mechdyn.gears.schema\n    return 'mechdyn.mounts.schema:build'\n"
    )
    assert _capability_imports_and_names(path) == [
        "mechdyn.drivetrain.schema",
        "mechdyn.gears.schema",
        "'mechdyn.mounts.schema:build'",
    ]


def test_listing_the_model_types_imports_nothing_numerical():
    code = (
        "import sys, mechdyn.registry as r; names = list(r.model_types());"
        "heavy = {'numpy', 'scipy', 'pydantic', 'pint', 'pandas', 'matplotlib', 'sqlalchemy', 'numba'};"
        "print(len(names), sorted(heavy & {m.split('.')[0] for m in sys.modules}))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == [str(len(TYPES)), "[]"]
