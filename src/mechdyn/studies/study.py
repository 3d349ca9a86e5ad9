"""A design study: the base model, the analysis, the parameters, what to look at, and how to search.

A study is read from a study file (TOML; see ``examples/studies/``) with :func:`load_study`, or
built in Python with :class:`Study`. Every error names the study file and the field.

.. code-block:: toml

    [study]
    name = "press-support-influence"
    kind = "oat"                     # oat, factorial, lhs, sobol, optimize, synthesis, tolerance
    model = "../press_on_support.toml"
    analysis = "support"

    [[parameters]]
    path = "support.stiffness"
    levels = ["-10 %", "-20 %", "-30 %"]

    [[outputs]]
    output = "transmitted_force_range_N"
    unit = "tonf"
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from mechdyn.io.modelfile import ModelSource, read
from mechdyn.studies.errors import StudyError
from mechdyn.studies.outputs import Constraint, Objective, Watched
from mechdyn.studies.parameters import Parameter
from mechdyn.studies.paths import ModelTree, PathError
from mechdyn.studies.plan import Study
from mechdyn.studies.study_file import ConstraintRow, OutputRow, StudyFile

__all__ = ["Study", "analysis_options", "load_studies", "load_study", "study_from_data"]


def _validation_error(path: str, exc: ValidationError) -> StudyError:
    problems = []
    for err in exc.errors():
        loc = " → ".join(str(p) if not isinstance(p, int) else f"#{p + 1}" for p in err["loc"])
        msg = err["msg"]
        if err["type"] == "extra_forbidden":
            msg = "unknown field"
        value = err.get("input")
        shown = "" if isinstance(value, (dict, list)) or value is None else f" (got {value!r})"
        problems.append(f"{loc}: {msg}{shown}")
    return StudyError(f"{path}: " + "; ".join(problems))


def _watched(analysis: Any, key: str, unit: str, where: str) -> Watched:
    """An output of the analysis, checked against what its summary holds."""
    from mechdyn.units import UnitError, convert

    try:
        si = analysis.output_unit(key)
    except LookupError as exc:
        raise StudyError(f"{where}: {exc.args[0]} (nested values with dots: joint_force_peak_N.F)") from None
    if unit:
        try:
            convert(1.0, si or "", unit)
        except UnitError:
            raise StudyError(
                f"{where}: unit {unit!r} cannot show {key!r}, which is in {si or 'no unit'}"
            ) from None
    return Watched(key, si, unit)


def _quantity(w: Watched, value: Any, what: str, where: str) -> float | None:
    from mechdyn.units import UnitError, to_si

    if value is None:
        return None
    try:
        return to_si(value, w.unit or "")
    except UnitError as exc:
        raise StudyError(
            f"{where}: {what} {value!r} of {w.key!r} needs a quantity in {w.unit or 'no unit'}: {exc}"
        ) from None


def _limit(w: Watched, row: OutputRow, where: str) -> Any:
    """An output row's limit (``tolerance``) as a :class:`mechdyn.uncertainty.Limit`, SI."""
    from mechdyn.uncertainty import Limit

    value = _quantity(w, row.limit, "limit", where)
    return Limit(w.key, float(value), row.side) if value is not None else None


def _constraint(
    analysis: Any, row: ConstraintRow, where: str, target: bool = False, limits: tuple[Any, ...] = ()
) -> Constraint:
    from mechdyn.studies.kinds.robust import statistic_of

    statistic = getattr(row, "statistic", None)  # a constraint's (robust design), never a target's
    w = statistic_of(_watched(analysis, row.output, row.unit, where), statistic, limits, where)
    c = Constraint(
        w,
        max=_quantity(w, row.max, "max", where),
        min=_quantity(w, row.min, "min", where),
        equals=_quantity(w, row.equals, "equals", where),
        tolerance=_quantity(w, row.tolerance, "tolerance", where),
    )
    if target and (c.equals is None or not c.tolerance):
        raise StudyError(
            f'{where}: a target needs equals and a tolerance, e.g. equals = "1496 mm", tolerance = "1 mm"'
        )
    if c.max is None and c.min is None and c.equals is None:
        raise StudyError(f"{where}: give max, min, or equals (with a tolerance)")
    if c.tolerance is not None and not c.tolerance > 0:
        raise StudyError(f"{where}: tolerance {row.tolerance!r} must be above zero")
    if c.equals is not None and c.tolerance is None:
        raise StudyError(
            f"{where}: equals {row.equals!r} needs a tolerance (an output computed in floating point never "
            'holds a value exactly), e.g. tolerance = "1 mm"'
        )
    if c.equals is not None and (c.min is not None or c.max is not None):
        raise StudyError(f"{where}: give equals (with a tolerance) or min/max, not both")
    if c.min is not None and c.max is not None and not c.min < c.max:
        raise StudyError(f"{where}: min {row.min!r} must be below max {row.max!r}")
    return c


def load_study(path: str | Path) -> Study:
    """Read a study file.

    Parameters
    ----------
    path : str or Path
        A TOML study file (``[study]``, ``[[parameters]]``, ``[[outputs]]``, ``[[objectives]]``,
        ``[[constraints]]``, ``[[targets]]``).

    Returns
    -------
    Study

    Raises
    ------
    StudyError
        Naming the file and the field: an unknown parameter path lists the valid paths nearby, an
        unknown output lists the analysis' outputs, a range with the wrong unit says which it needs.
    """
    from mechdyn.io.modelfile import read_toml

    src = read_toml(path, "a .toml study file")
    boxes = src.data.get("study", {}).get("boxes") if isinstance(src.data.get("study"), dict) else None
    if boxes:
        raise StudyError(
            f"{src.path}: [study] → boxes: the file holds {len(boxes)} studies, one per box; read it with "
            "load_studies (mechdyn study runs them all)"
        )
    return study_from_data(src.path, src.data)


def load_studies(path: str | Path) -> list[Study]:
    """The studies of a study file: one, or one per box of ``[study] boxes`` (named ``NAME ±10 %``),
    in which every parameter with ``range = "box"`` takes the box as its range.

    Parameters
    ----------
    path : str or Path
        The study file.

    Raises
    ------
    StudyError
        As :func:`load_study`; also a box that is not a relative range, or boxes without a
        parameter of ``range = "box"``.
    """
    import copy

    from mechdyn.io.modelfile import read_toml
    from mechdyn.studies.parameters import parse_relative

    src = read_toml(path, "a .toml study file")
    try:  # the file as a whole first: a box's study is then built from valid rows
        StudyFile.model_validate(src.data)
    except ValidationError as exc:
        raise _validation_error(src.path, exc) from None
    table = src.data.get("study")
    boxes = table.get("boxes") if isinstance(table, dict) else None
    if not boxes or not isinstance(table, dict):
        return [study_from_data(src.path, src.data)]
    rows = src.data.get("parameters") or []
    if not any(isinstance(r, dict) and r.get("range") == "box" for r in rows):
        raise StudyError(f'{src.path}: [study] → boxes: give the parameters that take them range = "box"')
    out = []
    for box in boxes:
        r = parse_relative(box)
        if r is None or r[0] != "±":
            raise StudyError(f'{src.path}: [study] → boxes: {box!r} is not a relative range such as "±10 %"')
        data = copy.deepcopy(dict(src.data))
        data["study"]["name"] = f"{table['name']} {box}"
        del data["study"]["boxes"]
        for row in data["parameters"]:
            if row.get("range") == "box":
                row["range"] = box
        from dataclasses import replace

        out.append(replace(study_from_data(src.path, data), family=table["name"]))
    return out


def study_from_data(path: str, data: Mapping[str, Any], base: ModelSource | None = None) -> Study:
    """A study from its file's parsed TOML (``path`` for messages and relative model paths).

    ``base`` gives the model file (with the files it refers to in ``includes``) instead of reading
    it from disk: a stored study is rebuilt on the model files it ran on.
    """
    from mechdyn.errors import ModelFileError
    from mechdyn.registry import get
    from mechdyn.units import UnitError

    src_path = path
    try:
        f = StudyFile.model_validate(data)
    except ValidationError as exc:
        raise _validation_error(src_path, exc) from None
    s = f.study
    if base is None:
        model_path = Path(os.path.normpath(Path(src_path).parent / s.model))
        if not model_path.is_file():
            raise StudyError(
                f"{src_path}: [study] → model: {s.model!r}: no such file ({model_path}); give the model "
                "file relative to the study file"
            )
        try:
            base = read(model_path)
        except ModelFileError as exc:
            raise StudyError(f"{src_path}: [study] → model: {exc}") from None
    try:
        analysis = get(s.analysis)
    except Exception as exc:
        raise StudyError(f"{src_path}: [study] → analysis: {exc}") from None
    if base.model_type not in analysis.model_types:
        raise StudyError(
            f"{src_path}: [study] → analysis: {s.analysis!r} runs on "
            f"{', '.join(analysis.model_types)} models; {s.model} is a {base.model_type!r} model"
        )
    options = analysis_options(analysis, s.options, src_path)
    tree = ModelTree(base)
    from mechdyn.studies.kinds.base import kind, level_kinds

    params: list[Parameter] = []
    for i, row in enumerate(f.parameters):
        where = f"{src_path}: [[parameters]] #{i + 1} (path = {row.path!r})"
        try:
            made = Parameter.from_spec(
                tree,
                row.path,
                range=row.range,
                levels=row.levels,
                tie=row.tie,
                name=row.name,
                where=where,
                scatter=row.scatter,
                design_scatter=s.kind == "optimize",
                level_kinds=level_kinds(),
            )
        except PathError as exc:
            raise StudyError(f"{where}: {exc}") from None
        except UnitError as exc:
            raise StudyError(f"{where}: {exc}") from None
        kind(s.kind).refuse_discrete(made, where)
        params.extend(made)
    correlations: tuple[tuple[str, str, float, str], ...] = tuple(
        (c.between[0], c.between[1], c.coefficient, c.measure) for c in f.correlations
    )
    if s.kind == "tolerance":  # the model file's [[scatter]]: the default of the values it names
        from mechdyn.studies.kinds.tolerance_model import with_model_scatter

        params, correlations = with_model_scatter(tree, params, correlations, src_path)
    if tree.alternatives:  # model files a choice names: the variants read them, the study stores them
        from dataclasses import replace as _replace

        base = _replace(base, includes={**base.includes, **tree.alternatives})
    if not params:
        raise StudyError(f"{src_path}: give at least one [[parameters]] row")
    seen: dict[str, int] = {}
    for p in params:
        if p.name in seen:
            raise StudyError(
                f"{src_path}: [[parameters]]: {p.name!r} is named twice; each parameter needs a name of its "
                'own (give the second a different path, or name = "...")'
            )
        seen[p.name] = 1
    # (a wildcard through a file that several rows share names its values once per row)
    moved = [loc for p in params for loc in dict.fromkeys(p.locations)]
    for loc in moved:
        if moved.count(loc) > 1:
            owners = [p.name for p in params if loc in p.locations]
            raise StudyError(
                f"{src_path}: [[parameters]]: {loc.path!r} is set by more than one parameter "
                f"({', '.join(owners)}); a model value can follow one parameter only"
            )
    plain = tuple(
        _watched(analysis, o.output, o.unit, f"{src_path}: [[outputs]] #{i + 1}")
        for i, o in enumerate(f.outputs)
    )
    limits = tuple(
        _limit(w, o, f"{src_path}: [[outputs]] #{i + 1}")
        for i, (w, o) in enumerate(zip(plain, f.outputs, strict=True))
        if o.limit is not None
    )
    from mechdyn.studies.kinds.robust import check_rows, statistic_of

    designed, scattered = params, []
    if s.kind == "optimize":  # robust design: scatter without a range is not a design variable
        designed = [p for p in params if p.scatter is None or p.bounded]
        scattered = [p for p in params if p.scatter is not None and not p.bounded]
    check_rows(src_path, s.kind, f, params)
    outputs = tuple(
        statistic_of(w, o.statistic, limits, f"{src_path}: [[outputs]] #{i + 1}")
        for i, (w, o) in enumerate(zip(plain, f.outputs, strict=True))
    )
    objectives = tuple(
        Objective(
            statistic_of(
                _watched(analysis, o.output, o.unit, f"{src_path}: [[objectives]] #{i + 1}"),
                o.statistic,
                limits,
                f"{src_path}: [[objectives]] #{i + 1}",
            ),
            o.goal,
        )
        for i, o in enumerate(f.objectives)
    )
    constraints = tuple(
        _constraint(analysis, c, f"{src_path}: [[constraints]] #{i + 1}", limits=limits)
        for i, c in enumerate(f.constraints)
    )
    targets = tuple(
        _constraint(analysis, c, f"{src_path}: [[targets]] #{i + 1}", True) for i, c in enumerate(f.targets)
    )
    study = Study(
        s.name,
        s.kind,
        base,
        s.analysis,
        tuple(designed),
        outputs,
        objectives,
        constraints,
        targets,
        options,
        s.samples,
        s.seed,
        s.curves,
        s.chunk,
        s.population,
        s.batch,
        s.sampler,
        dict(data),
        src_path,
        method=s.method,
        limits=limits,
        correlations=correlations,
        small_probability=s.small_probability,
        scattered=tuple(scattered),
        scatter_samples=s.scatter_samples,
    )
    if s.kind != "tolerance" and (f.correlations or s.small_probability is not None):
        given = "[[correlations]]" if f.correlations else "[study] small_probability"
        raise StudyError(f'{src_path}: {given} is for kind = "tolerance" studies; remove it')
    check(study)
    return study


def analysis_options(analysis: Any, given: Mapping[str, Any], where: str) -> dict[str, Any]:
    """An analysis' options as a file gives them (quantities with their units), checked and in SI.

    Parameters
    ----------
    analysis : mechdyn.registry.Analysis
        The analysis whose options they are.
    given : mapping
        Option name → value as the file writes it (a quantity as text with its unit, a list for an
        option of several values).
    where : str
        The file, for errors.

    Returns
    -------
    dict
        Option name → value, SI.

    Raises
    ------
    StudyError
        An option the analysis does not have, or a value it does not take (naming ``[study] →
        options → NAME``).
    """
    from mechdyn.units import UnitError, to_si

    known = {o.name: o for o in analysis.options}
    out: dict[str, Any] = {}
    for k, v in given.items():
        if k not in known:
            raise StudyError(
                f"{where}: [study] → options: {analysis.name} has no option {k!r}; its options: "
                f"{', '.join(known) or 'none'}"
            )
        o = known[k]
        here = f"{where}: [study] → options → {k}"
        values = v if isinstance(v, list) and o.kind != "names" else [v]
        if o.nargs and (not isinstance(v, list) or len(v) != o.nargs):
            raise StudyError(f"{here}: give {o.nargs} values in a list (got {v!r})")
        if not o.nargs and isinstance(v, list) and o.kind != "names":
            raise StudyError(f"{here}: give one value (got {v!r})")
        if o.kind == "quantity":
            try:
                got = [to_si(x, o.unit or "") for x in values]
            except UnitError as exc:
                raise StudyError(f"{here}: {exc}") from None
        else:
            got = [_option_value(o, x, here) for x in values]
        out[k] = got if o.nargs else got[0]
    return out


def _option_value(o: Any, v: Any, here: str) -> Any:
    """A non-quantity option from a study file, checked as its command-line flag would be."""
    import math

    if o.kind == "flag":
        if not isinstance(v, bool):
            raise StudyError(f"{here}: give true or false (got {v!r})")
    elif o.kind in ("int", "float"):
        number = isinstance(v, int) if o.kind == "int" else isinstance(v, (int, float))
        if isinstance(v, bool) or not number or not math.isfinite(v):
            wanted = "a whole number" if o.kind == "int" else "a number"
            raise StudyError(f"{here}: give {wanted} (got {v!r})")
        if o.minimum is not None and v < o.minimum:
            raise StudyError(f"{here}: {v!r} is below the least value, {o.minimum:g}")
    elif o.kind == "choice":
        if v not in o.choices:
            raise StudyError(f"{here}: {v!r} is not one of {', '.join(map(repr, o.choices))}")
    elif o.kind == "names":
        if not isinstance(v, list) or not all(isinstance(x, str) and x for x in v):
            raise StudyError(f"{here}: give a list of names (got {v!r})")
    elif not isinstance(v, str):
        raise StudyError(f"{here}: give text (got {v!r})")
    return v


def check(study: Study) -> None:
    """What the study's kind needs (:meth:`mechdyn.studies.kinds.Kind.check`: levels or ranges,
    objectives, targets) and the outputs to look at."""
    from mechdyn.studies.kinds import kind

    where = study.path or study.name
    kind(study.kind).check(study)
    if not study.watched:
        raise StudyError(f"{where}: give the [[outputs]] to look at")
