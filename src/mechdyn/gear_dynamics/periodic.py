"""The linear periodic model of a geared drivetrain at constant speed: what the steady-state solvers share.

At a constant speed the mesh stiffnesses k_j(τ_j) vary periodically with the mesh phases
τ_j = z_j θ_a / (2π), θ_a following the nominal rigid rotation. Linearised (teeth in contact), the
vibration x about that rotation obeys the linear time-periodic system

    M ẍ + C ẋ + K(t) x = F(t),  K(t) = K_s + Σ_j k_j(τ_j(t)) g_j g_jᵀ,

:class:`LinearPeriodic` (built by :func:`linear_periodic` from a
:class:`~mechdyn.gear_dynamics.system.GearSystem`), excited by the mean load and, through each mesh,
by its static transmission error. Its period is :class:`PeriodPlan` (:func:`period_plan`): the common
period of the mesh frequencies, each an integer order of the fundamental, or the dominant mesh's
period where they have no common one of modest length.

The rigid-body rotation of a free drivetrain is a Floquet multiplier 1 (double) that says nothing
about stability; it is removed, either by holding the reference disk at its prescribed speed (the
``"prescribed"`` boundary: its coordinate leaves the state) or by projecting the motion on the
M-orthogonal complement of the rigid-body vectors (``"free"``, ``"motor"``: the rigid-body coordinate
decouples since K(t) and the mesh damping do not resist a rigid rotation; where something damps the
rigid rotation it stays in the state as :attr:`LinearPeriodic.idle`).

Every periodic method builds on this module: the propagators and the monodromy matrix
(:mod:`.propagators`), the Floquet multipliers (:mod:`.floquet`), harmonic balance
(:mod:`.harmonic_balance`), shooting (:mod:`.shooting`, with backlash the event-located flow of
:mod:`._nonsmooth`), the steady state at one speed (:mod:`.steady`) and the speed sweep (:mod:`.sweep`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from fractions import Fraction
from typing import Any, Literal

import numpy as np

from mechdyn.checks import check_array, check_number
from mechdyn.errors import ModelError

__all__ = [
    "LinearPeriodic",
    "PeriodPlan",
    "interpolate",
    "interpolated_slope",
    "linear_periodic",
    "period_plan",
]

Boundary = Literal["prescribed", "free", "motor"]

#: The largest order of a mesh frequency over the common fundamental accepted before the common
#: period is given up for the dominant mesh's period (a 1:89 tooth ratio would need 89 mesh periods).
MAX_COMMON_ORDER = 64
_RATIONAL = 1e-9  # relative: a mesh frequency ratio this close to a fraction is that fraction


@dataclass(frozen=True)
class LinearPeriodic:
    """A drivetrain's linear time-periodic equations of motion about its nominal rotation.

    Attributes
    ----------
    basis : ndarray
        (n, m) the state coordinates x in the system's coordinates q: q = Ω t r + basis @ x, rad.
    M, K, C : ndarray
        (m, m) mass (kg·m²), structural stiffness without the meshes (N·m/rad), damping with the
        meshes' (N·m·s/rad).
    G : ndarray
        (J, m) mesh deflections along the line of action δ_j = G_j @ x, m per rad.
    mean_stiffness, mesh_damping : ndarray
        (J,) k̄_j in N/m and c_j in N·s/m.
    profiles, errors : tuple of ndarray
        k_j/k̄_j and the static transmission error e_j (m), sampled at τ = i/P, linear in between.
    backlash : tuple of float or None
        Total backlash per mesh, m.
    cycles : ndarray
        (J,) mesh cycles per radian of the reference disk, signed: τ_j = cycles_j Ω t.
    rigid : ndarray
        (n,) the nominal rigid rotation per radian of the reference disk, rad/rad.
    load : ndarray
        (m,) constant generalised force of the load torques (N·m), to which −Ω C_full r is added.
    drag : ndarray
        (m,) generalised force per unit speed of the grounded dampers, −basisᵀ C r, N·m·s/rad.
    names : tuple of str
        The meshes' names.
    reference : str
        The disk whose speed is Ω.
    boundary : str
        ``"prescribed"``, ``"free"`` or ``"motor"``.
    idle : int or None
        The coordinate of x that is the rigid-body angle where it is kept in the state (a free train
        whose rigid rotation is damped: by a motor's torque–speed slope or a grounded damper); no
        force depends on it (K, G and the forces have no entry there), so its Floquet multiplier is
        exactly 1 and is set aside (:meth:`deflate`), and its mean is fixed at 0. None otherwise.
    motor : MotorSlope or None
        The motor whose torque–speed slope damps the rigid rotation (``"motor"``), added to
        :attr:`C` at each speed by :meth:`at_speed`.
    drive : str
        The drive in words (for results).
    """

    basis: np.ndarray
    M: np.ndarray
    K: np.ndarray
    C: np.ndarray
    G: np.ndarray
    mean_stiffness: np.ndarray
    mesh_damping: np.ndarray
    profiles: tuple[np.ndarray, ...]
    errors: tuple[np.ndarray, ...]
    backlash: tuple[float | None, ...]
    cycles: np.ndarray
    rigid: np.ndarray
    load: np.ndarray
    drag: np.ndarray
    names: tuple[str, ...]
    reference: str
    boundary: str
    idle: int | None = None
    motor: Any = None
    drive: str = ""

    @property
    def m(self) -> int:
        """Number of state coordinates (half the state dimension)."""
        return self.M.shape[0]

    def force(self, speed: float) -> np.ndarray:
        """The constant generalised force at reference speed ``speed`` (rad/s), N·m.

        Parameters
        ----------
        speed : float
            Reference speed Ω, rad/s.
        """
        return self.load + speed * self.drag

    def at_speed(self, speed: float) -> LinearPeriodic:
        """The model at reference speed ``speed`` (rad/s): with a motor, its torque–speed slope at the
        torque that holds that speed added to :attr:`C` as a damper on the motor's disk (N·m·s/rad);
        the model itself otherwise.

        Parameters
        ----------
        speed : float
            Reference speed Ω, rad/s.
        """
        if self.motor is None:
            return self
        c = self.motor.damping(speed)
        return replace(self, C=self.C + c * np.outer(self.motor.row, self.motor.row), motor=None)

    @property
    def held_stiffness(self) -> np.ndarray:
        """(m, m) the stiffness with every mesh at its mean, N·m/rad."""
        return self.K + (self.G.T * self.mean_stiffness) @ self.G

    def static(self, force: np.ndarray) -> np.ndarray:
        """(m,) the deflection under a constant generalised force ``force`` (N·m) at mean mesh
        stiffness, rad; the rigid-body angle (:attr:`idle`) at 0.

        Parameters
        ----------
        force : ndarray
            (m,) generalised force, N·m.
        """
        K = self.held_stiffness
        if self.idle is None:
            return np.linalg.solve(K, force)
        keep = np.delete(np.arange(self.m), self.idle)
        x = np.zeros(self.m)
        x[keep] = np.linalg.solve(K[np.ix_(keep, keep)], np.asarray(force)[keep])
        return x

    def deflate(self, Phi: np.ndarray) -> np.ndarray:
        """A state-transition matrix over (x, ẋ) without the rigid-body angle's row and column (its
        multiplier is exactly 1: nothing depends on it); ``Phi`` itself where there is none.

        Parameters
        ----------
        Phi : ndarray
            (2m, 2m) state-transition matrix, dimensionless.
        """
        if self.idle is None:
            return Phi
        keep = np.delete(np.arange(Phi.shape[0]), self.idle)
        return Phi[np.ix_(keep, keep)]

    def with_profiles(self, profiles: tuple[np.ndarray, ...]) -> LinearPeriodic:
        """The same model with other stiffness profiles (k/k̄ samples per mesh).

        Parameters
        ----------
        profiles : tuple of ndarray
            One array of k/k̄ samples per mesh, dimensionless.
        """
        return replace(self, profiles=tuple(np.asarray(p, float) for p in profiles))


def interpolate(samples: np.ndarray, tau: Any) -> np.ndarray:
    """Periodic linear interpolation of samples taken at τ = i/P, i = 0 … P−1.

    Parameters
    ----------
    samples : ndarray
        (P,) values over one period, in their own unit.
    tau : array_like
        Phases, cycles (any real number; the period is 1).
    """
    P = samples.size
    u = np.mod(np.asarray(tau, float), 1.0) * P
    i = np.minimum(np.floor(u).astype(int), P - 1)
    f = u - i
    return samples[i] * (1.0 - f) + samples[(i + 1) % P] * f


def interpolated_slope(samples: np.ndarray, tau: Any) -> np.ndarray:
    """d/dτ of :func:`interpolate` (constant on each sample interval), unit of the samples per cycle.

    Parameters
    ----------
    samples : ndarray
        (P,) values over one period, in their own unit.
    tau : array_like
        Phases, cycles.
    """
    P = samples.size
    u = np.mod(np.asarray(tau, float), 1.0) * P
    i = np.minimum(np.floor(u).astype(int), P - 1)
    return (samples[(i + 1) % P] - samples[i]) * P


def _cleaned(v: np.ndarray, scale: float) -> np.ndarray:
    """``v`` with the rounding noise of a product that vanishes exactly (C r of a free train) set to 0."""
    return np.where(np.abs(v) > 1e-12 * scale, v, 0.0)


def _reference_column(system: Any, reference: str) -> tuple[int, float]:
    dt = system.drivetrain
    if reference not in dt.disk_index:
        raise ModelError(
            f"reference disk {reference!r} is not defined; give one of {', '.join(dt.disk_names)}",
            element="gear dynamics",
            field="reference",
        )
    row = np.asarray(system.T)[dt.disk_index[reference]]
    j = int(np.flatnonzero(row)[0])
    return j, float(row[j])


def linear_periodic(
    system: Any,
    *,
    reference: str,
    boundary: Boundary = "prescribed",
    load: Any = None,
    drive_disk: str | None = None,
    motor: Any = None,
) -> LinearPeriodic:
    """The linear time-periodic model of a :class:`~mechdyn.gear_dynamics.system.GearSystem`.

    Parameters
    ----------
    system : GearSystem
        The time-varying system of a drivetrain.
    reference : str
        The disk whose speed is the reference speed Ω.
    boundary : {"prescribed", "free", "motor"}
        ``"prescribed"``: the reference disk turns at exactly Ω (a kinematic input; the motor torque
        follows whatever the vibration asks); ``"free"``: no disk is held, a constant torque at
        ``drive_disk`` balances the load and the drag, and the rigid-body motion is projected out
        (M-orthogonal complement of the rigid-body vector; where a grounded damper acts on the rigid
        rotation it stays in the state as :attr:`LinearPeriodic.idle`); ``"motor"``: no disk is held
        and ``motor`` drives, its torque following its torque–speed curve about the torque that holds
        the speed (the slope damps the rigid rotation, kept in the state).
    load : mapping of str to float, optional
        Torque drawn at each named disk, N·m (or quantities), resisting that disk's rotation.
    drive_disk : str, optional
        With ``"free"``: the disk that takes the balancing torque (default: ``reference``).
    motor : MotorTorque, optional
        With ``"motor"``: the motor (:class:`mechdyn.gear_dynamics.loads.MotorTorque`, its disk, curve,
        ratio and sense).

    Returns
    -------
    LinearPeriodic
    """
    from mechdyn.gear_dynamics._operating import MotorSlope, balancing
    from mechdyn.units import si_field

    if boundary not in ("prescribed", "free", "motor"):
        raise ModelError(
            f"boundary {boundary!r}: give 'prescribed' (reference disk held at its speed), 'free' or 'motor'",
            element="gear dynamics",
            field="boundary",
        )
    if boundary == "motor" and motor is None:
        raise ModelError(
            "boundary 'motor' needs the motor (a MotorTorque); give motor=... or boundary='free'",
            element="gear dynamics",
            field="motor",
        )
    j_ref, t_ref = _reference_column(system, reference)
    M = np.asarray(system.M, float)
    K = np.asarray(system.K, float)
    C = np.asarray(system.C, float)
    meshes = tuple(system.meshes)
    n = M.shape[0]
    R = np.asarray(system.rigid_body, float).reshape(n, -1)
    turning = [c for c in R.T if abs(c[j_ref]) > 1e-12 * max(np.abs(c).max(), 1e-300)]
    if len(turning) != 1 or R.shape[1] != 1:
        why = (
            "it is held by a grounded spring, so it cannot turn at a steady speed"
            if not turning
            else f"it has {R.shape[1]} free branches; model only the branch that the reference drives"
        )
        raise ModelError(
            f"the drivetrain cannot run at a steady speed of disk {reference!r}: {why}",
            element="gear dynamics",
            field="reference",
        )
    r = turning[0] / (turning[0][j_ref] * t_ref)  # reference disk angle 1
    G = np.array([np.asarray(mesh.g, float) for mesh in meshes]).reshape(len(meshes), n)
    kbar = np.array([float(mesh.mean_stiffness) for mesh in meshes])
    cm = np.array([float(mesh.damping) for mesh in meshes])
    C_full = C + (G.T * cm) @ G
    torques = np.zeros(n)
    dt = system.drivetrain
    T = np.asarray(system.T, float)
    for disk, value in dict(load or {}).items():
        if disk not in dt.disk_index:
            raise ModelError(
                f"load at disk {disk!r}, which is not defined; give one of {', '.join(dt.disk_names)}",
                element="gear dynamics",
                field="load",
            )
        torque = si_field("gear dynamics", f"load[{disk!r}]", value, "N*m", what="load torque")
        turning_sense = float(np.sign(T[dt.disk_index[disk]] @ r))
        torques -= torque * (turning_sense or 1.0) * T[dt.disk_index[disk]]
    drag = _cleaned(-(C_full @ r), np.abs(C_full).max() * np.abs(r).max())
    idle: int | None = None
    slope = None
    drive = f"disk {reference!r} held at each speed (a kinematic input)"
    if boundary == "prescribed":
        basis = np.delete(np.eye(n), j_ref, axis=1)
    else:
        # M-orthogonal complement of the rigid-body vector: the rigid coordinate decouples where
        # nothing damps the rigid rotation (C r = 0); else it stays, last, as the idle coordinate
        Mr = M @ r
        q, _ = np.linalg.qr(np.column_stack([Mr, np.eye(n)]))
        basis = q[:, 1:n]
        disk = motor.disk if boundary == "motor" else (drive_disk or reference)
        row, need, torques, drag = balancing(system, r, disk, torques, drag)
        if boundary == "motor" or np.any(_cleaned(C_full @ r, np.abs(C_full).max() * np.abs(r).max())):
            basis = np.column_stack([basis, r])
            idle = n - 1
        if boundary == "motor":
            slope = MotorSlope(motor, basis.T @ row, need, float(row @ r))
            drive = slope.describe()
        else:
            drive = (
                f"no disk held: a constant torque at disk {disk!r} balances the load (a stiff speed "
                "control or a large inertia upstream)"
            )
    Mb, Kb, Cb, Gb = basis.T @ M @ basis, basis.T @ K @ basis, basis.T @ C_full @ basis, G @ basis
    load_b, drag_b = basis.T @ torques, _cleaned(basis.T @ drag, np.abs(C_full).max() * np.abs(r).max())
    if idle is not None:  # what vanishes exactly (K r = 0, G r = 0, rᵀ M B = 0, balanced forces)
        Mb[idle, :idle] = Mb[:idle, idle] = 0.0
        Kb[idle, :] = Kb[:, idle] = 0.0
        Gb[:, idle] = 0.0
        load_b[idle] = drag_b[idle] = 0.0
        Cb = np.where(np.abs(Cb) > 1e-12 * max(np.abs(Cb).max(), 1e-300), Cb, 0.0)
    cycles = np.array([mesh.teeth * float(np.asarray(mesh.phase_row, float) @ r) for mesh in meshes])
    cycles = cycles / (2 * np.pi)
    return LinearPeriodic(
        basis=basis,
        M=Mb,
        K=Kb,
        C=Cb,
        G=Gb,
        mean_stiffness=kbar,
        mesh_damping=cm,
        profiles=tuple(np.asarray(mesh.profile, float) for mesh in meshes),
        errors=tuple(np.asarray(mesh.error, float) for mesh in meshes),
        backlash=tuple(mesh.backlash for mesh in meshes),
        cycles=cycles,
        rigid=r,
        load=load_b,
        drag=drag_b,
        names=tuple(mesh.name for mesh in meshes),
        reference=reference,
        boundary=boundary,
        idle=idle,
        motor=slope,
        drive=drive,
    )


@dataclass(frozen=True)
class PeriodPlan:
    """The common period of the meshes and the order of each mesh frequency in it.

    Attributes
    ----------
    fundamental : float
        Cycles of the fundamental per radian of the reference disk (ω₀ = 2π · fundamental · Ω).
    orders : ndarray
        (J,) integer m_j: mesh j's frequency is m_j ω₀ (0 for a mesh held at its mean stiffness).
    signs : ndarray
        (J,) +1 or −1: the sense in which the mesh phase advances.
    note : str
        How the period was chosen when the meshes have no common period of modest length.
    """

    fundamental: float
    orders: np.ndarray
    signs: np.ndarray
    note: str = ""

    def period(self, speed: float) -> float:
        """The period at reference speed ``speed`` (rad/s), s.

        Parameters
        ----------
        speed : float
            Reference speed Ω, rad/s.
        """
        return 1.0 / (self.fundamental * speed)


def period_plan(lin: LinearPeriodic, dominant: str | None = None) -> PeriodPlan:
    """The common period of the mesh frequencies, or the dominant mesh's period.

    Mesh frequencies are rational multiples of the reference speed when they follow tooth ratios; the
    fundamental is their greatest common divisor and each mesh frequency is an integer multiple m_j of
    it. Where some m_j would exceed :data:`MAX_COMMON_ORDER` (or the ratio is not rational to 1e-9),
    the period of the dominant mesh (the largest k̄ times stiffness fluctuation, or ``dominant``) is
    used, the meshes with other periods are held at their mean stiffness, and :attr:`PeriodPlan.note`
    says so.

    Parameters
    ----------
    lin : LinearPeriodic
    dominant : str, optional
        The mesh whose period to use when there is no common one.
    """
    nu = np.abs(lin.cycles)
    signs = np.where(lin.cycles < 0, -1, 1)
    varying = np.array(
        [
            np.ptp(p) > 0 or np.ptp(e) > 0 or b is not None
            for p, e, b in zip(lin.profiles, lin.errors, lin.backlash, strict=True)
        ],
        dtype=bool,
    )
    varying &= nu > 0
    if not varying.any():  # constant stiffness, no error: any period does; the first mesh's
        turning = np.flatnonzero(nu > 0)
        if turning.size == 0:  # no teeth given: one cycle per revolution of the reference
            return PeriodPlan(1.0 / (2 * np.pi), np.zeros(nu.size, int), signs)
        varying[turning[0]] = True
    base = float(nu[varying].min())
    fractions = [Fraction(float(v / base)).limit_denominator(MAX_COMMON_ORDER) for v in nu]
    exact = all(abs(float(f) - v / base) <= _RATIONAL * v / base for f, v in zip(fractions, nu, strict=True))
    if exact:
        denominator = math.lcm(*(fractions[i].denominator for i in np.flatnonzero(varying)))
        numerators = [int(fractions[i] * denominator) for i in np.flatnonzero(varying)]
        common = math.gcd(*numerators)
        orders = np.zeros(nu.size, int)
        for i in np.flatnonzero(varying):
            orders[i] = int(fractions[i] * denominator) // common
        if orders.max() <= MAX_COMMON_ORDER:
            return PeriodPlan(base * common / denominator, orders, signs)
    if dominant is not None and dominant not in lin.names:
        raise ModelError(
            f"dominant mesh {dominant!r} is not a flexible mesh; give one of {', '.join(lin.names)}",
            element="gear dynamics",
            field="dominant",
        )
    weight = [lin.mean_stiffness[i] * np.ptp(lin.profiles[i]) for i in range(nu.size)]
    i_dom = lin.names.index(dominant) if dominant is not None else int(np.argmax(weight))
    ratio = nu / nu[i_dom]
    keep = [i for i in range(nu.size) if abs(ratio[i] - np.round(ratio[i])) < _RATIONAL]
    orders = np.where(np.isin(np.arange(nu.size), keep), np.round(ratio), 0).astype(int)
    held = [lin.names[i] for i in range(nu.size) if i not in keep and varying[i]]
    note = (
        f"the mesh frequencies have no common period within {MAX_COMMON_ORDER} mesh periods; the period "
        f"of mesh {lin.names[i_dom]!r} is used and {', '.join(map(repr, held))} "
        "held at mean stiffness (no error)"
    )
    return PeriodPlan(float(nu[i_dom]), orders, signs, note)


def _highest_frequency(lin: LinearPeriodic) -> float:
    """Highest natural frequency of the system at its stiffest mesh phase bound, rad/s."""
    k_top = np.array([k * p.max() for k, p in zip(lin.mean_stiffness, lin.profiles, strict=True)])
    K = lin.K + (lin.G.T * k_top) @ lin.G
    w2 = np.linalg.eigvals(np.linalg.solve(lin.M, K)).real
    return float(np.sqrt(max(w2.max(), 0.0))) if w2.size else 0.0


def _natural_frequencies(lin: LinearPeriodic) -> np.ndarray:
    from scipy.linalg import eigh

    keep = np.delete(np.arange(lin.m), [] if lin.idle is None else [lin.idle])
    w2 = eigh(lin.held_stiffness[np.ix_(keep, keep)], lin.M[np.ix_(keep, keep)], eigvals_only=True)
    return np.sqrt(np.clip(w2, 0.0, None)) / (2 * np.pi)


def _speeds(speeds: Any) -> np.ndarray:
    s = np.atleast_1d(check_array("gear dynamics", "speeds", speeds, "rad/s", positive=True, what="speeds"))
    if s.ndim != 1 or s.size == 0:
        raise ModelError(
            "give the speeds as a 1-D list of positive values in rad/s",
            element="gear dynamics",
            field="speeds",
        )
    return s


def _check_speed(field: str, speed: Any) -> float:
    return check_number("gear dynamics", field, speed, "rad/s", positive=True, what="speed")
