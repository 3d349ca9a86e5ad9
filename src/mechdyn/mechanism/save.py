"""A :class:`~mechdyn.mechanism.Mechanism` as a mechanism model file (:func:`mechdyn.save`).

The drawing, the bodies (as given, without their counterweights, which are written as
``[[counterweights]]``), the joints (revolute, prismatic with its axis, gear pairs with their pitch
curves), the driver and gravity are written exactly, every float as its ``repr`` in its SI unit; so
are the ``[settings]`` of a loaded file (angle datum, output, number of crank angles, traced points,
field velocity). A planting mechanism loaded from its design file (``type = "planting_mechanism"``)
is written as its ``[design]``, the variables it is built from.

What a mechanism file holds as tables is written from the functions its builder made of them:
process forces tabulated against crank angle or output position, a driver's speed profile, the
radii of a sampled pitch curve. A process force or a speed profile that is a Python function has no
file form, and is refused. A pitch curve is written as the circle, eccentric circle, ellipse or
sampled radii it was made from (:mod:`mechdyn.mechanism.pitch`), found in its radius function and
checked: the curve the file builds must have the same radius function, to the last bit, or the
curve is refused. An eccentric circle's eccentricity is written as a ratio of its radius; the writer
picks, among the floats next to e/ρ, one that gives back e, and refuses the rare e that none does.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mechdyn.errors import MechdynError
from mechdyn.io.save import model_header, written_by
from mechdyn.io.writing import TomlDocument, quantity_text
from mechdyn.mechanism.model import Counterweight, GearJoint, Mechanism, ProcessForce, TabulatedForce

__all__ = ["to_toml"]

# the design variables of a planting-mechanism file and their SI units (PlanterDesign's fields)
_DESIGN_UNITS = {
    "eccentricity_ratio": "",
    "alpha": "rad",
    "beta": "rad",
    "arm_radius": "m",
    "fork_length": "m",
    "fork_angle": "rad",
    "com_offset": "m",
    "arm_mass": "kg",
    "idler_mass": "kg",
    "planet_mass": "kg",
    "arm_inertia": "kg*m^2",
    "idler_inertia": "kg*m^2",
    "planet_inertia": "kg*m^2",
    "speed": "rad/s",
    "gravity": "m/s^2",
}


def _q(value: float, unit: str) -> Any:
    return quantity_text(float(value), unit)


def _pair(values: Any, unit: str) -> list[Any]:
    return [_q(v, unit) for v in values]


def to_toml(model: Mechanism, settings: Any = None, *, path: Any, source: Any = None) -> str:
    """The model file of a mechanism: a ``type = "mechanism"`` file body by body, or, for a planting
    mechanism loaded from its design file, that file's ``[design]`` and ``[settings]``.

    Parameters
    ----------
    model : Mechanism
        The mechanism; drawing points in m, masses in kg, inertias in kg·m², angles (prismatic axes,
        gear orientations and pressure angles, the angle datum) in rad, the crank speed in rad/s,
        gravity in m/s², pitch radii in m, all written exactly.
    settings : MechanismSpec, optional
        The record of a loaded file (:attr:`mechdyn.io.LoadedModel.settings`): its number of crank
        angles, traced points and field velocity (m/s) are written too.
    path : Path
        The file to be written.
    source : ModelSource, optional
        The file the model was loaded from (its description and source are kept; a planting
        mechanism's design is read from it).

    Returns
    -------
    str
        The TOML text.

    Raises
    ------
    MechdynError
        For what a mechanism file cannot hold: a process force or a speed profile given as a Python
        function, a pitch curve the file cannot rebuild exactly; each names the element.
    """
    if source is not None and source.model_type == "planting_mechanism" and _is_the_design(model, settings):
        return _planter_text(model, settings, source)
    return _mechanism_text(model, settings, source)


# -- a planting mechanism by its design ---------------------------------------------------------


def _is_the_design(model: Mechanism, settings: Any) -> bool:
    """Whether ``model`` is the mechanism its file's design built (not one put in its place)."""
    built = getattr(settings, "mechanism", None)
    return built is model or built == model


def _planter_text(model: Mechanism, spec: Any, source: Any) -> str:
    from mechdyn.io.modelfile import validate
    from mechdyn.mechanism.planter import PlanterFile

    design = validate(PlanterFile, source).design
    doc = TomlDocument()
    doc.comment(written_by("A planting mechanism's design"))
    doc.table("model", model_header("planting_mechanism", model.name, source))
    doc.table("design", {k: _q(getattr(design, k), unit) for k, unit in _DESIGN_UNITS.items()})
    doc.table("settings", _spec_settings(spec))
    return doc.text()


def _spec_settings(spec: Any) -> dict[str, Any]:
    """The ``[settings]`` that a loaded file's record keeps besides its mechanism."""
    if spec is None:
        return {}
    return {
        "n_angles": int(spec.n_angles),
        "trace": list(spec.trace) or None,
        "field_velocity": _pair(spec.field_velocity, "m/s") if spec.field_velocity is not None else None,
        "rated_torque": _q(spec.rated_torque, "N*m") if getattr(spec, "rated_torque", None) else None,
        "rated_force": _q(spec.rated_force, "N") if getattr(spec, "rated_force", None) else None,
        **_frame_settings(getattr(spec, "frame", None)),
    }


def _frame_settings(frame: Any) -> dict[str, Any]:
    """A press frame's ``[settings]`` (stiffness, reverse capacity, damping), none without one."""
    if frame is None:
        return {}
    return {
        "press_stiffness": _q(frame.stiffness, "N/m"),
        "reverse_capacity": float(frame.reverse_capacity),
        "press_damping": float(frame.damping_ratio),
    }


# -- a mechanism body by body --------------------------------------------------------------------


def _mechanism_text(model: Mechanism, spec: Any, source: Any) -> str:
    doc = TomlDocument()
    doc.comment(written_by("A mechanism"))
    doc.table("model", model_header("mechanism", model.name, source))
    doc.table("points", {name: _pair(xy, "m") for name, xy in model.points.items()})
    for b in model.bare_bodies:  # the counterweights are written on their own
        com = b.center_of_mass
        row = {
            "name": b.name,
            "points": list(b.points),
            "mass": _q(b.mass, "kg"),
            "inertia": _q(b.inertia, "kg*m^2"),
            "center_of_mass": com if isinstance(com, str) or com is None else _pair(com, "m"),
        }
        doc.table("bodies", row, array=True)
    for j in model.joints:
        _joint(doc, j, source)
    doc.table("driver", _driver(model))
    datum = model.angle_datum if model.angle_datum == "bdc" else _q(model.angle_datum, "rad")
    table = {
        "gravity": _pair(model.gravity, "m/s^2"),
        "angle_datum": datum,
        "output": list(model.output) if model.output is not None else None,
    }
    doc.table("settings", table | _spec_settings(spec))
    for pf in model.process_forces:
        doc.table("process_forces", _process_force(pf), array=True)
    for w in model.counterweights:
        doc.table("counterweights", _counterweight(w), array=True)
    return doc.text()


def _counterweight(w: Counterweight) -> dict[str, Any]:
    """A counterweight's row: its link, mass (kg), position (m, or a point's name), own inertia
    (kg·m², when it has one) and its name (when not the default)."""
    row: dict[str, Any] = {
        "body": w.body,
        "mass": _q(w.mass, "kg"),
        "position": w.position if isinstance(w.position, str) else _pair(w.position, "m"),
    }
    if w.inertia:
        row["inertia"] = _q(w.inertia, "kg*m^2")
    if w.name != f"counterweight on {w.body}":
        row["name"] = w.name
    return row


def _same_kind(source: Any) -> bool:
    return source is not None and source.model_type == "mechanism"


def _joint(doc: TomlDocument, j: Any, source: Any) -> None:
    row: dict[str, Any] = {"name": j.name}
    # the joint protocol says what a joint is: it pins two bodies at a point, slides one along a line
    # of the other, or rolls two pitch curves on each other (a gear joint holds its curve)
    if j.pins or j.slides:
        row |= {"type": "prismatic" if j.slides else "revolute", "bodies": list(j.bodies), "point": j.point}
        if j.slides:
            row["axis"] = _q(j.axis, "rad")
        doc.table("joints", row, array=True)
        return
    if getattr(j, "curve", None) is None:
        raise MechdynError(
            f"mechdyn.save: joint {j.name!r} is a {type(j).__name__}; a mechanism file holds revolute, "
            "prismatic and gear joints"
        )
    pitch = _pitch(j, source)
    row |= {
        "type": "gear",
        "bodies": list(j.bodies),
        "points": list(j.points),
        "carrier": j.carrier,
        "pitch": None if pitch["kind"] == "samples" else pitch,
        "orientation": _q(j.orientation, "rad"),
        "pressure_angle": _q(j.pressure_angle, "rad"),
        "internal": bool(j.internal),
        "flank": j.flank,
    }
    doc.table("joints", row, array=True)
    if pitch["kind"] == "samples":  # a long list of radii reads better as a table of its own
        doc.table("joints.pitch", pitch)


def _driver(model: Mechanism) -> dict[str, Any]:
    d = model.driver
    row = {"body": d.body, "pivot": d.pivot, "tip": d.tip, "speed": _q(d.speed, "rad/s")}
    if d.profile is None:
        return row
    held = _made_by(d.profile, "mechdyn.mechanism.schema", "_profile.<locals>.rates")
    if held is None:
        raise MechdynError(
            f"mechdyn.save: the driver's speed profile is a Python function ({_named(d.profile)}); a "
            "mechanism file holds a speed profile only as rows [angle, speed] (speed_profile), so it "
            "cannot be written. Save the mechanism with a constant speed "
            "(dataclasses.replace(mechanism, driver=dataclasses.replace(mechanism.driver, profile=None))) "
            "and add the rows to the file by hand"
        )
    spline = held["spline"]  # through the rows' angles and speeds, closed at 2π with the first speed
    angles, speeds = spline.x[:-1], spline.c[-1]  # a cubic's constant term is its value at the knot
    row["speed_profile"] = [[_q(a, "rad"), _q(abs(w), "rad/s")] for a, w in zip(angles, speeds, strict=True)]
    return row


def _process_force(pf: ProcessForce) -> dict[str, Any]:
    table = pf.force
    if not isinstance(table, TabulatedForce):
        raise MechdynError(
            f"mechdyn.save: the process force on body {pf.body!r} at point {pf.point!r} is a Python "
            f"function ({_named(pf.force)}); a mechanism file holds a process force only as a table "
            "against crank angle or output position ([[process_forces]]), so it cannot be written. Save "
            "the mechanism without it (dataclasses.replace(mechanism, process_forces=())) and add its "
            "table to the file by hand"
        )
    unit = "rad" if table.versus == "angle" else "m"
    rows = [[_q(x, unit), _q(f, "N")] for x, f in zip(table.x, table.magnitude, strict=True)]
    return {
        "body": pf.body,
        "point": pf.point,
        "direction": _q(table.direction, "rad"),
        "versus": table.versus,
        "table": rows,
    }


def _named(fn: Any) -> str:
    return str(getattr(fn, "__qualname__", None) or type(fn).__name__)


def _made_by(fn: Any, module: str, qualname: str) -> dict[str, Any] | None:
    """The variables a function made by ``module``'s ``qualname`` closes over, by name; None for
    another function. A mechanism keeps the functions its file's tables were made into, not the
    tables: these variables are the tables."""
    if getattr(fn, "__module__", None) != module or getattr(fn, "__qualname__", None) != qualname:
        return None
    return _closure(fn)


def _closure(fn: Any) -> dict[str, Any]:
    cells = getattr(fn, "__closure__", None) or ()
    return dict(zip(fn.__code__.co_freevars, (c.cell_contents for c in cells), strict=True))


# -- pitch curves --------------------------------------------------------------------------------

_PITCH_MAKERS = {
    "circle.<locals>.<lambda>": "circle",
    "eccentric_circle.<locals>.<lambda>": "eccentric",
    "ellipse_about_focus.<locals>.<lambda>": "ellipse",
    "sampled.<locals>.radius": "samples",
}


def _pitch(j: GearJoint, source: Any) -> dict[str, Any]:
    """Gear 1's ``pitch`` table: the curve's kind and the numbers it was made from, checked to build
    the same radius function."""
    from mechdyn.mechanism import pitch

    radius = j.curve.radius
    kind = _PITCH_MAKERS.get(getattr(radius, "__qualname__", ""))
    if kind is None or getattr(radius, "__module__", None) != pitch.__name__:
        raise MechdynError(
            f"mechdyn.save: gear joint {j.name!r} has a pitch curve {j.curve.name!r} whose radius is a "
            f"Python function ({_named(radius)}); a mechanism file holds circles, eccentric circles, "
            "ellipses about a focus and sampled radii (mechdyn.mechanism.pitch)"
        )
    held = _closure(radius)
    if kind == "circle":
        table: dict[str, Any] = {"kind": kind, "radius": _q(held["radius"], "m")}
        return _checked(j, table, [pitch.circle(float(held["radius"]))])
    if kind == "ellipse":
        A, eps = float(held["A"]), float(held["eps"])
        table = {"kind": kind, "semi_major": _q(A, "m"), "eccentricity_ratio": eps}
        return _checked(j, table, [pitch.ellipse_about_focus(A, eps)])
    if kind == "eccentric":
        rho, e = float(held["rho"]), float(held["e"])
        ratio = _ratio_giving(e, rho)
        if ratio is None:
            raise MechdynError(
                f"mechdyn.save: gear joint {j.name!r}: a mechanism file gives an eccentric circle's "
                f"eccentricity as a ratio of its radius, and no ratio times the radius {rho!r} m gives "
                f"its eccentricity {e!r} m to the last bit; build the curve as "
                "pitch.eccentric_circle(radius, ratio * radius) to save it"
            )
        table = {"kind": kind, "radius": _q(rho, "m"), "eccentricity_ratio": ratio}
        return _checked(j, table, [pitch.eccentric_circle(rho, ratio * rho)])
    # sampled radii: the curve keeps their Fourier series; the file it came from keeps the radii
    candidates = [r for r in (_source_radii(j.name, source), _radii_from_series(held)) if r is not None]
    for radii in candidates:
        table = {"kind": kind, "radii": [_q(r, "m") for r in radii]}
        if _same_radius(j.curve, pitch.sampled(radii, j.name)):
            return table
    raise MechdynError(
        f"mechdyn.save: gear joint {j.name!r} has a sampled pitch curve, which keeps the Fourier series of "
        "its radii rather than the radii; the radii recovered from the series rebuild it only to "
        "rounding, so the file would not load back equal. Load the mechanism from a file that gives "
        'the radii (pitch = { kind = "samples", radii = [...] }) to save it'
    )


def _checked(j: GearJoint, table: dict[str, Any], rebuilt: list[Any]) -> dict[str, Any]:
    if not _same_radius(j.curve, rebuilt[0]):  # the pitch module changed how it makes its curves
        raise MechdynError(
            f"mechdyn.save: gear joint {j.name!r}: the {table['kind']} pitch curve the file would hold "
            f"does not rebuild the curve {j.curve.name!r} exactly"
        )
    return table


def _same_radius(curve: Any, rebuilt: Any) -> bool:
    """Whether two pitch curves are made the same way of the same numbers (so equal to the bit)."""
    a, b = curve.radius, rebuilt.radius
    if curve.circular != rebuilt.circular or a.__code__ is not b.__code__:
        return False
    held, again = _closure(a), _closure(b)
    return held.keys() == again.keys() and all(
        np.array_equal(np.asarray(held[k]), np.asarray(again[k])) for k in held
    )


def _ratio_giving(e: float, rho: float) -> float | None:
    """A float ratio ε with ε·ρ == e exactly, among e/ρ and the floats next to it; None if none."""
    if e == 0.0:
        return 0.0
    ratio = e / rho
    below = above = ratio
    candidates = [ratio]
    for _ in range(8):
        below, above = math.nextafter(below, -math.inf), math.nextafter(above, math.inf)
        candidates += [above, below]
    return next((r for r in candidates if r * rho == e and 0.0 <= r < 1.0), None)


def _radii_from_series(held: dict[str, Any]) -> list[float]:
    """The radii a sampled curve's series came from, to rounding (its weighted coefficients c·n)."""
    c, w = np.asarray(held["c"]), np.asarray(held["w"])
    n = 2 * (c.size - 1) if w[-1] == 1.0 else 2 * c.size - 1  # an even count halves its last weight
    return [float(r) for r in np.fft.irfft(c * n, n)]


def _source_radii(joint: str, source: Any) -> list[float] | None:
    """The radii of the joint's sampled pitch curve in the file it was loaded from, SI."""
    if not _same_kind(source):
        return None
    from mechdyn.io.modelfile import validate
    from mechdyn.mechanism.schema import MechanismFile

    for j in validate(MechanismFile, source).joints:
        if j.name == joint and j.pitch is not None and j.pitch.radii:
            return [float(r) for r in j.pitch.radii]
    return None
