"""The mechanism model file: ``[model] type = "mechanism"``.

``[points]`` is the drawing (global coordinates of every named point in one assembled pose);
``[[bodies]]`` list their points, mass, inertia about the centre of mass and centre of mass;
``[[joints]]`` are revolute or prismatic at a point; ``[driver]`` turns a crank; ``[settings]`` sets
gravity, the angle datum, the output and the number of crank angles; ``[[process_forces]]`` are
piecewise-linear tables against crank angle or output position. See ``examples/slider_crank.toml``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from pydantic import Field, field_validator

from mechdyn.io.fields import Angle, FileModel, Length, ModelTableBase, quantity
from mechdyn.io.modelfile import ModelSource, field_context, validate
from mechdyn.mechanism.model import Body, Driver, Mechanism, Prismatic, ProcessForce, Revolute

__all__ = ["MechanismFile", "MechanismSpec", "build"]

Mass = quantity("kg")
Inertia = quantity("kg*m^2")
Speed = quantity("rad/s")
Acceleration = quantity("m/s^2")
Force = quantity("N")


class ModelTable(ModelTableBase):
    type: Literal["mechanism"]
    name: str = "mechanism"


class BodyTable(FileModel):
    name: str
    points: list[str] = Field(min_length=1)
    mass: Mass = 0.0
    inertia: Inertia = 0.0
    center_of_mass: tuple[Length, Length] | str | None = None


class JointTable(FileModel):
    name: str
    type: Literal["revolute", "prismatic"]
    bodies: tuple[str, str]
    point: str
    axis: Angle | None = None


class DriverTable(FileModel):
    body: str
    pivot: str
    tip: str
    speed: Speed
    speed_profile: list[tuple[str, str]] | None = None


class SettingsTable(FileModel):
    gravity: tuple[Acceleration, Acceleration] = (0.0, 0.0)
    angle_datum: Angle | Literal["bdc"] = 0.0
    n_angles: int = Field(default=360, ge=8, le=100_000)
    output: tuple[str, str] | None = None

    @field_validator("angle_datum", mode="before")
    @classmethod
    def _bdc(cls, v):  # "bdc" is a word, not a quantity
        return v.strip().lower() if isinstance(v, str) and v.strip().lower() == "bdc" else v


class ProcessForceTable(FileModel):
    body: str
    point: str
    direction: Angle
    versus: Literal["angle", "position"]
    table: list[tuple[str, str]] = Field(min_length=2)


class MechanismFile(FileModel):
    """Schema of a mechanism model file."""

    model: ModelTable
    points: dict[str, tuple[Length, Length]]
    bodies: list[BodyTable] = Field(min_length=1)
    joints: list[JointTable] = Field(min_length=1)
    driver: DriverTable
    settings: SettingsTable = SettingsTable()
    process_forces: list[ProcessForceTable] = Field(default_factory=list)


@dataclass(frozen=True)
class MechanismSpec:
    """A mechanism as read from a file, with the number of crank angles to analyse."""

    mechanism: Mechanism
    n_angles: int

    @property
    def name(self) -> str:
        return self.mechanism.name


def _tabulated(pf: ProcessForceTable, where: str) -> ProcessForce:
    from mechdyn.units import to_si

    x_unit = "rad" if pf.versus == "angle" else "m"
    xs, fs = [], []
    for i, (x, f) in enumerate(pf.table):
        try:
            xs.append(to_si(x, x_unit))
            fs.append(to_si(f, "N"))
        except ValueError as exc:
            raise ValueError(f"table row {i + 1} ({x!r}, {f!r}): {exc}") from None
    xs_a, fs_a = np.asarray(xs), np.asarray(fs)
    if np.any(np.diff(xs_a) <= 0):
        raise ValueError(f"table {pf.versus} values must increase row by row; got {xs}")
    c, s = math.cos(pf.direction), math.sin(pf.direction)

    def force(angle: np.ndarray, position: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        x = angle if pf.versus == "angle" else position
        f = np.interp(x, xs_a, fs_a, left=0.0, right=0.0)
        return f * c, f * s

    return ProcessForce(pf.body, pf.point, force)


def _profile(table: list[tuple[str, str]], speed: float):
    """A periodic cubic spline of crank speed against angle turned from the drawing."""
    from scipy.interpolate import CubicSpline

    from mechdyn.units import to_si

    try:
        x = np.array([to_si(a, "rad") for a, _ in table])
        w = np.array([abs(to_si(v, "rad/s")) for _, v in table]) * math.copysign(1.0, speed)
    except ValueError as exc:
        raise ValueError(f"speed_profile: {exc}") from None
    if x[0] != 0 or np.any(np.diff(x) <= 0) or x[-1] >= 2 * math.pi:
        raise ValueError("speed_profile angles must start at 0 deg and increase below 360 deg")
    if np.any(w == 0):
        raise ValueError("speed_profile speeds must not be zero")
    spline = CubicSpline(np.append(x, 2 * math.pi), np.append(w, w[0]), bc_type="periodic")
    slope = spline.derivative()

    def rates(turned: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        t = np.mod(turned, 2 * math.pi)
        omega = spline(t)
        return omega, omega * slope(t) * math.copysign(1.0, speed)  # θ̈ = θ̇ dθ̇/dθ

    return rates


def build(source: ModelSource) -> MechanismSpec:
    """Builder for ``[model] type = "mechanism"``."""
    f = validate(MechanismFile, source)
    bodies = []
    for i, b in enumerate(f.bodies):
        with field_context(source, f"[[bodies]] #{i + 1} (name = {b.name!r})"):
            bodies.append(Body(b.name, tuple(b.points), b.mass, b.inertia, b.center_of_mass))
    joints: list[Revolute | Prismatic] = []
    for i, j in enumerate(f.joints):
        with field_context(source, f"[[joints]] #{i + 1} (name = {j.name!r})"):
            if j.type == "revolute":
                if j.axis is not None:
                    raise ValueError("a revolute joint has no axis; remove it")
                joints.append(Revolute(j.name, j.bodies, j.point))
            else:
                if j.axis is None:
                    raise ValueError('a prismatic joint needs its sliding axis, e.g. axis = "0 deg"')
                joints.append(Prismatic(j.name, j.bodies, j.point, j.axis))
    forces = []
    for i, pf in enumerate(f.process_forces):
        where = f"[[process_forces]] #{i + 1}"
        with field_context(source, where):
            forces.append(_tabulated(pf, where))
    with field_context(source, "[driver]"):
        profile = _profile(f.driver.speed_profile, f.driver.speed) if f.driver.speed_profile else None
        driver = Driver(f.driver.body, f.driver.pivot, f.driver.tip, f.driver.speed, profile)
    tables = {b.name: f"[[bodies]] #{i + 1} (name = {b.name!r})" for i, b in enumerate(f.bodies)}
    tables |= {j.name: f"[[joints]] #{i + 1} (name = {j.name!r})" for i, j in enumerate(f.joints)}
    tables["driver"] = "[driver]"
    with field_context(source, "[model]", tables):
        mech = Mechanism(
            points=dict(f.points),
            bodies=tuple(bodies),
            joints=tuple(joints),
            driver=driver,
            gravity=f.settings.gravity,
            process_forces=tuple(forces),
            output=f.settings.output,
            angle_datum=f.settings.angle_datum,
            name=f.model.name,
        )
    return MechanismSpec(mech, f.settings.n_angles)
