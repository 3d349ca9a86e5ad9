"""Saving models built in Python as model files that :func:`mechdyn.load` reads back equal.

Each model type names the class of its model and its writer (a function that returns the text of the
file) in its registration (:class:`mechdyn.registry.ModelType`); :func:`register_writer` adds a writer
for a model class outside them. Every float is written as its ``repr`` with its SI unit
(``"0.02 kg*m^2"``), so reading the file back gives the same floats and an equal model. The writers
are imported when first used.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from mechdyn.errors import MechdynError
from mechdyn.registry import model_types, resolve

__all__ = ["dumps", "register_writer", "save", "writable_types"]

# "module:Class" of a model -> "module:function" returning the text of its model file, for the writers
# registered with register_writer (those of the model types are in their registrations)
_EXTRA_WRITERS: dict[str, str] = {}


def register_writer(model_class: str, writer: str) -> None:
    """Register the writer of a model class, for :func:`mechdyn.save` (a model type names its writer
    in its :class:`mechdyn.registry.ModelType`; this is for a class outside them).

    Parameters
    ----------
    model_class : str
        ``"module.Class"`` (or ``"module:Class"``) of the model (``"mypackage.model.Pump"``);
        subclasses use it too. It takes precedence over a model type's writer of the same class.
    writer : str
        ``"module:function"``; ``function(model, settings, *, path, source, **options)`` returns the
        file's text. ``settings`` is the loaded file's record (:attr:`mechdyn.io.LoadedModel.settings`)
        or None for a model built in Python; ``path`` the file to be written (for relative paths);
        ``source`` the file it was loaded from, or None.

    Raises
    ------
    ValueError
        For a class not given with its module.
    """
    module, colon, name = model_class.partition(":")
    if not colon:  # "module.Class"
        module, _, name = model_class.rpartition(".")
    if not module or not name:
        raise ValueError(f"{model_class!r}: give the model class as 'module.Class'")
    _EXTRA_WRITERS[f"{module}:{name}"] = writer


def _writers() -> dict[str, str]:
    """``"module:Class"`` of a model → its writer: the model types' (in registration order), then
    those registered with :func:`register_writer`."""
    found = {t.model_class: t.writer for t in model_types().values() if t.model_class and t.writer}
    return found | _EXTRA_WRITERS


def writable_types() -> list[str]:
    """The model classes :func:`mechdyn.save` can write, by name (``"Drivetrain"``, …).

    Returns
    -------
    list of str
        Their class names.
    """
    return list(dict.fromkeys(name.partition(":")[2] for name in _writers()))


def _writer(model: Any) -> Callable[..., str]:
    writers = _writers()
    classes = [f"{cls.__module__}:{cls.__qualname__}" for cls in type(model).__mro__]
    for name in classes:
        where = writers.get(name)
        if where is not None:
            writer: Callable[..., str] = resolve(where)
            return writer
    kinds = ", ".join(writable_types())
    hint = ""
    # a type whose model this is, but that has no writer: its files are written by hand
    by_hand = [t.name for t in model_types().values() if t.model_class in classes]
    if by_hand:
        kind = by_hand[0]
        hint = f"; a {kind}'s file is written by hand for now (`mechdyn new {kind}` gives a template)"
    raise MechdynError(
        f"mechdyn.save: cannot write a {type(model).__module__}.{type(model).__qualname__} to a model file; "
        f"it writes a {kinds}, or a model loaded with mechdyn.load{hint}"
    )


def dumps(model: Any, *, path: str | Path | None = None, **options: Any) -> str:
    """The text of the model file of ``model`` (what :func:`save` writes).

    Parameters
    ----------
    model : Drivetrain, Mechanism, MountedMachine, GearPair or LoadedModel
        A model built in Python, or a loaded model file (:func:`mechdyn.load`; its analysis settings
        and its ``[[scatter]]`` are written too).
    path : str or Path, optional
        Where the file will be: a file it refers to (a support's mechanism) is named relative to it.
    **options
        What the writer of the model's type takes besides the model: ``load`` (a
        :class:`mechdyn.support.PeriodicLoad`) for a :class:`mechdyn.support.MountedMachine`.

    Returns
    -------
    str
        The TOML text.

    Raises
    ------
    MechdynError
        For a model type that has no writer, naming it and the types that have one.
    """
    from mechdyn.io.modelfile import LoadedModel

    settings = None
    source = None
    if isinstance(model, LoadedModel):
        model, settings, source = model.model, model.settings, model.source
    writer = _writer(model)
    target = Path(path) if path is not None else Path("model.toml")
    text = writer(model, settings, path=target, source=source, **options)
    return text + _scatter(text, target if path is not None else None, source)


def _scatter(text: str, target: Path | None, source: Any) -> str:
    """The loaded file's ``[[scatter]]`` and ``[[correlations]]`` (:mod:`mechdyn.io.scatter`), to be
    written after the model's own tables, checked against the file written (when its place is known:
    the files it refers to are named relative to it)."""
    from mechdyn.io.scatter import check_written, scatter_text

    extra = scatter_text(source)
    if not extra:
        return ""
    extra = "\n" + extra
    if target is not None:
        check_written(text + extra, str(target), source)
    return extra


def save(model: Any, path: str | Path, **options: Any) -> Path:
    """Write a model to a model file that :func:`mechdyn.load` reads back equal.

    Every float is written as its ``repr`` in its SI unit (``inertia = "0.02 kg*m^2"``), so the model
    that :func:`mechdyn.load` builds from the file equals ``model`` (dataclass equality). A drivetrain's
    elements come back grouped as the file lists them (shafts, meshes, grounded springs, grounded
    dampers), each group in the model's order. An existing file is overwritten.

    Parameters
    ----------
    model : Drivetrain, Mechanism, MountedMachine, GearPair or LoadedModel
        A :class:`mechdyn.drivetrain.Drivetrain`; a :class:`mechdyn.mechanism.Mechanism`; a
        :class:`mechdyn.support.MountedMachine` with its ``load``; a :class:`mechdyn.gears.GearPair`;
        or a model file loaded with :func:`mechdyn.load`, whose analysis settings (a drivetrain's
        ``[campbell]`` and ``[response]``, a mechanism's angles and traced points, a support's
        excitation and ``[analysis]``, a gear pair's ``[mesh]``) are written too, and its
        ``[[scatter]]`` and ``[[correlations]]`` as the file gives them.
    path : str or Path
        The model file to write (TOML).
    **options
        ``load`` (a :class:`mechdyn.support.PeriodicLoad`: a vertical force, or unbalanced rotors) for
        a :class:`mechdyn.support.MountedMachine` built in Python.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    MechdynError
        For a model type that cannot be written, naming it and the types that can; for a
        mechanism's part given as a Python function (a process force, a speed profile, a pitch curve
        of its own) that no table of the file can hold; for a model the file format cannot hold (a
        support load with horizontal components that came from no mechanism file, say), saying what
        it can hold; for a ``[[scatter]]`` row whose value the saved file writes in another form.

    Examples
    --------
    >>> import mechdyn
    >>> from mechdyn.drivetrain import Disk, Drivetrain, Shaft
    >>> disks = (Disk("motor", 0.02), Disk("load", 0.5))
    >>> model = Drivetrain(disks, (Shaft("shaft", ("motor", "load"), 2e4),))
    >>> path = mechdyn.save(model, "two_disks.toml")  # doctest: +SKIP
    >>> mechdyn.load(path).model == model  # doctest: +SKIP
    True
    """
    target = Path(path)
    if target.is_dir():
        raise MechdynError(f"mechdyn.save: {target} is a folder; give the path of the model file to write")
    if not target.parent.is_dir():
        raise MechdynError(f"mechdyn.save: {target.parent} is not a folder; create it or give another path")
    text = dumps(model, path=target, **options)
    target.write_text(text, encoding="utf-8")
    return target


def model_header(kind: str, name: str, source: Any = None) -> dict[str, Any]:
    """The ``[model]`` table of a saved file: its type and name, and the description and source of
    the file it was loaded from, if any.

    Parameters
    ----------
    kind : str
        The ``[model] type``.
    name : str
        The model's name.
    source : ModelSource, optional
        The file the model was loaded from.
    """
    table: dict[str, Any] = {"type": kind, "name": name}
    if source is not None:
        given = source.data.get("model", {})
        for key in ("description", "source"):
            if given.get(key):
                table[key] = given[key]
    return table


def written_by(what: str) -> str:
    """The first comment of a saved file.

    Parameters
    ----------
    what : str
        What the file holds (``"a drivetrain"``).
    """
    return (
        f"{what}, written by mechdyn.save: every quantity in SI, each float written in full\n"
        "(Python's repr), so that mechdyn.load reads back the same model."
    )
