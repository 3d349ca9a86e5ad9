"""The mechanism model file: ``[model] type = "mechanism"``.

``[points]`` is the drawing (global coordinates of every named point in one assembled pose);
``[[bodies]]`` list their points, mass, inertia about the centre of mass and centre of mass;
``[[joints]]`` are revolute or prismatic at a point; ``[driver]`` turns a crank; ``[settings]`` sets
gravity, the angle datum, the output, the number of crank angles, the points to ``trace`` and the
machine's ``field_velocity`` (for the path of a tool over the ground); ``[[process_forces]]`` are
piecewise-linear tables against crank angle or output position; ``[[counterweights]]`` put masses on
links (``body``, ``mass``, ``position`` as [x, y] in the drawing or a point's name, optional
``inertia``), folded into their links when the model is assembled. A ``gear`` joint meshes two gears
pivoted on a common ``carrier`` at its two ``points``, with gear 1's pitch curve in ``pitch``
(circle, eccentric circle, ellipse about a focus, or sampled radii; ``radius = "closing"`` sizes a
noncircular gear so that its mate closes at the drawing's centre distance). See
``examples/slider_crank.toml`` and ``examples/transplanter_rp1.toml``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import Field, field_validator

from mechdyn.errors import ModelFileError
from mechdyn.io.fields import (
    Acceleration,
    Angle,
    AngularSpeed,
    Check,
    Dimensionless,
    FileModel,
    Force,
    Inertia,
    Length,
    LinearStiffness,
    Mass,
    ModelTableBase,
    Torque,
    Velocity,
)
from mechdyn.io.modelfile import ModelSource, field_context, validate
from mechdyn.mechanism.kinematics import MAX_ANGLES
from mechdyn.mechanism.model import (
    Body,
    Counterweight,
    Driver,
    GearJoint,
    Mechanism,
    Prismatic,
    ProcessForce,
    Revolute,
    TabulatedForce,
)

__all__ = ["MechanismFile", "MechanismSpec", "build"]


class ModelTable(ModelTableBase):
    type: Literal["mechanism"]
    """The file type, ``"mechanism"``: it selects the schema and the analyses that read the file."""
    name: str = "mechanism"
    """The model's name, shown in tables, plots, reports and the results database."""


# a mass and an inertia are not negative (a massless link: 0), checked with the file's other problems
BodyMass = Annotated[Mass, Check("kg", nonnegative=True)]
BodyInertia = Annotated[Inertia, Check("kg*m^2", nonnegative=True)]


class BodyTable(FileModel):
    name: str
    """The body's name, unique in the file; joints and the driver refer to it."""
    points: list[str] = Field(min_length=1)
    """The points of ``[points]`` that belong to this body (they move with it)."""
    mass: BodyMass = 0.0
    """The body's mass."""
    inertia: BodyInertia = 0.0
    """Moment of inertia about the centre of mass, perpendicular to the plane."""
    center_of_mass: tuple[Length, Length] | str | None = None
    """Centre of mass: [x, y] in the drawing, or a point's name (default: the mean of the body's points)."""


class CounterweightTable(FileModel):
    body: str
    """The link it sits on, by name."""
    mass: BodyMass
    """Its mass."""
    position: tuple[Length, Length] | str
    """Where it sits: [x, y] in the drawing, or a point's name; it moves with its link."""
    inertia: BodyInertia = 0.0
    """Its own moment of inertia about its centre (default: a point mass)."""
    name: str = ""
    """Its name in tables and messages (default: "counterweight on <body>")."""


class PitchTable(FileModel):
    kind: Literal["circle", "eccentric", "ellipse", "samples"]
    """Gear 1's pitch curve: ``circle``, ``eccentric`` (a circle pivoted off its centre), ``ellipse`` (pivoted
    at a focus) or ``samples`` (radii at equal angles); gear 2 is its exact conjugate."""
    radius: Length | Literal["closing"] | None = None
    """Radius of a circle or an eccentric circle; ``"closing"`` sizes it to the centre distance of the
    drawing."""
    eccentricity_ratio: float | None = Field(default=None, ge=0, lt=1)
    """Eccentricity over radius of an eccentric circle, or the eccentricity of an ellipse."""
    semi_major: Length | Literal["closing"] | None = None
    """Semi-major axis of an ellipse; ``"closing"`` sizes it to the drawing."""
    radii: list[Length] | None = None
    """Pitch radii at equal angles over one turn (``samples``), interpolated by a Fourier series."""


class JointTable(FileModel):
    name: str
    """The joint's name, unique in the file; tables of joint forces use it."""
    type: Literal["revolute", "prismatic", "gear"]
    """``revolute`` (a pin), ``prismatic`` (a slider on a guide) or ``gear`` (two gears in mesh)."""
    bodies: tuple[str, str]
    """The two bodies it joins, by name; ``ground`` is the frame."""
    point: str | None = None
    """The point where a revolute or prismatic joint sits."""
    axis: Angle | None = None
    """Direction of a prismatic joint's sliding axis, from the x axis; it points *up* (bottom dead centre is
    the lowest position along it)."""
    points: tuple[str, str] | None = None
    """A gear joint: the pivots of gear 1 and gear 2 on the carrier."""
    carrier: str = "ground"
    """A gear joint: the body both gears pivot on (``ground`` for the frame)."""
    pitch: PitchTable | None = None
    orientation: Angle = 0.0
    """A gear joint: the angle of gear 1's pitch curve in the drawing (its installation phase)."""
    pressure_angle: Angle = 0.3490658503988659
    """A gear joint: the pressure angle of the teeth."""
    internal: bool = False
    """A gear joint: gear 2 is a ring gear around gear 1."""
    flank: Literal["load", "fixed"] = "load"
    """A gear joint: ``load`` (the normal force |F_t| tan φ pushes the gears apart on whichever flank is
    loaded) or ``fixed`` (the published law F_n = F_t tan φ)."""


class DriverTable(FileModel):
    body: str
    """The crank: the body the motor turns."""
    pivot: str
    """The crank's fixed pivot."""
    tip: str
    """A second point of the crank; the crank angle is that of pivot → tip from the x axis."""
    speed: AngularSpeed
    """Crank speed (constant unless ``speed_profile`` is given)."""
    speed_profile: list[tuple[str, str]] | None = None
    """Crank speed against crank angle, rows [angle, speed] from 0° up to below 360°, interpolated
    (periodic cubic spline); the angular acceleration follows from it. The angle is the crank angle
    that results show: from ``angle_datum`` (``"bdc"``: from the located bottom dead centre),
    counter-clockwise, whichever way the crank turns; the speeds' sign is that of ``speed``."""


class SettingsTable(FileModel):
    gravity: tuple[Acceleration, Acceleration] = (0.0, 0.0)
    """Gravity in the plane of the drawing, [g_x, g_y] (default: none)."""
    angle_datum: Angle | Literal["bdc"] = 0.0
    """Where crank angles count from: an angle, or ``"bdc"`` (the located bottom dead centre)."""
    n_angles: int = Field(default=360, ge=8, le=MAX_ANGLES)
    """Crank angles per revolution."""
    output: tuple[str, str] | None = None
    """The output: [body, point] whose motion is reported (default: the one slider whose guide is the
    frame; a slider on a moving guide is the stroke only when named here, and with several sliders on
    the frame one must be named)."""
    trace: list[str] = Field(default_factory=list)
    """Points whose paths are drawn (coupler curves) and whose positions, velocities and accelerations the
    table gives."""
    field_velocity: tuple[Velocity, Velocity] | None = None
    """Velocity of the machine over the ground, [v_x, v_y], for the paths over the field."""
    rated_torque: Torque | None = Field(default=None, gt=0)
    """A press's rated crank torque: with a slide output, the tonnage curve (the slide force it can
    deliver at each crank angle, T_r/|ds/dθ|), the energy per stroke and the process force checked against
    the curve are reported."""
    rated_force: Force | None = Field(default=None, gt=0)
    """A press's rated force (with ``rated_torque``): the rated point, the distance before bottom dead centre
    from which the rated torque delivers it, is reported."""
    press_stiffness: LinearStiffness | None = Field(default=None, gt=0)
    """The press's stiffness between slide and bed (frame, drive and bearings), e.g. "5 MN/mm": with a
    tabulated process force that breaks off on the working stroke, the reverse load at break-through
    is reported against the reverse capacity."""
    reverse_capacity: Dimensionless = Field(default=0.1, gt=0, le=1)
    """The reverse load the press is rated for, as a fraction of ``rated_force`` (commonly 0.1)."""
    press_damping: Dimensionless = Field(default=0.0, ge=0, lt=1)
    """Damping ratio of the frame-and-slide mode at break-through (0: undamped, an upper bound)."""

    @field_validator("angle_datum", mode="before")
    @classmethod
    def _bdc(cls, v):  # "bdc" is a word, not a quantity
        return v.strip().lower() if isinstance(v, str) and v.strip().lower() == "bdc" else v


class ProcessForceTable(FileModel):
    body: str
    """The body the process force acts on."""
    point: str
    """The point where it acts."""
    direction: Angle
    """Its direction from the x axis."""
    versus: Literal["angle", "position"]
    """Whether ``table`` is against crank ``angle`` or output ``position``."""
    table: list[tuple[str, str]] = Field(min_length=2)
    """Rows [angle or position, force], each with its unit, interpolated linearly."""


class MechanismFile(FileModel):
    """Schema of a mechanism model file."""

    model: ModelTable
    points: dict[str, tuple[Length, Length]]
    """The assembly drawing: every named point at one assembled pose, ``A = ["100 mm", "0 mm"]``. It fixes the
    link lengths and the assembly branch."""
    bodies: list[BodyTable] = Field(min_length=1)
    joints: list[JointTable] = Field(min_length=1)
    driver: DriverTable
    settings: SettingsTable = SettingsTable()
    process_forces: list[ProcessForceTable] = Field(default_factory=list)
    counterweights: list[CounterweightTable] = Field(default_factory=list)
    """Masses fixed on links to balance them, folded into their links when the model is assembled."""


@dataclass(frozen=True)
class MechanismSpec:
    """A mechanism as read from a file, with the number of crank angles to analyse."""

    mechanism: Mechanism
    n_angles: int
    trace: tuple[str, ...] = ()
    field_velocity: tuple[float, float] | None = None
    rated_torque: float | None = None  # N·m
    rated_force: float | None = None  # N
    frame: Any = None  # mechdyn.mechanism.tonnage.Frame

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
    return ProcessForce(pf.body, pf.point, TabulatedForce(pf.versus, xs_a, fs_a, pf.direction))


def _profile(table: list[tuple[str, str]], speed: float):
    """A periodic cubic spline of crank speed against crank angle from the angle datum."""
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

    def rates(angle: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        t = np.mod(angle, 2 * math.pi)
        omega = spline(t)
        return omega, omega * slope(t)  # θ̈ = θ̇ dθ̇/dθ

    return rates


def _gear(j: JointTable, points: dict[str, tuple[float, float]]) -> GearJoint:
    """A gear joint from its table; ``"closing"`` sizes a noncircular curve to the drawing's centre
    distance."""
    from mechdyn.mechanism import pitch

    if j.points is None or j.pitch is None:
        raise ValueError("a gear joint needs points (the two pivots) and a pitch table")
    if j.point is not None or j.axis is not None:
        raise ValueError("a gear joint has points, not point or axis; remove them")
    for p in j.points:
        if p not in points:
            raise ValueError(f"point {p!r} is not in the drawing")
    a = float(np.hypot(*np.subtract(points[j.points[1]], points[j.points[0]])))
    t = j.pitch
    if t.kind == "circle":
        if not isinstance(t.radius, float):
            raise ValueError('pitch: a circle needs its radius, e.g. radius = "20 mm"')
        curve = pitch.circle(t.radius)
    elif t.kind == "eccentric":
        eps = t.eccentricity_ratio or 0.0
        rho = t.radius
        if rho == "closing":
            rho = a / pitch.closing_centre_distance(pitch.eccentric_circle(1.0, eps))
        if not isinstance(rho, float):
            raise ValueError('pitch: an eccentric gear needs radius (or "closing") and eccentricity_ratio')
        curve = pitch.eccentric_circle(rho, eps * rho)
    elif t.kind == "ellipse":
        A = a / 2 if t.semi_major == "closing" else t.semi_major
        if not isinstance(A, float) or t.eccentricity_ratio is None:
            raise ValueError('pitch: an ellipse needs semi_major (or "closing") and eccentricity_ratio')
        curve = pitch.ellipse_about_focus(A, t.eccentricity_ratio)
    else:
        if not t.radii:
            raise ValueError("pitch: samples need radii over one turn")
        curve = pitch.sampled(t.radii, j.name)
    return GearJoint(
        j.name,
        j.bodies,
        j.points,
        curve,
        carrier=j.carrier,
        orientation=j.orientation,
        pressure_angle=j.pressure_angle,
        internal=j.internal,
        flank=j.flank,
    )


def build(source: ModelSource) -> MechanismSpec:
    """Builder for ``[model] type = "mechanism"``."""
    f = validate(MechanismFile, source)
    bodies = []
    for i, b in enumerate(f.bodies):
        with field_context(source, f"[[bodies]] #{i + 1} (name = {b.name!r})"):
            bodies.append(Body(b.name, tuple(b.points), b.mass, b.inertia, b.center_of_mass))
    joints: list[Revolute | Prismatic | GearJoint] = []
    for i, j in enumerate(f.joints):
        with field_context(source, f"[[joints]] #{i + 1} (name = {j.name!r})"):
            if j.type == "gear":
                joints.append(_gear(j, f.points))
                continue
            if j.point is None:
                raise ValueError(f"a {j.type} joint needs its point")
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
    weights = []
    for i, c in enumerate(f.counterweights):
        with field_context(source, f"[[counterweights]] #{i + 1} (body = {c.body!r})"):
            w = Counterweight(c.body, c.mass, c.position, c.inertia, c.name)
        tables[w.name] = f"[[counterweights]] #{i + 1} (body = {c.body!r})"
        weights.append(w)
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
            counterweights=tuple(weights),
        )
    with field_context(source, "[settings] → trace"):
        for p in f.settings.trace:
            if p not in mech.points:
                raise ValueError(f"point {p!r} is not in the drawing")
    st = f.settings
    with field_context(source, "[settings] → rated_torque"):
        if st.rated_force is not None and st.rated_torque is None:
            raise ValueError('rated_force needs rated_torque (the rated crank torque, e.g. "1600 kN*m")')
        if st.rated_torque is not None and mech.output_joint() is None:
            raise ValueError("a rated torque gives a press's tonnage: the mechanism needs a slide output")
    frame = None
    if st.press_stiffness is not None:
        from mechdyn.mechanism.tonnage import Frame

        if st.rated_torque is None:
            raise ModelFileError(
                source.path,
                "[settings] → press_stiffness",
                "press_stiffness checks a press's reverse load: give its rated_torque and rated_force too",
                st.press_stiffness,
            )
        frame = Frame(st.press_stiffness, st.reverse_capacity, st.press_damping)
    return MechanismSpec(
        mech, st.n_angles, tuple(st.trace), st.field_velocity, st.rated_torque, st.rated_force, frame
    )
