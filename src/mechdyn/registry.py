"""The registry of analyses and model types: each is registered once, and everything else finds it here.

An :class:`Analysis` names the model types it runs on, the function that runs it, its options (with
units and help) and the summary keys its result documents. The command line builds one subcommand
per analysis from this, the results store records its name and options, and design studies and
reports look analyses up by name. Adding an analysis is one function returning a
:class:`mechdyn.results.Result` and one :func:`register` call in its capability's ``analyses``
module.

A :class:`ModelType` says how the files of one ``[model] type`` are validated, built into a model
and its settings, and written back; the capability registers it with :func:`register_model_type`
next to its analyses, and :mod:`mechdyn.io` finds it through :func:`model_types` (the reader and
writer of model files name no capability).

This module and the registration modules import no numerical library, so that listing analyses and
model types and ``mechdyn --help`` start at once; the analysis function imports what it runs, and a
model type names its builder, schema and writer as ``"module:name"`` strings imported when used.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any, Literal

from mechdyn.errors import MechdynError

__all__ = [
    "Analysis",
    "LoadedModel",
    "ModelType",
    "NotBatchable",
    "Option",
    "Output",
    "analyses",
    "extend_model_type",
    "get",
    "model_scatter",
    "model_types",
    "register",
    "register_model_type",
    "resolve",
    "summary_columns",
]

# The modules in which the capabilities register their analyses and model types (the studies their
# file type), imported on first look-up.
CAPABILITIES = (
    "mechdyn.drivetrain.analyses",
    "mechdyn.gear_dynamics.analyses",
    "mechdyn.mechanism.analyses",
    "mechdyn.support.analyses",
    "mechdyn.gears.analyses",
    "mechdyn.mounts.analyses",
    "mechdyn.drive.analyses",
    "mechdyn.balance.analyses",
    "mechdyn.measurement.analyses",
    "mechdyn.studies.file_type",
)


class NotBatchable(MechdynError):
    """An analysis' batch evaluation cannot take these variants (a design study then evaluates
    them one by one, with the same results)."""


OptionKind = Literal["flag", "int", "float", "quantity", "choice", "text", "names"]


@dataclass(frozen=True)
class Option:
    """One option of an analysis: a keyword of its function and a ``--flag`` of its command.

    Attributes
    ----------
    name : str
        Keyword argument (``rigid_gears``); the command-line flag is ``--rigid-gears``.
    kind : {"flag", "int", "float", "quantity", "choice", "text", "names"}
        ``quantity`` values are read with units and converted to ``unit``; ``names`` is a list of
        words (disk names, say).
    help : str
        One line for ``--help``.
    unit : str, optional
        SI unit of a ``quantity`` option (what the function receives).
    nargs : int, optional
        Number of values (2 for a range); one value when None.
    choices : tuple of str
        Allowed values of a ``choice`` option.
    default : Any
        Value when the option is not given (None: the model file's setting, else the function's).
    minimum : float, optional
        Smallest allowed value of an ``int`` or ``float`` option, in the option's ``unit``.
    metavar : str or tuple of str, optional
        Placeholder(s) in ``--help``.
    writes : bool
        The option names a file the analysis writes (``--write-updated PATH``): not stored with the
        run's parameters, so that a report, which runs a stored run again, writes nothing.
    """

    name: str
    kind: OptionKind
    help: str
    unit: str | None = None
    nargs: int | None = None
    choices: tuple[str, ...] = ()
    default: Any = None
    minimum: float | None = None
    metavar: str | tuple[str, ...] | None = None
    writes: bool = False

    def __post_init__(self) -> None:
        if self.kind == "quantity" and not self.unit:
            raise ValueError(f"option {self.name!r}: a quantity option needs its SI unit")

    @property
    def flag(self) -> str:
        return "--" + self.name.replace("_", "-")

    def describe(self) -> dict[str, Any]:
        """JSON-ready description (``mechdyn analyses --json``)."""
        d: dict[str, Any] = {"name": self.name, "flag": self.flag, "kind": self.kind, "help": self.help}
        for key in ("unit", "nargs", "default", "minimum"):
            if getattr(self, key) is not None:
                d[key] = getattr(self, key)
        if self.choices:
            d["choices"] = list(self.choices)
        return d


@dataclass(frozen=True)
class Output:
    """A summary key of an analysis' result, its unit and what it means.

    The unit is read from the key's suffix (:func:`mechdyn.units.key_unit`) unless given; keys
    without a unit (counts, names, flags, nested tables) say so with ``unit=""``.

    Parameters
    ----------
    key : str
        The summary key, ending with its unit (``stroke_m``).
    description : str
        What it means, for ``mechdyn analyses`` and the documentation.
    unit : str, optional
        Its SI unit, when the key's suffix does not give it (``""`` for none).
    """

    key: str
    description: str
    unit: str | None = None

    def __post_init__(self) -> None:
        if self.unit is None:
            from mechdyn.units import key_unit

            unit = key_unit(self.key)
            if unit is None:
                raise ValueError(
                    f"summary key {self.key!r} has no unit suffix; end it with its unit (e.g. _N, _m) "
                    'or give unit="" for a count, name, flag or table'
                )
            object.__setattr__(self, "unit", unit)

    def describe(self) -> dict[str, Any]:
        """JSON-ready description: key, unit and meaning."""
        return {"key": self.key, "unit": self.unit, "description": self.description}


@dataclass(frozen=True)
class Analysis:
    """A registered analysis.

    Attributes
    ----------
    name : str
        Its name, also its command (``mechdyn NAME FILE``).
    model_types : tuple of str
        The ``[model] type`` values of the files it runs on.
    function : callable
        ``function(loaded, **options) -> Result``, where ``loaded`` is the
        :class:`mechdyn.io.LoadedModel` of a file of one of ``model_types``.
    help : str
        One line for ``mechdyn --help`` and ``mechdyn analyses``.
    options : tuple of Option
    outputs : tuple of Output
        Every key its result's ``summary()`` can hold.
    examples : tuple of str
        Command lines shown at the end of ``--help``.
    uses_store : bool
        The function takes ``store=`` (the results database), e.g. to read or keep a calibration.
    model_noun : str
        What its models are called in messages (default: the first model type).
    batch : callable, optional
        ``batch(loaded, columns, keys, **options) -> (outputs, errors)``: many variants of one model
        at once, for design studies. ``columns`` maps ``(files, keys)`` of a model value
        (:class:`mechdyn.studies.paths.Location` without its path) to its SI values over V
        variants; ``outputs`` maps each wanted summary key (nested with dots) to V values (NaN for
        a failed variant); ``errors`` holds each variant's error message or None. It raises
        :class:`NotBatchable` for a value or output it does not handle; it must give what
        :meth:`run` would give variant by variant.
    headline : tuple of str
        The few summary keys a report names first (a press's stroke, peak torque and shaking force);
        keys a result does not have are passed over.
    animates : bool
        Its result has ``animate(path, frames=…)`` (a linkage over one crank cycle): the command takes
        ``--animate PATH`` and the report shows the animation.
    """

    name: str
    model_types: tuple[str, ...]
    function: Callable[..., Any]
    help: str
    options: tuple[Option, ...] = ()
    outputs: tuple[Output, ...] = ()
    examples: tuple[str, ...] = ()
    uses_store: bool = False
    model_noun: str = ""
    batch: Callable[..., Any] | None = None
    headline: tuple[str, ...] = ()
    animates: bool = False

    @property
    def output_units(self) -> dict[str, str]:
        """Summary key → unit."""
        return {o.key: o.unit or "" for o in self.outputs}

    def output_unit(self, key: str) -> str:
        """The SI unit of one of the analysis' outputs, by its key: a registered output, or a value
        inside one named with dots (``joint_force_peak_N.F``, ``natural_frequencies_hz.1``), whose
        own key suffix names its unit where it has one.

        Parameters
        ----------
        key : str
            The output's key.

        Returns
        -------
        str
            The unit's text (``"N"``, ``"Hz"``), ``""`` for a number without unit.

        Raises
        ------
        LookupError
            A key whose head is not a registered output (naming the nearest and listing them all).
        """
        import difflib

        from mechdyn.units import key_unit

        outputs = self.output_units
        head = key.split(".")[0]
        if head not in outputs:
            near = difflib.get_close_matches(head, list(outputs), n=3)
            raise LookupError(
                f"{key!r} is not an output of the {self.name} analysis"
                + (f"; did you mean {', '.join(near)}?" if near else "")
                + f" Its outputs: {', '.join(outputs)}"
            )
        si = key_unit(key.split(".")[-1]) or outputs[head] or ""
        return "" if si == "1" else si

    def run(self, model: Any, **options: Any) -> Any:
        """Run the analysis with the given options (None means "not given").

        Parameters
        ----------
        model : LoadedModel or model object
            A loaded model file (:func:`mechdyn.io.load_model`), or a model built in Python (then
            taken as of the analysis' first model type, with no file settings).
        **options
            The analysis' options by name, SI.
        """
        if not isinstance(model, LoadedModel):
            model = LoadedModel(self.model_types[0], model)
        if model.type not in self.model_types:
            where = model.source.path if model.source is not None else repr(model.name)
            from mechdyn.errors import ModelFileError

            needs = " or ".join(f'type = "{t}"' for t in self.model_types)
            noun = self.model_noun or self.model_types[0]
            raise ModelFileError(
                where, "[model] → type", f"{model.type!r} is not a {noun} model; this command needs {needs}"
            )
        kw = {k: v for k, v in options.items() if v is not None}
        unknown = set(kw) - {o.name for o in self.options} - ({"store"} if self.uses_store else set())
        if unknown:
            raise MechdynError(
                f"analysis {self.name!r} has no option {', '.join(repr(u) for u in sorted(unknown))}; "
                f"its options: {', '.join(o.name for o in self.options) or 'none'}"
            )
        return self.function(model, **kw)

    def describe(self) -> dict[str, Any]:
        """JSON-ready description: name, model types, options and summary keys with units."""
        return {
            "name": self.name,
            "model_types": list(self.model_types),
            "help": self.help,
            "options": [o.describe() for o in self.options],
            "outputs": [o.describe() for o in self.outputs],
        }


_REGISTRY: dict[str, Analysis] = {}


def register(analysis: Analysis) -> Analysis:
    """Add an analysis to the registry (its name must be new); returns it.

    Parameters
    ----------
    analysis : Analysis
        The analysis, with its options and outputs.
    """
    if analysis.name in _REGISTRY and _REGISTRY[analysis.name] is not analysis:
        raise ValueError(f"an analysis named {analysis.name!r} is already registered")
    _REGISTRY[analysis.name] = analysis
    return analysis


def _import_capabilities() -> None:
    for module in CAPABILITIES:
        importlib.import_module(module)


def analyses() -> Mapping[str, Analysis]:
    """Every registered analysis by name, in registration order."""
    _import_capabilities()
    return dict(_REGISTRY)


def get(name: str) -> Analysis:
    """The analysis called ``name``; an error lists the registered names.

    Parameters
    ----------
    name : str
        A registered analysis (``mechdyn analyses`` lists them).
    """
    found = analyses()
    if name not in found:
        raise MechdynError(f"no analysis named {name!r}; registered: {', '.join(found)}")
    return found[name]


def resolve(reference: str) -> Any:
    """The object that a lazy ``"module:name"`` reference names, its module imported now.

    Parameters
    ----------
    reference : str
        ``"module:name"`` (``"mechdyn.drivetrain.schema:build"``); ``name`` may be dotted
        (``"module:Class.method"``).

    Raises
    ------
    MechdynError
        When the module or the name is not found, naming the reference.
    """
    module, sep, name = reference.partition(":")
    if not sep or not module or not name:
        raise MechdynError(f"{reference!r} is not a reference; write it as 'module:name'")
    try:
        obj: Any = importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name is None or not (module == exc.name or module.startswith(exc.name + ".")):
            raise  # a module that the named one imports is missing: not this reference's fault
        raise MechdynError(f"{reference!r}: no module {module!r}") from None
    for part in name.split("."):
        if not hasattr(obj, part):
            raise MechdynError(f"{reference!r}: module {module!r} has no {name!r}")
        obj = getattr(obj, part)
    return obj


SCATTER_READER = "mechdyn.studies.model_scatter:read_scatter"
"""Who reads a model file's ``[[scatter]]`` and ``[[correlations]]``: the studies, whose path resolver
and parameter reader make the rows' variables (:mod:`mechdyn.io.scatter` describes and writes the
tables). Named here, as the capabilities are, so that the files beneath the studies reach it."""


def model_scatter(source: Any) -> Any:
    """The scatter a model file gives its values, checked (:data:`SCATTER_READER`); None without
    ``[[scatter]]`` rows.

    Parameters
    ----------
    source : mechdyn.io.modelfile.ModelSource
        The parsed model file.

    Returns
    -------
    mechdyn.studies.model_scatter.ModelScatter or None

    Raises
    ------
    ModelFileError
        Naming the file, the row and field, the value and the fix
        (:func:`mechdyn.studies.model_scatter.read_scatter`).
    """
    return resolve(SCATTER_READER)(source)


def _check_reference(owner: str, field: str, value: str | None) -> None:
    if value is not None:
        module, sep, name = value.partition(":")
        if not (sep and module and name):
            raise ValueError(f"model type {owner!r}: {field} {value!r} must be written 'module:name'")


@dataclass(frozen=True)
class ModelType:
    """A model-file type: how the files of one ``[model] type`` are validated, loaded and saved.

    Every reference is a ``"module:name"`` string, imported when a file of the type is first loaded,
    documented or saved, so that registering a type imports nothing numerical. A file of the type
    loads (:func:`mechdyn.load`) as ``record = builder(source)``; the
    :class:`mechdyn.io.LoadedModel`'s ``model`` is ``record.<model_attribute>`` (the record itself
    when no attribute is named) and its ``settings`` is ``settings(source, record)`` (the record
    itself when no function is named).

    Attributes
    ----------
    name : str
        The type as files name it, ``[model] type = name``.
    builder : str or None
        ``"module:function"``; ``function(source)`` builds the record of a
        :class:`mechdyn.io.ModelSource` of the type (the model and the file's settings). None for a
        file type that holds no model (the study file): its schema is known to
        :func:`mechdyn.io.modelfile.schema_of`, ``mechdyn fields`` and ``mechdyn new``, but
        :func:`mechdyn.load` does not take it.
    schema : str or None
        ``"module:Class"``, the pydantic schema that validates a whole file of the type, for
        :func:`mechdyn.io.modelfile.schema_of`, ``mechdyn fields``, ``mechdyn new`` and the
        documentation's model-file reference.
    model_attribute : str or None
        The attribute of the builder's record that is the model the analyses run on; None when the
        record is the model.
    settings : str or None
        ``"module:function"``; ``function(source, record)`` reads the file's settings (analysis
        tables) when the record does not hold them; None when the record is the settings.
    model_class : str or None
        ``"module:Class"`` of the model, so that :func:`mechdyn.save` finds the writer of a model
        built in Python (or says, for a type without a writer, that its files are written by hand).
    writer : str or None
        ``"module:function"`` that writes a model of ``model_class`` as a file of the type:
        ``function(model, settings, *, path, source, **options)`` returns the file's text
        (``settings`` is the loaded file's settings, or None for a model built in Python).
    """

    name: str
    builder: str | None
    schema: str | None = None
    model_attribute: str | None = None
    settings: str | None = None
    model_class: str | None = None
    writer: str | None = None

    def __post_init__(self) -> None:
        if not self.name or not isinstance(self.name, str):
            raise ValueError(f"a model type needs a name, not {self.name!r}")
        for field in ("builder", "schema", "settings", "model_class", "writer"):
            _check_reference(self.name, field, getattr(self, field))
        if self.writer is not None and self.model_class is None:
            raise ValueError(f"model type {self.name!r}: a writer needs the model_class it writes")
        if self.builder is None and (self.model_attribute or self.settings or self.writer):
            raise ValueError(f"model type {self.name!r}: a file type without a builder loads no model")

    @property
    def loads(self) -> bool:
        """Whether :func:`mechdyn.load` builds a model from files of this type (it has a builder)."""
        return self.builder is not None


_MODEL_TYPES: dict[str, ModelType] = {}  # as extended (what files of the type are read with)
_REGISTERED: dict[str, ModelType] = {}  # as their capability registered them


def register_model_type(model_type: ModelType) -> ModelType:
    """Add a model-file type to the registry; returns it.

    A capability calls this in its ``analyses`` module, next to its analyses' :func:`register`.
    Registering the same record again (or the type as extended) does nothing; another record under a
    registered name is an error.

    Parameters
    ----------
    model_type : ModelType
        The type, its builder and schema, and how its model, settings and writer are found.

    Raises
    ------
    ValueError
        When another type of that name is registered.
    """
    existing = _REGISTERED.get(model_type.name)
    if existing is not None and model_type not in (existing, _MODEL_TYPES[model_type.name]):
        raise ValueError(f"a model type named {model_type.name!r} is already registered")
    if existing is None:
        _REGISTERED[model_type.name] = model_type
    _MODEL_TYPES.setdefault(model_type.name, model_type)
    return model_type


def extend_model_type(name: str, *, schema: str | None = None, settings: str | None = None) -> ModelType:
    """Let another capability add tables to a registered file type; returns the extended type.

    The gear-dynamics wing adds a drivetrain file's time tables this way, so that the drivetrain
    wing knows nothing of them: ``schema`` is a subclass of the type's schema that validates the
    whole file (the builder validates with :func:`mechdyn.io.modelfile.schema_of`, which answers the
    extended one), and ``settings`` reads the type's own settings and adds what the new tables say.
    Extending again with the same references does nothing.

    Parameters
    ----------
    name : str
        A registered model type (``"drivetrain"``); the capability that registers it must be
        imported first.
    schema, settings : str, optional
        ``"module:name"`` references that replace the type's (None: keep it).

    Raises
    ------
    ValueError
        For a type not registered, or one extended already with other references.
    """
    base = _REGISTERED.get(name)
    if base is None:
        raise ValueError(
            f"model type {name!r} is not registered; import the capability that registers it first"
        )
    extended = replace(
        base,
        schema=schema if schema is not None else base.schema,
        settings=settings if settings is not None else base.settings,
    )
    current = _MODEL_TYPES[name]
    if current != base and current != extended:
        raise ValueError(f"model type {name!r} is extended already ({current.schema}, {current.settings})")
    _MODEL_TYPES[name] = extended
    return extended


def model_types() -> Mapping[str, ModelType]:
    """Every registered model-file type by name, in registration order (the study file included,
    as a type without a builder).

    The registration modules (:data:`CAPABILITIES`) are imported on the first call; they import no
    numerical library.
    """
    _import_capabilities()
    return dict(_MODEL_TYPES)


def summary_columns(summary: Mapping[str, Any], keys: Sequence[str], V: int) -> dict[str, Any]:
    """The wanted keys (nested with dots) of a batch summary, each an ndarray of V values.

    Parameters
    ----------
    summary : mapping
        A batch evaluation's figures, nested as the analysis' ``summary()`` (a list as a mapping of
        ``"1"``, ``"2"``, … to its entries), each leaf V values in the output's unit.
    keys : sequence of str
        The summary keys a study reads.
    V : int
        The number of variants.

    Raises
    ------
    NotBatchable
        For a key the batch summary does not hold.
    """
    import numpy as np

    out = {}
    for key in keys:
        node: Any = summary
        for part in key.split("."):
            if not isinstance(node, Mapping) or part not in node:
                raise NotBatchable(f"the batch does not compute {key}")
            node = node[part]
        arr = np.asarray(node, dtype=float)
        if arr.shape != (V,):
            raise NotBatchable(f"{key} is not one number per variant")
        out[key] = arr
    return out


@dataclass(frozen=True)
class LoadedModel:
    """A model file as loaded: the model, the file's analysis settings, and the file itself.

    Attributes
    ----------
    type : str
        The file's ``[model] type``.
    model : object
        The immutable model the analyses run on (a :class:`~mechdyn.drivetrain.Drivetrain`, a
        :class:`~mechdyn.mechanism.Mechanism`, a :class:`~mechdyn.support.MountedMachine`, a
        :class:`~mechdyn.gears.GearPair`, two teeth, a mount estimate).
    settings : object
        What else the file says (analysis tables, load, samples): its builder's record, or what its
        type's settings function reads (:class:`mechdyn.registry.ModelType`).
    source : ModelSource or None
        The file (None for a model built in Python).
    """

    type: str
    model: Any
    settings: Any = None
    source: Any = None  # a mechdyn.io.modelfile.ModelSource (the registry stands below the files)

    @property
    def name(self) -> str:
        return str(getattr(self.model, "name", "") or getattr(self.settings, "name", ""))

    @property
    def scatter(self) -> Any:
        """How the file says its values scatter: its ``[[scatter]]`` and ``[[correlations]]`` rows as
        a :class:`mechdyn.studies.model_scatter.ModelScatter` (``.space`` is their
        :class:`mechdyn.uncertainty.InputSpace`); None for a file without them or a model built in
        Python. No analysis reads it; a ``tolerance`` study on the file takes it as its default."""
        if self.source is None:
            return None
        return model_scatter(self.source)
