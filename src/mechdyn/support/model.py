"""A rigid machine on elastic mounts: the body, the mounts and the assembled M, K, C.

The machine is one rigid body with six coordinates about its centre of mass, q = (x, y, z, rx, ry,
rz): small translations of the centre of mass and small rotations about the machine axes (z up).
A mount is a point spring and damper along three local axes; the displacement of the body at the
mount is u = t + θ × r = T q with T = [I, −[r]×] and r the mount's position from the centre of mass,
so the mount contributes Tᵀ R k Rᵀ T to K (R holds the mount's axes as columns) and likewise to C.
The machine may keep only some of the coordinates: ``("z",)`` is the one-degree-of-freedom model
(the machine moving up and down on its support), ``("x", "z", "ry")`` the planar model in the
vertical x–z plane (rocking about y), all six the spatial model. (E.g. Harris & Piersol, *Shock and
Vibration Handbook*, ch. 30 "Theory of vibration isolation", rigid body on resilient supports.)
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.checks import check_array, check_number
from mechdyn.errors import ModelError
from mechdyn.units import STANDARD_GRAVITY, si_field

if TYPE_CHECKING:
    import pandas as pd

__all__ = [
    "DOFS",
    "MAX_DAMPING_RATIO",
    "PLANAR",
    "SPATIAL",
    "Mount",
    "MountedMachine",
    "RigidBody",
    "model_frame",
]

MAX_DAMPING_RATIO = 10.0
"""The largest damping ratio ζ a support may have: ten times critical, far beyond any mount (rubber
has ζ ≈ 0.05, a viscous damper about 1); more only makes the start-up integration stiff."""

DOFS = ("x", "y", "z", "rx", "ry", "rz")
SPATIAL = DOFS
PLANAR = ("x", "z", "ry")
_MOTION = {
    "x": "sliding along x",
    "y": "sliding along y",
    "z": "bouncing along z",
    "rx": "rolling about x",
    "ry": "pitching about y",
    "rz": "yawing about z",
}


def _vector(owner: str, field: str, value: Any, unit: str, n: int = 3, **rule: Any) -> np.ndarray:
    """``n`` quantities (or SI numbers) as an array in ``unit``, each checked by
    :func:`~mechdyn.units.si_field` (finite, within the unit's magnitude limit, and ``rule``)."""
    if isinstance(value, str) or np.ndim(value) == 0 or len(value) != n:
        raise ModelError(f"{value!r} must be {n} values in {unit}", element=owner, field=field)
    return np.array([si_field(owner, field, v, unit, **rule) for v in value])


def _skew(r: np.ndarray) -> np.ndarray:
    """[r]×, with [r]× v = r × v."""
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


@dataclass(frozen=True)
class RigidBody:
    """The machine as one rigid body.

    Parameters
    ----------
    mass : float or quantity
        kg, from 1e-9 to 1e8 kg.
    center_of_mass : (x, y, z)
        m, in machine coordinates (z up), each at most 1e3 m in magnitude.
    inertia : (3,) or (3, 3)
        Moments of inertia about axes through the centre of mass parallel to x, y, z (kg·m²), or
        the whole inertia tensor there; each entry at most 1e10 kg·m² in magnitude.
    """

    mass: Any
    center_of_mass: Any = (0.0, 0.0, 0.0)
    inertia: Any = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", si_field("machine", "mass", self.mass, "kg", positive=True))
        object.__setattr__(
            self, "center_of_mass", _vector("machine", "center_of_mass", self.center_of_mass, "m")
        )
        J = np.asarray(self.inertia, dtype=object)
        if J.shape == (3,):
            J = np.diag(_vector("machine", "inertia", self.inertia, "kg*m^2"))
        elif J.shape == (3, 3):
            J = np.array([[si_field("machine", "inertia", v, "kg*m^2") for v in row] for row in J])
        else:
            raise ModelError(
                f"shape {J.shape} must be three moments (kg·m²) or a 3×3 tensor",
                element="machine",
                field="inertia",
            )
        if not np.allclose(J, J.T, rtol=1e-12, atol=0.0):
            raise ModelError("the inertia tensor must be symmetric", element="machine", field="inertia")
        smallest = float(np.linalg.eigvalsh(J).min())
        if smallest < -1e-12 * max(abs(J).max(), 1.0):
            raise ModelError(
                f"the inertia tensor must be positive semi-definite (each moment ≥ 0); its smallest "
                f"principal moment is {smallest:g} kg·m²",
                element="machine",
                field="inertia",
            )
        object.__setattr__(self, "inertia", J)

    @property
    def mass_matrix(self) -> np.ndarray:
        """6×6 M about the centre of mass (translations decouple from rotations there)."""
        M = np.zeros((6, 6))
        M[:3, :3] = self.mass * np.eye(3)
        M[3:, 3:] = self.inertia
        return M


@dataclass(frozen=True)
class Mount:
    """A resilient mount: a point spring and viscous damper along three local axes.

    Parameters
    ----------
    name : str
    position : (x, y, z)
        Where it holds the machine, m, machine coordinates, each at most 1e3 m in magnitude.
    stiffness : (3,)
        Along the mount's local axes, N/m (for an elastomer mount: shear, shear, compression), each
        from 0 to 1e15 N/m.
    damping : (3,)
        Along the local axes, N·s/m, each from 0 to 1e13 N·s/m.
    axes : (3, 3), optional
        The local axes as columns, in machine coordinates (orthonormal, right-handed); by default
        the machine axes. :meth:`with_orientation` builds them from angles.
    anchored : bool
        Bolted down: it may carry tension. A free-standing mount may only push.
    """

    name: str
    position: Any
    stiffness: Any
    damping: Any = (0.0, 0.0, 0.0)
    axes: Any = None
    anchored: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", _vector(self.name, "position", self.position, "m"))
        for f, unit in (("stiffness", "N/m"), ("damping", "N*s/m")):
            v = _vector(self.name, f, getattr(self, f), unit)
            if (v < 0).any():
                raise ModelError(
                    f"{v.tolist()} {unit}: every component must be ≥ 0 (a negative value has no "
                    "physical mount; check the sign)",
                    element=self.name,
                    field=f,
                )
            object.__setattr__(self, f, v)
        R = (
            np.eye(3)
            if self.axes is None
            else check_array(self.name, "axes", self.axes, what="direction cosines")
        )
        if R.shape != (3, 3) or not np.allclose(R.T @ R, np.eye(3), atol=1e-9) or np.linalg.det(R) < 0:
            raise ModelError(
                "the local axes must be three orthonormal right-handed columns",
                element=self.name,
                field="axes",
            )
        object.__setattr__(self, "axes", R)

    @classmethod
    def with_orientation(cls, name: str, position: Any, stiffness: Any, angles: Any, **kw: Any) -> Mount:
        """A mount whose local axes are the machine axes turned by angles [about x, about y, about z].

        The axes are turned first about the machine's x axis by ``angles[0]``, then about the machine's
        y axis by ``angles[1]``, then about its z axis by ``angles[2]`` (fixed axes, right-hand rule):
        ``axes`` = R_z R_y R_x, the same as turning about z, then the new y′, then the new x″ by the
        angles in reverse order. A mount tilted by ``[30°, 0, 0]`` has its compression axis (the third
        local axis) at (0, −sin 30°, cos 30°). The model file's ``orientation`` is read the same way.

        Parameters
        ----------
        name : str
            The mount's name.
        position : sequence of float or quantity
            Where it acts on the machine, m.
        stiffness : sequence of float or quantity
            Along its local axes (shear, shear, compression), N/m.
        angles : sequence of float or quantity
            [about x, about y, about z], rad.
        **kw
            Further :class:`Mount` fields (``damping``, ``anchored``).
        """
        from scipy.spatial.transform import Rotation

        a = _vector(name, "orientation", angles, "rad")
        # lower-case axes: rotations about the fixed (extrinsic) axes, in the order given
        return cls(name, position, stiffness, axes=Rotation.from_euler("xyz", a).as_matrix(), **kw)

    @property
    def stiffness_matrix(self) -> np.ndarray:
        """3×3 in machine axes, N/m."""
        return self.axes @ np.diag(self.stiffness) @ self.axes.T

    @property
    def damping_matrix(self) -> np.ndarray:
        """3×3 in machine axes, N·s/m."""
        return self.axes @ np.diag(self.damping) @ self.axes.T


@dataclass(frozen=True)
class MountedMachine:
    """A rigid machine on N mounts, analysed in some or all of its six coordinates.

    Parameters
    ----------
    body : RigidBody
    mounts : sequence of Mount
    dofs : sequence of str
        The coordinates kept, a subset of ``("x", "y", "z", "rx", "ry", "rz")`` in that order:
        :data:`SPATIAL` (all six), :data:`PLANAR` (x, z, ry) or ``("z",)``.
    gravity : float
        m/s², along −z, for the static check of the mounts; from 0 to 1e6 m/s².
    name : str

    Raises
    ------
    ModelError
        When a mount's stiffness is negative, when the mounts leave a kept motion unrestrained
        (naming it), or when a free-standing mount would be pulled under the machine's weight.
    """

    body: RigidBody
    mounts: tuple[Mount, ...]
    dofs: tuple[str, ...] = SPATIAL
    gravity: float = STANDARD_GRAVITY
    name: str = "machine"

    def to_frame(self) -> Any:
        """The mounts as assembled, one row per mount: position (m), stiffness (N/m) and damping
        (N·s/m) along its axes, anchored, and where the values came from
        (:func:`model_frame`)."""
        return model_frame(self)

    def __post_init__(self) -> None:
        object.__setattr__(self, "mounts", tuple(self.mounts))
        object.__setattr__(self, "dofs", tuple(self.dofs))
        object.__setattr__(
            self, "gravity", si_field(self.name, "gravity", self.gravity, "m/s^2", nonnegative=True)
        )
        if not self.mounts:
            raise ModelError("a machine needs at least one mount", element=self.name, field="mounts")
        names = [m.name for m in self.mounts]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise ModelError(f"mount names {dup} appear more than once", element=self.name, field="mounts")
        bad = [d for d in self.dofs if d not in DOFS]
        if (
            bad
            or list(self.dofs) != sorted(self.dofs, key=DOFS.index)
            or len(set(self.dofs)) != len(self.dofs)
        ):
            raise ModelError(
                f"{list(self.dofs)} must be distinct coordinates of {list(DOFS)} in that order",
                element=self.name,
                field="dofs",
            )
        rot = {"rx": 0, "ry": 1, "rz": 2}
        for d in self.dofs:
            if d in rot and self.body.inertia[rot[d], rot[d]] <= 0:
                raise ModelError(
                    f"the moment of inertia about {d[1]} is zero but the model keeps the rotation {d}; "
                    "give the machine's inertia",
                    element="machine",
                    field="inertia",
                )
        self._check_stable()
        self._check_static()

    @classmethod
    def single_dof(
        cls, mass: Any, stiffness: Any, damping_ratio: float, name: str = "machine"
    ) -> MountedMachine:
        """The published one-degree-of-freedom model: mass m on a support of stiffness k, damping ratio ζ.

        c = 2 ζ √(k m) (e.g. Rao, *Mechanical Vibrations*, §2.6).

        Parameters
        ----------
        mass : float or quantity
            m, kg, from 1e-9 to 1e8 kg.
        stiffness : float or quantity
            k, N/m, from 1e-6 to 1e15 N/m.
        damping_ratio : float
            ζ, dimensionless, from 0 to 10 (:data:`MAX_DAMPING_RATIO`; 1 is critical damping).
        name : str
            The machine's name.
        """
        body = RigidBody(mass)
        k = si_field("support", "stiffness", stiffness, "N/m", positive=True)
        zeta = si_field(
            "support",
            "damping_ratio",
            damping_ratio,
            "",
            low=0.0,
            high=MAX_DAMPING_RATIO,
            what="damping ratio",
        )
        c = 2.0 * zeta * math.sqrt(k * body.mass)
        mount = Mount("support", (0.0, 0.0, 0.0), (0.0, 0.0, k), (0.0, 0.0, c))
        return cls(body, (mount,), ("z",), name=name)

    # -- assembly ----------------------------------------------------------------------------
    @cached_property
    def _select(self) -> np.ndarray:
        """6×n: the kept coordinates as columns of the identity."""
        return np.eye(6)[:, [DOFS.index(d) for d in self.dofs]]

    def mount_transform(self, mount: Mount) -> np.ndarray:
        """3×n T with u = T q: the body's displacement at the mount from the kept coordinates.

        Parameters
        ----------
        mount : Mount
            One of the machine's mounts.
        """
        r = mount.position - self.body.center_of_mass
        return np.hstack([np.eye(3), -_skew(r)]) @ self._select

    @cached_property
    def mass_matrix(self) -> np.ndarray:
        """n×n M over the kept coordinates (kg, kg·m²)."""
        S = self._select
        return S.T @ self.body.mass_matrix @ S

    def _assemble(self, which: str) -> np.ndarray:
        n = len(self.dofs)
        out = np.zeros((n, n))
        for m in self.mounts:
            T = self.mount_transform(m)
            out += T.T @ getattr(m, which) @ T
        return 0.5 * (out + out.T)

    @cached_property
    def stiffness_matrix(self) -> np.ndarray:
        """n×n K over the kept coordinates (N/m, N·m/rad, N/rad)."""
        return self._assemble("stiffness_matrix")

    @cached_property
    def damping_matrix(self) -> np.ndarray:
        """n×n C over the kept coordinates."""
        return self._assemble("damping_matrix")

    def load_matrix(self) -> np.ndarray:
        """n×6 B: generalised forces from a load (F, M about the machine origin), Q = B [F; M_O].

        About the centre of mass G the moment is M_G = M_O − r_G × F.
        """
        B = np.eye(6)
        B[3:, :3] = -_skew(self.body.center_of_mass)
        return self._select.T @ B

    # -- checks ------------------------------------------------------------------------------
    def _check_stable(self) -> None:
        K = self.stiffness_matrix
        scale = np.abs(np.diag(K)).max(initial=0.0)
        w, v = np.linalg.eigh(K)
        free = w <= 1e-10 * max(scale, 1e-300)
        if free.any():
            shape = v[:, int(np.argmin(w))]
            d = self.dofs[int(np.argmax(np.abs(shape)))]
            raise ModelError(
                f"the mounts do not resist {_MOTION[d]} ({d}); the layout is unstable — add stiffness "
                "along that direction or spread the mounts out (they must not all stand on one line)",
                element=self.name,
                field="mounts",
            )

    @cached_property
    def static_mount_forces(self) -> np.ndarray:
        """(N, 3) force on each mount under the machine's weight, N, machine axes (−z pushes down)."""
        weight = np.array([0.0, 0.0, -self.body.mass * self.gravity])
        Q = self.load_matrix() @ np.concatenate([weight, np.cross(self.body.center_of_mass, weight)])
        q = np.linalg.solve(self.stiffness_matrix, Q)
        return np.array([m.stiffness_matrix @ (self.mount_transform(m) @ q) for m in self.mounts])

    def _check_static(self) -> None:
        f = self.static_mount_forces
        for m, fm in zip(self.mounts, f, strict=True):
            if not m.anchored and fm[2] > 1e-9 * self.body.mass * self.gravity:
                raise ModelError(
                    f"under the machine's weight this mount would be pulled up with {fm[2]:.4g} N: the "
                    "centre of mass lies outside what the mounts can carry. Move the mounts under the "
                    "centre of mass, or set anchored = true for a bolted mount",
                    element=m.name,
                    field="position",
                )

    @property
    def static_deflection(self) -> np.ndarray:
        """(N,) downward deflection of each mount under the machine's weight, m (along z)."""
        return np.array(
            [
                -fm[2] / m.stiffness_matrix[2, 2] if m.stiffness_matrix[2, 2] > 0 else 0.0
                for m, fm in zip(self.mounts, self.static_mount_forces, strict=True)
            ]
        )

    # -- variants ----------------------------------------------------------------------------
    def scaled(self, stiffness: float = 1.0, damping: float = 1.0) -> MountedMachine:
        """The same machine with every mount's stiffness and damping multiplied by the factors.

        Parameters
        ----------
        stiffness, damping : float
            The factors, dimensionless: the stiffness factor positive, the damping factor not negative
            (the scaled mounts must stay within their own bounds).
        """
        stiffness = check_number(self.name, "stiffness", stiffness, positive=True, what="stiffness factor")
        damping = check_number(self.name, "damping", damping, nonnegative=True, what="damping factor")
        mounts = tuple(
            replace(m, stiffness=m.stiffness * stiffness, damping=m.damping * damping) for m in self.mounts
        )
        return replace(self, mounts=mounts)


# -- the machine as assembled, one row per mount -------------------------------------------------------


def _source(name: str, drawn: Mapping[str, Any]) -> str:
    """Where a mount's stiffness came from, in words."""
    d = drawn.get(name)
    if d is None:
        return "given"
    kind = re.sub(r"(?<!^)(?=[A-Z])", " ", str(d["estimate"])).lower()  # ElastomerPad: elastomer pad
    said = f"{kind} estimate from {d['source']}"
    calibration = d.get("calibration", "as drawn")
    if isinstance(calibration, Mapping):
        said += f", calibrated ({calibration.get('provenance', 'stored')})"
    return said


def model_frame(machine: MountedMachine, drawn: Mapping[str, Any] | None = None) -> pd.DataFrame:
    """The mounts as assembled, one row per mount, SI: position (m), stiffness (N/m) and damping
    (N·s/m) along the mount's axes, anchored, and where the values came from.

    Parameters
    ----------
    machine : MountedMachine
        The machine as analysed.
    drawn : mapping, optional
        The mounts estimated from their drawings, as for :func:`mechdyn.support.summary.model_tables`.
    """
    import pandas as pd

    rows = []
    for m in machine.mounts:
        row: dict[str, Any] = {"mount": m.name}
        row |= {f"{c}_m": float(v) for c, v in zip("xyz", m.position, strict=True)}
        row |= {f"stiffness_{a}_N_per_m": float(k) for a, k in zip("123", m.stiffness, strict=True)}
        row |= {f"damping_{a}_N_s_per_m": float(c) for a, c in zip("123", m.damping, strict=True)}
        row |= {"anchored": bool(m.anchored), "from": _source(m.name, drawn or {})}
        rows.append(row)
    return pd.DataFrame(rows)
