"""The measurement model file: ``[model] type = "measurement"``.

A measurement file names a test and the model it tests: ``[measurement]`` gives the data file (UFF 58
or CSV, relative to this file), the model file (a support or a drivetrain, relative to this file) and
the band the modes are identified in; ``[[points]]`` maps each measurement point (node) of the data to
a model point (a mount of a support by name, a location x, y, z in the machine's coordinates, or a
drivetrain disk by name); optional ``[[update]]`` rows name the model values to update (study paths,
``mounts.*.stiffness.z``) with their prior scatter, ``[updating]`` the updating's settings, and an
optional ``[predict]`` table names an analysis of the tested model to run on the updated one with the band
the test leaves (:mod:`mechdyn.measurement.prediction`). See ``examples/measured/tap_test.toml``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import Field, model_validator

from mechdyn.errors import MechdynError, ModelFileError
from mechdyn.io.fields import Check, FileModel, Frequency, Length, ModelTableBase
from mechdyn.io.modelfile import ModelSource, reference_path, referenced, validate
from mechdyn.measurement.prediction import PredictTable, build_predict

__all__ = ["MeasurementFile", "MeasurementSpec", "build"]

# the model types whose modes a test can be compared with (their coordinates a point maps to)
TESTED_TYPES = ("support", "drivetrain")
UFF_SUFFIXES = (".uff", ".unv", ".uf")


class ModelTable(ModelTableBase):
    type: Literal["measurement"]
    """The file type, ``"measurement"``: it selects the schema and the analyses that read the file."""
    name: str = "measurement"
    """The test's name, shown in tables, plots, reports and the results database."""


PositiveFrequency = Annotated[Frequency, Check("Hz", positive=True)]


class MeasurementTable(FileModel):
    data: str
    """The measured frequency responses: a Universal File (dataset 58; ``.uff``, ``.unv``) or a CSV file
    (see ``mechdyn.measurement.read_csv``), relative to this file."""
    model: str
    """The model file the test is compared with (a support or a drivetrain), relative to this file."""
    f_min: PositiveFrequency
    """Lower end of the band the modes are identified in."""
    f_max: PositiveFrequency
    """Upper end of the band the modes are identified in."""
    units: str | None = None
    """The FRFs' unit when a UFF file does not say it (e.g. ``"m/s^2/N"``)."""
    max_order: int = Field(default=40, ge=4, le=200)
    """Highest number of pole pairs of the stabilisation chart (about 3 to 5 times the modes in the band)."""
    bootstrap: int = Field(default=20, ge=0, le=1000)
    """Bootstrap data sets for the noise part of the modes' scatter (0: none)."""
    min_mac: float = Field(default=0.5, gt=0, lt=1)
    """Measured and model modes pair only at this MAC or above."""

    @model_validator(mode="after")
    def _band(self) -> MeasurementTable:
        if not self.f_min < self.f_max:
            raise ValueError(
                f"the band f_min = {self.f_min:g} Hz … f_max = {self.f_max:g} Hz is empty; give f_min < f_max"
            )
        return self


class PointTable(FileModel):
    point: str
    """The measurement point (node) as the data file names it."""
    mount: str | None = None
    """The support's mount at this point, by name (its position is the point's location)."""
    location: list[Length] | None = Field(default=None, min_length=3, max_length=3)
    """The point's location x, y, z in the machine's coordinates (a support's rigid body)."""
    disk: str | None = None
    """The drivetrain disk whose rotation this point measures, by name."""

    @model_validator(mode="after")
    def _one_target(self) -> PointTable:
        given = [k for k in ("mount", "location", "disk") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(
                f"point {self.point!r}: give exactly one of mount (a name), location (x, y, z) or disk "
                f"(a name); got {', '.join(given) or 'none'}"
            )
        return self


class UpdateRow(FileModel):
    path: str
    """A model value to update, named as a design study names it (``mounts.*.stiffness.z``: the z
    stiffness of every mount, moved by one factor); a positive quantity."""
    prior_scatter: Annotated[float, Check("", positive=True)] = 1.0
    """Standard uncertainty of the value's logarithm before the test (0.3: about ±30 %)."""


class UpdatingTable(FileModel):
    damping_error: Annotated[float, Check("", positive=True)] | None = None
    """Also fit the damping ratios, with this relative uncertainty of the model's damping estimate (0.05:
    5 %); without it only the frequencies are fitted."""
    model_error: Annotated[float, Check("", positive=True)] = 1e-3
    """Relative uncertainty added to each measured frequency's scatter (the model's form error)."""
    shape_weight: Annotated[float, Check("", nonnegative=True)] = 0.0
    """Weight of the mode shapes' residuals (1 − MAC) against the frequencies' (0: frequencies only)."""
    starts: int = Field(default=8, ge=0, le=256)
    """Sobol start points of the global search (0: the model's values only)."""
    search: Annotated[float, Check("", low=1.0, low_open=True)] = 2.0
    """Factor of the global search box around the model's values (2: half to twice)."""
    max_uncertainty: Annotated[float, Check("", positive=True)] = 0.5
    """A value whose data-only scatter of its logarithm exceeds this is not identifiable."""
    posterior: Literal["linear", "sampling"] = "linear"
    """The updated values' uncertainty: "linear", the Laplace covariance of the residuals, or
    "sampling", the Bayesian posterior sampled (importance sampling, with its diagnostics stated)."""
    samples: int = Field(default=1000, ge=50, le=100_000)
    """Draws of the posterior, with posterior = "sampling"."""


class MeasurementFile(FileModel):
    """Schema of a measurement model file."""

    model: ModelTable
    measurement: MeasurementTable
    points: list[PointTable] = Field(default_factory=list)
    update: list[UpdateRow] = Field(default_factory=list)
    updating: UpdatingTable = UpdatingTable()
    predict: PredictTable | None = None
    """An analysis of the tested model to predict with the band the test leaves (optional)."""


@dataclass(frozen=True)
class MeasurementSpec:
    """A test as read from its file: the measured FRFs, the tested model and the mapping.

    Attributes
    ----------
    name : str
        The test's name.
    measured : MeasuredFRF
        The frequency responses, SI.
    tested : LoadedModel
        The model the test is compared with (a support or a drivetrain).
    mapping : mapping of str to str or tuple
        Measurement point → model coordinate (a disk) or location (x, y, z) in m.
    f_min_hz, f_max_hz : float
        The identification band, Hz.
    parameters : tuple of str
        The study paths to update (empty: compare only).
    prior_scatter : tuple of float
        Standard uncertainty of each parameter's logarithm before the test, dimensionless.
    identification : MeasurementTable
        The file's ``[measurement]`` table (order, bootstrap, MAC threshold).
    updating : UpdatingTable
        The file's ``[updating]`` table.
    data_file, model_file : str
        The data and model files as the file names them (relative).
    point_names : tuple of str
        The measurement points as the file's ``[[points]]`` list them.
    predict : PredictSpec or None
        The file's ``[predict]`` table as checked (None: no prediction).
    """

    name: str
    measured: Any
    tested: Any
    mapping: Mapping[str, Any]
    f_min_hz: float
    f_max_hz: float
    parameters: tuple[str, ...]
    prior_scatter: tuple[float, ...]
    identification: MeasurementTable
    updating: UpdatingTable
    data_file: str
    model_file: str
    point_names: tuple[str, ...] = field(default=())
    predict: Any = None


def _read_data(source: ModelSource, t: MeasurementTable) -> Any:
    from mechdyn.measurement.data import read_csv, read_uff

    where = "[measurement] → data"
    path = Path(reference_path(source, t.data))
    if not path.is_file():
        raise ModelFileError(
            source.path,
            where,
            f"{t.data!r}: no such file next to this model ({path}); give the UFF 58 or CSV file of the "
            "measured frequency responses, relative to this file",
            t.data,
        )
    suffix = path.suffix.lower()
    if suffix in UFF_SUFFIXES:
        return read_uff(path, units=t.units)
    if suffix == ".csv":
        return read_csv(path)
    raise ModelFileError(
        source.path,
        where,
        f"{t.data!r}: a {suffix or 'suffix-less'} file is neither a Universal File (.uff, .unv) nor a CSV "
        "file (.csv); give the measured data in one of these",
        t.data,
    )


def _tested(source: ModelSource, t: MeasurementTable) -> Any:
    from mechdyn.io.modelfile import load_source

    where = "[measurement] → model"
    tested = referenced(source, t.model)
    if tested is None:
        raise ModelFileError(
            source.path,
            where,
            f"{t.model!r}: no such file next to this model ({reference_path(source, t.model)}); give the "
            "model file the test is compared with (a support or a drivetrain), relative to this file",
            t.model,
        )
    if tested.model_type not in TESTED_TYPES:
        raise ModelFileError(
            source.path,
            where,
            f"{t.model!r} is a {tested.model_type!r} model; a test is compared with a "
            f"{' or a '.join(TESTED_TYPES)} model (their modes and coordinates)",
            t.model,
        )
    return load_source(tested)


def _mapping(source: ModelSource, points: list[PointTable], tested: Any, measured: Any) -> dict[str, Any]:
    """Measurement point → model coordinate or location, each point checked against the model and the
    data."""
    in_data = list(dict.fromkeys(p for p, _ in (*measured.outputs, *measured.references)))
    mapping: dict[str, Any] = {}
    support = tested.type == "support"
    mounts = {m.name: m for m in tested.model.mounts} if support else {}
    disks = [str(n) for n in tested.model.dof_names] if not support else []
    for i, p in enumerate(points):
        where = f"[[points]] #{i + 1} (point = {p.point!r})"
        if p.point in mapping:
            raise ModelFileError(source.path, where + " → point", f"{p.point!r} is mapped twice; map it once")
        if p.point not in in_data:
            raise ModelFileError(
                source.path,
                where + " → point",
                f"{p.point!r} is not a point of the data file; its points: {', '.join(map(repr, in_data))}",
                p.point,
            )
        if p.mount is not None:
            if not support:
                raise ModelFileError(
                    source.path,
                    where + " → mount",
                    f"{p.mount!r}: a {tested.type} has no mounts; map the point to a disk",
                    p.mount,
                )
            if p.mount not in mounts:
                raise ModelFileError(
                    source.path,
                    where + " → mount",
                    f"{p.mount!r} is not a mount of the model; its mounts: {', '.join(map(repr, mounts))}",
                    p.mount,
                )
            mapping[p.point] = tuple(float(v) for v in mounts[p.mount].position)
        elif p.location is not None:
            if not support:
                raise ModelFileError(
                    source.path,
                    where + " → location",
                    f"a {tested.type}'s coordinates are its disks' rotations; map the point to a disk",
                    p.location,
                )
            mapping[p.point] = tuple(float(v) for v in p.location)
        else:
            if not support:
                if p.disk not in disks:
                    raise ModelFileError(
                        source.path,
                        where + " → disk",
                        f"{p.disk!r} is not a disk of the model; its disks: {', '.join(map(repr, disks))}",
                        p.disk,
                    )
            else:
                raise ModelFileError(
                    source.path,
                    where + " → disk",
                    f"{p.disk!r}: a support has no disks; map the point to a mount or a location (x, y, z)",
                    p.disk,
                )
            mapping[p.point] = p.disk
    unmapped = [p for p in in_data if p not in mapping and p not in disks]
    if unmapped:
        noun = "a mount (mount = name) or a location (x, y, z)" if support else "a disk (disk = name)"
        raise ModelFileError(
            source.path,
            "[[points]]",
            f"the data's point(s) {', '.join(map(repr, unmapped))} map to no model point; add a [[points]] "
            f"row for each, naming {noun}",
            unmapped,
        )
    return mapping


def _check_band(source: ModelSource, t: MeasurementTable, measured: Any) -> None:
    f = measured.frequencies_hz
    lo, hi = float(f[0]), float(f[-1])
    for name, value in (("f_min", t.f_min), ("f_max", t.f_max)):
        if not lo <= value <= hi:
            raise ModelFileError(
                source.path,
                f"[measurement] → {name}",
                f"{value:g} Hz lies outside the data's {lo:g} … {hi:g} Hz; give a band within the "
                "measured lines",
                value,
            )


def _check_paths(source: ModelSource, rows: list[UpdateRow], tested: Any) -> None:
    from mechdyn.measurement.updating import _parameters
    from mechdyn.studies.paths import ModelTree

    tree = ModelTree(tested.source)
    seen: set[str] = set()
    for i, row in enumerate(rows):
        where = f"[[update]] #{i + 1} → path"
        if row.path in seen:
            raise ModelFileError(source.path, where, f"{row.path!r} is given twice; update it once", row.path)
        seen.add(row.path)
        try:
            tree.resolve(row.path)
            _parameters(tree, [row.path])  # a positive quantity: updated on its logarithm
        except MechdynError as exc:
            said = str(exc).removeprefix("update_model: ")
            raise ModelFileError(source.path, where, f"{row.path!r}: {said}", row.path) from None


def build(source: ModelSource) -> MeasurementSpec:
    """Builder for ``[model] type = "measurement"``: read the data and the tested model, map the
    points, check the band and the paths to update.

    Parameters
    ----------
    source : ModelSource
        The measurement file.

    Returns
    -------
    MeasurementSpec

    Raises
    ------
    ModelFileError
        Naming the file, the table and field, the value and the fix (a missing data or model file,
        an unknown mount or disk, an unmapped point, a band outside the data, an unknown path, an
        analysis, output or option ``[predict]`` cannot run, too few samples).
    """
    f = validate(MeasurementFile, source)
    t = f.measurement
    measured = _read_data(source, t)
    _check_band(source, t, measured)
    tested = _tested(source, t)
    mapping = _mapping(source, f.points, tested, measured)
    _check_paths(source, f.update, tested)
    predict = None if f.predict is None else build_predict(str(source.path), f.predict, tested.type)
    return MeasurementSpec(
        name=f.model.name,
        measured=measured,
        tested=tested,
        mapping=mapping,
        f_min_hz=t.f_min,
        f_max_hz=t.f_max,
        parameters=tuple(r.path for r in f.update),
        prior_scatter=tuple(r.prior_scatter for r in f.update),
        identification=t,
        updating=f.updating,
        data_file=t.data,
        model_file=t.model,
        point_names=tuple(p.point for p in f.points),
        predict=predict,
    )
