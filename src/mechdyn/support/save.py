"""A :class:`~mechdyn.support.MountedMachine` and its load as a support model file
(:func:`mechdyn.save`).

The machine is written exactly: its rigid body, its mounts (stiffness and damping along their local
axes) or its one-degree-of-freedom ``[support]``, gravity and the coordinates kept. A mount's axes
other than the machine's are written as the three angles of ``orientation`` and a rotor's axis other
than x, y or z as a direction: the writer picks, among the floats next to them, those that give back
the same matrix and unit vector where one does, else they come back within rounding (1e-16).

The load is what a support file can hold: unbalanced rotors (exactly), a vertical force as samples
over one period or as harmonics (to rounding, about 1e-16 of the largest value: the file gives them
in the time domain or as amplitude and phase), or, for a loaded file, its mechanism model file
(named relative to the new file).
"""

from __future__ import annotations

import itertools
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from mechdyn.errors import MechdynError
from mechdyn.io.save import model_header, written_by
from mechdyn.io.writing import TomlDocument, quantity_text
from mechdyn.support.excitation import PeriodicLoad, series_on_grid
from mechdyn.support.model import PLANAR, SPATIAL, Mount, MountedMachine

__all__ = ["to_toml"]


def _q(value: float, unit: str) -> Any:
    return quantity_text(float(value), unit)


def _vector(values: Any, unit: str) -> list[Any]:
    return [_q(v, unit) for v in np.asarray(values, dtype=float)]


def _single_dof(machine: MountedMachine) -> tuple[float, float] | None:
    """(k, ζ) when the machine is :meth:`MountedMachine.single_dof`'s model, else None.

    ζ is chosen so that the file's c = 2 ζ √(k m) gives back the machine's damping exactly (among the
    floats next to c / (2 √(k m))) where one does.
    """
    if machine.dofs != ("z",):
        return None
    (m,) = machine.mounts if len(machine.mounts) == 1 else (None,)
    body = machine.body
    if (
        m is None
        or m.name != "support"
        or m.anchored
        or np.any(m.position != 0.0)
        or np.any(m.stiffness[:2] != 0.0)
        or np.any(m.damping[:2] != 0.0)
        or not np.array_equal(m.axes, np.eye(3))
        or np.any(body.center_of_mass != 0.0)
        or np.any(body.inertia != 0.0)
    ):
        raise MechdynError(
            "mechdyn.save: a support file keeps the vertical coordinate alone (dofs = ('z',)) only for "
            "its one-degree-of-freedom [support], MountedMachine.single_dof's model (one mount "
            "'support' at the origin, vertical stiffness and damping, no inertia); give this machine "
            "dofs = PLANAR or SPATIAL, or build it with MountedMachine.single_dof"
        )
    k, c = float(m.stiffness[2]), float(m.damping[2])
    root = math.sqrt(k * body.mass)
    zeta = c / (2.0 * root)
    candidates = [zeta]
    up = down = zeta
    for _ in range(8):
        up, down = math.nextafter(up, math.inf), math.nextafter(down, -math.inf)
        candidates += [up, down]
    exact = [z for z in candidates if 2.0 * z * root == c]
    return k, exact[0] if exact else zeta


def _orientation(mount: Mount) -> list[Any] | None:
    """The ``orientation`` angles of a mount's axes (None for the machine's axes), chosen so that
    :meth:`Mount.with_orientation` gives back the same axes exactly where one of the floats next to
    the angles does (a matrix given directly may come back within rounding)."""
    axes = np.asarray(mount.axes, dtype=float)
    if np.array_equal(axes, np.eye(3)):
        return None
    from scipy.spatial.transform import Rotation

    angles = Rotation.from_matrix(axes).as_euler("xyz")
    best = _preimage(axes, [float(a) for a in angles], lambda v: Rotation.from_euler("xyz", v).as_matrix())
    return _vector(best, "rad")


def _near(x: float) -> list[float]:
    """``x``, the floats next to it, and the round numbers it may have been (a 0 that the conversion
    turned into 1e-17)."""
    up = math.nextafter(x, math.inf)
    down = math.nextafter(x, -math.inf)
    out = [x, up, down, math.nextafter(up, math.inf), math.nextafter(down, -math.inf)]
    out += [float(f"{x:.15g}"), float(f"{x:.12g}")]
    if abs(x) < 1e-12:
        out.append(0.0)
    return list(dict.fromkeys(out))


def _preimage(target: np.ndarray, guess: list[float], f: Any) -> list[float]:
    """Numbers near ``guess`` that ``f`` maps onto ``target`` exactly, if any; else those closest."""
    best, best_error = guess, math.inf
    for trial in itertools.product(*(_near(x) for x in guess)):
        error = float(np.abs(f(np.array(trial)) - target).max())
        if error < best_error:
            best, best_error = list(trial), error
        if error == 0.0:
            break
    return best


def _axis(axis: np.ndarray) -> Any:
    """A rotor's axis as a file gives it: ``"x"``, ``"y"``, ``"z"``, or a direction that normalises
    to the same unit vector (the rotor normalises what it is given)."""
    for name, unit in zip("xyz", np.eye(3), strict=True):
        if np.array_equal(axis, unit):
            return name
    for scale in (np.abs(axis).max(), np.abs(axis[axis != 0]).min()):
        v = axis / scale
        if np.array_equal(v / np.linalg.norm(v), axis):
            return [float(x) for x in v]
    return _preimage(axis, [float(x) for x in axis], lambda v: v / np.linalg.norm(v))


def _load(doc: TomlDocument, load: PeriodicLoad, speed_range: Any) -> None:
    if load.rotors:
        doc.table("excitation", {"speed_range": _vector(speed_range, "rad/s") if speed_range else None})
        for r in load.rotors:
            row = {
                "name": r.name,
                "unbalance": _q(r.unbalance, "kg*m"),
                "speed": _q(r.speed, "rad/s"),
                "axis": _axis(np.asarray(r.axis, dtype=float)),
                "position": _vector(r.position, "m"),
                "phase": _q(r.phase, "rad"),
            }
            doc.table("excitation.rotors", row, array=True)
        return
    c = np.asarray(load.coefficients)
    others = [
        name for i, name in enumerate(("Fx", "Fy", "Fz", "Mx", "My", "Mz")) if i != 2 and np.any(c[:, i])
    ]
    if others or np.imag(c[0, 2]) != 0.0:
        raise MechdynError(
            "mechdyn.save: a support file holds a vertical force (force_z samples or harmonics), "
            "unbalanced rotors or a mechanism model file; this load also has "
            f"{', '.join(others) or 'a complex mean'}: save the support file loaded with mechdyn.load "
            "(its mechanism file is referenced), or give a load of Fz alone"
        )
    fz = c[:, 2]
    if load.n_samples is not None:
        samples = series_on_grid(fz, load.n_samples)
        doc.table("excitation", {"period": _q(load.period, "s"), "force_z": _vector(samples, "N")})
        return
    rows = [
        [h, _q(2.0 * abs(a), "N"), _q(float(np.angle(a)), "rad")] for h, a in enumerate(fz) if h and a != 0
    ]
    mean = float(np.real(fz[0]))
    doc.table(
        "excitation",
        {"period": _q(load.period, "s"), "harmonics": rows, "mean_force_z": _q(mean, "N") if mean else None},
    )


def _mechanism(doc: TomlDocument, e: Any, path: Path) -> None:
    """The ``[excitation]`` of a mechanism's load: its file relative to the new file, and placement."""
    where = Path(os.path.relpath(Path(e.path).resolve(), path.resolve().parent)).as_posix()
    p = e.placement
    doc.table(
        "excitation",
        {
            "mechanism": where,
            "angles": int(e.angles),
            "origin": _vector(p.origin, "m"),
            "x_axis": [float(v) for v in p.x_axis],
            "y_axis": [float(v) for v in p.y_axis],
        },
    )


def _foundation(doc: TomlDocument, foundation: Any, floor_points: Any) -> None:
    """``[foundation]`` and ``[foundation.soil]``: the block by its mass, centre of mass, inertia and
    base (exactly), the soil as the half-space it came from or as its springs and dashpots."""
    block = foundation.block
    J = np.asarray(block.inertia, dtype=float)
    if np.any(J != np.diag(np.diag(J))):
        raise MechdynError(
            "mechdyn.save: a foundation block with products of inertia cannot be written: [foundation] "
            "takes its three moments about axes parallel to x, y, z"
        )
    table: dict[str, Any] = {
        "mass": _q(block.mass, "kg"),
        "center_of_mass": _vector(block.center_of_mass, "m"),
        "inertia": _vector(np.diag(J), "kg*m^2"),
        "base": _vector(foundation.base, "m"),
        "footprint": None if foundation.footprint is None else _vector(foundation.footprint, "m"),
        "floor_points": None if floor_points is None else [_vector(p, "m") for p in floor_points],
    }
    doc.table("foundation", table)
    soil = foundation.soil
    if soil is not None:
        doc.table(
            "foundation.soil",
            {
                "shear_modulus": _q(soil.shear_modulus, "Pa"),
                "poisson_ratio": float(soil.poisson_ratio),
                "density": _q(soil.density, "kg/m^3"),
            },
        )
        return
    K, C = foundation.soil_stiffness, foundation.soil_damping
    doc.table(
        "foundation.soil",
        {
            "stiffness": _vector(K[:3], "N/m"),
            "rotational_stiffness": _vector(K[3:], "N*m/rad"),
            "damping": _vector(C[:3], "N*s/m"),
            "rotational_damping": _vector(C[3:], "N*m*s/rad"),
        },
    )


def to_toml(
    model: MountedMachine, settings: Any = None, *, path: Path, source: Any = None, load: Any = None
) -> str:
    """The support model file of a machine on its supports and its load.

    Parameters
    ----------
    model : MountedMachine
        The machine: mass in kg, centre of mass in m, inertia in kg·m², mount positions in m,
        stiffness in N/m, damping in N·s/m, gravity in m/s², written exactly; its mounts' axes as
        ``orientation`` angles in rad.
    settings : SupportSpec, optional
        The loaded file's record: its load (a mechanism file, samples, harmonics or rotors), the
        start-up settings and the rotors' speed range.
    path : Path
        The file to be written (a mechanism file is named relative to it).
    source : ModelSource, optional
        The file the model was loaded from (its description and source are kept).
    load : PeriodicLoad, optional
        The load, for a machine built in Python (instead of the settings' load): unbalanced rotors,
        or a vertical force alone (N; samples or harmonics).

    Returns
    -------
    str
        The TOML text.

    Raises
    ------
    MechdynError
        Without a load; for a load the file cannot hold (horizontal components, a moment) or a
        machine it cannot (a one-coordinate model that is not the one-degree-of-freedom support).
    """
    if load is None and settings is None:
        raise MechdynError(
            "mechdyn.save: a support file needs the machine's load; give it: "
            "mechdyn.save(machine, path, load=PeriodicLoad.from_harmonics(...)) (a vertical force) or "
            "load=PeriodicLoad.from_unbalance(rotors)"
        )
    if load is not None and not isinstance(load, PeriodicLoad):
        raise MechdynError(
            f"mechdyn.save: load is a {type(load).__name__}; give a mechdyn.support.PeriodicLoad"
        )
    doc = TomlDocument()
    doc.comment(written_by("A machine on its supports"))
    doc.table("model", model_header("support", model.name, source))
    body = model.body
    J = np.asarray(body.inertia, dtype=float)
    single = _single_dof(model)
    if single is not None:
        doc.table("machine", {"mass": _q(body.mass, "kg")})
        doc.table("support", {"stiffness": _q(single[0], "N/m"), "damping_ratio": float(single[1])})
    else:
        if model.dofs not in (PLANAR, SPATIAL):
            raise MechdynError(
                f"mechdyn.save: a support file keeps the coordinates {PLANAR} (planar) or all six "
                f"(spatial); this machine keeps {model.dofs}"
            )
        doc.table(
            "machine",
            {
                "mass": _q(body.mass, "kg"),
                "center_of_mass": _vector(body.center_of_mass, "m"),
                "inertia": _vector(np.diag(J), "kg*m^2"),
                "inertia_products": _vector([J[0, 1], J[0, 2], J[1, 2]], "kg*m^2"),
            },
        )
        estimates = getattr(settings, "estimates", {}) or {}
        for m in model.mounts:
            drawn = estimates.get(m.name)
            note = (
                f"stiffness and damping as estimated from the drawing ({drawn.source}), written as numbers"
                if drawn is not None
                else ""
            )
            row = {
                "name": m.name,
                "position": _vector(m.position, "m"),
                "stiffness": _vector(m.stiffness, "N/m"),
                "damping": _vector(m.damping, "N*s/m"),
                "orientation": _orientation(m),
                "anchored": True if m.anchored else None,
            }
            doc.table("mounts", row, array=True, note=note)
    excitation = load if load is not None else getattr(settings, "excitation", None)
    if isinstance(excitation, PeriodicLoad):
        _load(doc, excitation, getattr(settings, "speed_range", None))
    elif excitation is not None and hasattr(excitation, "placement"):
        _mechanism(doc, excitation, path)
    else:
        raise MechdynError(f"mechdyn.save: cannot write a support load of type {type(excitation).__name__}")
    analysis: dict[str, Any] = {}
    if single is None:
        analysis["dofs"] = "planar" if model.dofs == PLANAR else "spatial"
    table = getattr(settings, "settings", None)
    if table is not None:
        analysis["start_up_cycles"] = int(table.start_up_cycles)
        analysis["start_up_method"] = table.start_up_method
        if table.machine_group is not None:
            analysis["machine_group"] = int(table.machine_group)
        if table.foundation != "auto":
            analysis["foundation"] = table.foundation
        if table.vibration_points is not None:
            analysis["vibration_points"] = [[_q(x, "m") for x in p] for p in table.vibration_points]
        if table.separation_margin != 0.2:
            analysis["separation_margin"] = float(table.separation_margin)
    analysis["gravity"] = _q(model.gravity, "m/s^2")
    doc.table("analysis", analysis)
    if getattr(settings, "foundation", None) is not None:
        _foundation(doc, settings.foundation, getattr(settings, "floor_points", None))
    return doc.text()
