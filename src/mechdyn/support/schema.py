"""The support model file: ``[model] type = "support"``.

``[machine]`` is the rigid machine (mass, centre of mass, inertia); it stands either on a
one-degree-of-freedom ``[support]`` (stiffness and damping ratio, as published for press A) or on
``[[mounts]]`` (position, stiffness and damping along three local axes, orientation, anchored).
``[excitation]`` is a mechanism model file (its shaking force and moment, placed in the machine by
``origin``, ``x_axis`` and ``y_axis``) or a drive model file (the same mechanism driven by its motor:
the shaking at the drive's real, fluctuating speed, sampled uniformly in time over its period), a
vertical force over one ``period`` given as samples or
harmonics, or unbalanced rotors (``[[excitation.rotors]]``, with an optional ``speed_range`` to sweep).
``[analysis]`` picks the planar or spatial model, the start-up cycles and the factors of
the stiffness and damping study. An optional ``[foundation]`` puts a foundation block on soil under
the mounts (:mod:`mechdyn.support.foundation_schema`). See ``examples/press_on_support.toml``,
``examples/press_on_mounts.toml``, ``examples/press_driven_on_mounts.toml`` and
``examples/pump_set_unbalance.toml``.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING, Annotated, Any, Literal

import numpy as np
from pydantic import BeforeValidator, Field, model_validator

from mechdyn.errors import ModelFileError
from mechdyn.io.fields import (
    Angle,
    AngularSpeed,
    Dimensionless,
    FileModel,
    Force,
    Inertia,
    Length,
    LinearDamping,
    LinearStiffness,
    Mass,
    ModelTableBase,
    Time,
    quantity,
)
from mechdyn.io.modelfile import (
    ModelSource,
    build_source,
    field_context,
    reference_path,
    referenced,
    validate,
)
from mechdyn.support.analysis_table import AnalysisTable
from mechdyn.support.excitation import PeriodicLoad, Placement
from mechdyn.support.foundation_schema import FoundationTable, build_foundation
from mechdyn.support.model import PLANAR, SPATIAL, Mount, MountedMachine, RigidBody
from mechdyn.support.spec import DriveExcitation, MechanismExcitation, PlacedEstimate, SupportSpec
from mechdyn.support.unbalance import Rotor, frequency_given_as_speed
from mechdyn.units import convert

__all__ = ["DriveExcitation", "MechanismExcitation", "PlacedEstimate", "SupportFile", "SupportSpec", "build"]

Vector3 = tuple[float, float, float]
if TYPE_CHECKING:
    Unbalance = float
else:
    Unbalance = quantity("kg*m")


def _not_a_frequency(value: Any) -> Any:
    """A rotor's speed in Hz would be read as rad/s (2π too slow): refused with the speed in rpm."""
    wrong = frequency_given_as_speed(value)
    if wrong:
        raise ValueError(wrong)
    return value


RotorSpeed = Annotated[AngularSpeed, BeforeValidator(_not_a_frequency)]


class ModelTable(ModelTableBase):
    type: Literal["support"]
    """The file type, ``"support"``: it selects the schema and the analyses that read the file."""
    name: str = "machine on its supports"
    """The model's name, shown in tables, plots, reports and the results database."""


class MachineTable(FileModel):
    mass: Mass = Field(gt=0.0)
    """The machine's total mass (a rigid body)."""
    center_of_mass: tuple[Length, Length, Length] = (0.0, 0.0, 0.0)
    """Its centre of mass [x, y, z], z up."""
    inertia: tuple[Inertia, Inertia, Inertia] = (0.0, 0.0, 0.0)
    """Moments of inertia [I_xx, I_yy, I_zz] about axes through the centre of mass."""
    inertia_products: tuple[Inertia, Inertia, Inertia] = Field(
        default=(0.0, 0.0, 0.0),
        description="(Ixy, Ixz, Iyz): the tensor's off-diagonal components, I_xy = −∫xy dm, kg·m² "
        "(CAD programs often list +∫xy dm: change the sign)",
    )


class SingleDofTable(FileModel):
    stiffness: LinearStiffness
    """Vertical stiffness k of the one-degree-of-freedom support."""
    damping_ratio: Dimensionless
    """Damping ratio ζ of the support (c = 2 ζ √(k m))."""


class MountTable(FileModel):
    name: str
    """The mount's name, unique in the file; mount forces are reported by it."""
    position: tuple[Length, Length, Length]
    """Where the mount acts on the machine, [x, y, z]."""
    stiffness: tuple[LinearStiffness, LinearStiffness, LinearStiffness] | None = Field(
        default=None, description="along the mount's local axes (shear, shear, compression)"
    )
    mount: str | None = Field(
        default=None, description="a mount model file (relative to this file) whose estimate stands here"
    )
    estimate: dict[str, Any] | None = Field(
        default=None,
        description="the mount described inline, as in a mount file: {pad = {...}}, {bolted = {...}}, ...",
    )
    lateral_stiffness: LinearStiffness | None = Field(
        default=None, description="across the axis, for an estimate that does not give it"
    )
    calibration: Literal["as drawn", "stored"] = Field(
        default="as drawn",
        description='"stored": apply the latest calibration of this estimate kept in the results database',
    )
    damping: tuple[LinearDamping, LinearDamping, LinearDamping] | None = Field(
        default=None,
        description="along the local axes; by default 0, or from an estimate's loss factor",
    )
    orientation: tuple[Angle, Angle, Angle] = (0.0, 0.0, 0.0)
    """Rotations of the mount's local axes [about x, about y, about z], applied in that order about the
    machine's fixed axes (axes = R_z R_y R_x); the third local axis is its compression axis, so
    ["30 deg", 0, 0] tilts it to (0, −sin 30°, cos 30°)."""
    anchored: bool = False
    """Whether the mount is bolted to the floor (it may then pull); a free-standing mount that the machine's
    weight would have to pull is refused."""

    @model_validator(mode="after")
    def _one_stiffness(self) -> MountTable:
        given = [k for k in ("stiffness", "mount", "estimate") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(
                "give the mount's stiffness as numbers (stiffness = [shear, shear, compression]), "
                "by its estimate from the drawing (mount = a mount file, or an inline estimate = {pad = "
                f"{{...}}}}), exactly one of the three; got {given or 'none'}"
            )
        estimated_only = self.lateral_stiffness is not None or self.calibration != "as drawn"
        if self.stiffness is not None and estimated_only:
            raise ValueError("lateral_stiffness and calibration belong to a mount estimated from its drawing")
        return self


class RotorTable(FileModel):
    name: str | None = None
    """The rotor's name, unique among the rotors (default: "rotor 1", "rotor 2", ...)."""
    unbalance: Unbalance = Field(gt=0.0)
    """Its residual unbalance U = m·e, e.g. "0.02 kg*m" or "20 kg*mm" (ISO 21940-11 gives U = G m / Ω
    for a rotor of mass m balanced to grade G)."""
    speed: RotorSpeed
    """Its running speed, e.g. "1480 rpm" (not in Hz); a negative speed turns it the other way about its
    axis. The rotors' speeds must be in a whole-number ratio (one shaft, a gear, a belt)."""
    axis: str | Vector3
    """Its spin axis: "x", "y" or "z", or a direction [ax, ay, az] in machine coordinates (z up)."""
    position: tuple[Length, Length, Length] = (0.0, 0.0, 0.0)
    """The centre of its plane of unbalance (a point on its axis), [x, y, z]: the force's moment about
    the machine origin is r × F."""
    phase: Angle = 0.0
    """The heavy spot's angle at t = 0, from up (+z; from +x for a vertical axis), turning with the rotor."""


class ExcitationTable(FileModel):
    mechanism: str | None = None
    """A mechanism model file (relative to this file) whose shaking force and moment load the machine,
    or a drive model file (``type = "drive"``): the same at the drive's real, fluctuating speed."""
    angles: int | None = Field(default=None, ge=8, le=100_000)
    """Crank angles per revolution for that mechanism or drive (default: its own setting)."""
    origin: tuple[Length, Length, Length] = (0.0, 0.0, 0.0)
    """Where the mechanism's origin sits in the machine, [x, y, z]."""
    x_axis: Vector3 | None = None
    """Direction in the machine of the mechanism's x axis (with ``y_axis``; default: its output axis points
    up)."""
    y_axis: Vector3 | None = None
    """Direction in the machine of the mechanism's y axis (with ``x_axis``)."""
    period: Time | None = None
    """Period of a load given by samples or harmonics."""
    force_z: list[Force] | None = None
    """The vertical force at equal steps over one period (instead of ``mechanism``)."""
    harmonics: list[tuple[int, Force, Angle]] | None = None
    """The vertical force as rows [order, amplitude, phase] (instead of ``mechanism``)."""
    mean_force_z: Force = 0.0
    """A constant vertical force added to samples or harmonics."""
    rotors: list[RotorTable] | None = Field(
        default=None,
        description="unbalanced rotors whose rotating force U Ω² and moment r × F load the machine "
        "(instead of mechanism, force_z or harmonics); several add",
    )
    speed_range: tuple[RotorSpeed, RotorSpeed] | None = None
    """The first rotor's speeds to sweep for the floor force and the isolation, [from, to], e.g.
    ["0 rpm", "3000 rpm"] (default: 0 to 1.2 times its running speed); the other rotors keep their ratio
    to it."""

    @model_validator(mode="after")
    def _one_source(self) -> ExcitationTable:
        given = [k for k in ("mechanism", "force_z", "harmonics", "rotors") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(
                "give exactly one of mechanism (a mechanism model file), force_z (samples over one "
                "period), harmonics ([order, amplitude, phase] rows) or [[excitation.rotors]] "
                f"(unbalanced rotors); got {given or 'none'}"
            )
        if self.rotors is not None:
            self._rotors_alone()
            return self
        if self.speed_range is not None:
            raise ValueError(
                "speed_range sweeps the speed of unbalanced rotors: give [[excitation.rotors]], or remove it"
            )
        if self.mechanism is None and self.period is None:
            raise ValueError('samples and harmonics need the period, e.g. period = "4 s"')
        if self.mechanism is not None and self.period is not None:
            raise ValueError("the mechanism's speed sets the period; remove period")
        if (self.x_axis is None) != (self.y_axis is None):
            raise ValueError("give both x_axis and y_axis, or neither (the output axis then points up)")
        return self

    def _rotors_alone(self) -> None:
        """Rotors set their own period and place themselves; what belongs to other loads is refused."""
        rotors = self.rotors or []
        if not rotors:
            raise ValueError(
                'give at least one rotor: [[excitation.rotors]] with unbalance = "0.02 kg*m", '
                'speed = "1480 rpm" and axis = "y"'
            )
        if self.period is not None:
            raise ValueError("the rotors' speeds set the period; remove period")
        if self.mean_force_z != 0.0:
            raise ValueError(
                "mean_force_z adds to samples or harmonics; a rotor's force has no mean: remove it"
            )
        if self.x_axis is not None or self.y_axis is not None or any(v != 0.0 for v in self.origin):
            raise ValueError(
                "origin, x_axis and y_axis place a mechanism; a rotor is placed by its own position and "
                "axis: remove them"
            )
        names = [r.name for r in rotors if r.name is not None]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ValueError(f"rotor names {dup} appear more than once; give each rotor its own name")
        if self.speed_range is not None:
            lo, hi = self.speed_range
            if not 0.0 <= lo < hi:
                rpm = convert(1.0, "rad/s", "rpm")
                raise ValueError(
                    f"speed_range [{lo * rpm:.6g} rpm, {hi * rpm:.6g} rpm] must rise from a speed ≥ 0 to a "
                    'higher one, e.g. speed_range = ["0 rpm", "3000 rpm"]'
                )


class SupportFile(FileModel):
    """Schema of a support model file."""

    model: ModelTable
    machine: MachineTable
    support: SingleDofTable | None = None
    mounts: list[MountTable] | None = None
    excitation: ExcitationTable
    analysis: AnalysisTable = AnalysisTable()
    foundation: FoundationTable | None = None
    """A foundation block on soil under the mounts (:mod:`mechdyn.support.foundation_schema`);
    without it the mounts stand on rigid ground."""

    @model_validator(mode="after")
    def _one_support(self) -> SupportFile:
        if (self.support is None) == (self.mounts is None):
            raise ValueError(
                "give either [support] (one degree of freedom: stiffness and damping_ratio) or "
                "[[mounts]] (a rigid machine on mounts), not both or neither"
            )
        return self


def _inertia_tensor(t: MachineTable) -> np.ndarray:
    ixx, iyy, izz = t.inertia
    ixy, ixz, iyz = t.inertia_products
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


def _excitation(f: SupportFile, source: ModelSource) -> PeriodicLoad | MechanismExcitation | DriveExcitation:
    e = f.excitation
    if e.mechanism is not None:
        from mechdyn.drive.schema import DriveSpec
        from mechdyn.mechanism.schema import MechanismSpec

        msource = referenced(source, e.mechanism)
        if msource is None:
            raise ModelFileError(
                source.path,
                "[excitation] → mechanism",
                f"{e.mechanism!r}: no such file next to this model ({reference_path(source, e.mechanism)}); "
                "give the mechanism model file's path relative to this file",
                e.mechanism,
            )
        spec = build_source(msource)
        path = msource.path
        if not isinstance(spec, MechanismSpec | DriveSpec):
            raise ModelFileError(
                source.path,
                "[excitation] → mechanism",
                f"{e.mechanism!r} is a {msource.model_type!r} model; give a mechanism model file, or a "
                "drive model file (the mechanism driven by its motor)",
                e.mechanism,
            )
        mechanism = spec.mechanism if isinstance(spec, MechanismSpec) else spec.drive.mechanism
        with field_context(source, "[excitation]"):
            if e.x_axis is None:
                place = Placement.output_up(mechanism, e.origin)
            else:
                place = Placement(e.origin, e.x_axis, e.y_axis)
        if isinstance(spec, DriveSpec):
            n = e.angles or spec.settings.n_angles
            return DriveExcitation(spec.drive, n, place, str(path), str(source.path))
        return MechanismExcitation(spec.mechanism, e.angles or spec.n_angles, place, str(path))
    if e.rotors is not None:
        return _rotors(e.rotors, source)
    with field_context(source, "[excitation]"):
        if e.force_z is not None:
            samples = np.asarray(e.force_z, dtype=float)
            if samples.size < 2:
                raise ValueError("force_z needs at least two samples over the period")
            return PeriodicLoad.from_samples(e.period, samples + e.mean_force_z)
        amps = {}
        for order, amp, phase in e.harmonics or []:
            if order < 1 or order in amps:
                raise ValueError(f"harmonic order {order} must be ≥ 1 and appear once")
            amps[order] = amp * complex(math.cos(phase), math.sin(phase))
        return PeriodicLoad.from_harmonics(e.period, amps, e.mean_force_z)


def _rotors(rows: list[RotorTable], source: ModelSource) -> PeriodicLoad:
    """The load of the ``[[excitation.rotors]]``: each rotor checked in its own table, then together
    (a speed ratio that is not a whole-number one is placed at the rotor that breaks it)."""
    rotors, where = [], {}
    for i, r in enumerate(rows):
        name = r.name or f"rotor {i + 1}"
        where[name] = f"[excitation] → [[rotors]] #{i + 1} (name = {name!r})"  # as the schema's errors
        with field_context(source, where[name]):
            rotors.append(Rotor(r.unbalance, r.speed, r.axis, r.position, r.phase, name))
    with field_context(source, "[excitation] → [[rotors]]", where):
        return PeriodicLoad.from_unbalance(rotors)


def build(source: ModelSource) -> SupportSpec:
    """Builder for ``[model] type = "support"``."""
    f = validate(SupportFile, source)
    excitation = _excitation(f, source)
    estimates: dict[str, PlacedEstimate] = {}
    if f.support is not None:
        with field_context(source, "[support]"):
            machine = MountedMachine.single_dof(
                f.machine.mass, f.support.stiffness, f.support.damping_ratio, f.model.name
            )
            machine = replace(machine, gravity=f.analysis.gravity)
    else:
        machine, estimates = _on_mounts(f, source)
    return SupportSpec(
        f.model.name,
        machine,
        excitation,
        f.analysis,
        estimates=estimates,
        speed_range=f.excitation.speed_range,
        foundation=None if f.foundation is None else build_foundation(f.foundation, source),
        floor_points=None if f.foundation is None else f.foundation.floor_points,
    )


def _on_mounts(f: SupportFile, source: ModelSource) -> tuple[MountedMachine, dict[str, PlacedEstimate]]:
    """The rigid machine on its ``[[mounts]]``, and the mounts estimated from their drawings.

    A row without ``damping`` whose stiffness comes from an estimate gets c = η k / ω along each
    local axis, η the estimate's loss factor and ω = √(Σ k / m) the machine's translational natural
    frequency along that axis (the mounts' local axes summed as if aligned with the machine's): the
    viscous equivalent ζ = η/2 at that resonance.
    """
    rows = f.mounts or []
    where = {m.name: f"[[mounts]] #{i + 1} (name = {m.name!r})" for i, m in enumerate(rows)}
    drawn = [m for m in rows if m.mount is not None or m.estimate is not None]
    estimates = {m.name: _placed(m, source, where[m.name]) for m in drawn}
    stiffness = {
        m.name: np.asarray(m.stiffness if m.stiffness is not None else estimates[m.name].axes(), float)
        for m in rows
    }
    with np.errstate(over="ignore"):  # a mass too small for any machine is refused by RigidBody below
        omega = np.sqrt(np.clip(sum(stiffness.values()) / f.machine.mass, 0.0, None))
    mounts = []
    for m in rows:
        e, k = estimates.get(m.name), stiffness[m.name]
        damping: Any = m.damping
        if damping is None:
            eta = 0.0 if e is None else e.estimate.loss_factor
            damping = np.divide(eta * k, omega, out=np.zeros(3), where=omega > 0)
        with field_context(source, where[m.name]):
            mount = Mount.with_orientation(
                m.name, m.position, k, m.orientation, damping=damping, anchored=m.anchored
            )
        mounts.append(mount)
    tables = where | {"machine": "[machine]", f.model.name: "[[mounts]]"}
    with field_context(source, "[machine]", tables):
        body = RigidBody(f.machine.mass, f.machine.center_of_mass, _inertia_tensor(f.machine))
        dofs = PLANAR if f.analysis.dofs == "planar" else SPATIAL
        machine = MountedMachine(body, tuple(mounts), dofs, f.analysis.gravity, f.model.name)
    return machine, estimates


def _placed(row: MountTable, source: ModelSource, where: str) -> PlacedEstimate:
    """The mount estimate a ``[[mounts]]`` row names (a mount file) or holds (an inline table)."""
    from mechdyn.mounts.schema import build as build_mount

    if row.mount is not None:
        msource = referenced(source, row.mount)
        if msource is None:
            raise ModelFileError(
                source.path,
                f"{where} → mount",
                f"{row.mount!r}: no such file next to this model ({reference_path(source, row.mount)}); "
                "give the mount model file's path relative to this file",
                row.mount,
            )
        spec = build_source(msource)
        path = msource.path
        if msource.model_type != "mount":
            raise ModelFileError(
                source.path,
                f"{where} → mount",
                f"{row.mount!r} is a {msource.model_type!r} model; give a mount model file",
                row.mount,
            )
        origin = str(path)
    else:
        data = {"model": {"type": "mount", "name": row.name}, **(row.estimate or {})}
        inline = ModelSource(source.path, source.text, source.sha256, data)
        try:
            spec = build_mount(inline)
        except ModelFileError as exc:

            def located(loc: str) -> str:
                return f"{where} → estimate" + (f" → {loc}" if loc else "")

            problems = [(located(loc), msg) for loc, msg in exc.problems]
            raise ModelFileError(
                source.path, located(exc.location), exc.detail, exc.value, problems=problems
            ) from None
        origin = f"{source.path}: {where}"
    estimate = spec.mount
    if row.lateral_stiffness is None and estimate.lateral_stiffness is None:
        raise ModelFileError(
            source.path,
            f"{where} → lateral_stiffness",
            f"the {spec.kind} estimate gives no stiffness across its axis; give lateral_stiffness, "
            'e.g. lateral_stiffness = "2e7 N/m"',
        )
    return PlacedEstimate(
        estimate, row.lateral_stiffness, row.calibration == "stored", row.damping is None, origin
    )
