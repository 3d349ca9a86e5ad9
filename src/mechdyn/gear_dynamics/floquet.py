"""Floquet stability of a geared drivetrain with time-varying mesh stiffness.

At a constant speed the mesh stiffnesses k_j(τ_j) vary periodically with the mesh phases
τ_j = z_j θ_a / (2π), θ_a following the nominal rigid rotation. Linearised (teeth in contact, no
backlash), the vibration about that rotation obeys the linear time-periodic system

    M ẍ + C ẋ + K(t) x = F(t),  K(t) = K_s + Σ_j k_j(τ_j(t)) g_j g_jᵀ,

whose stability follows from the monodromy matrix Φ(T), the state-transition matrix over one period
T (Floquet's theorem; Nayfeh & Mook, *Nonlinear Oscillations*, 1979, §5.2): the free vibration grows
where the spectral radius ρ, the largest modulus of its eigenvalues μ (the Floquet multipliers),
exceeds 1, at the rate ln ρ / T.

The rigid-body rotation of a free drivetrain is a multiplier 1 (double) that says nothing about
stability; it is removed, either by holding the reference disk at its prescribed speed (the
``"prescribed"`` boundary: its coordinate leaves the state) or by projecting the motion on the
M-orthogonal complement of the rigid-body vectors (``"free"``: the rigid-body coordinate decouples
since K(t) and the mesh damping do not resist a rigid rotation).

Two ways to Φ(T): ``"magnus"``, a product of matrix exponentials over uniform segments with the
fourth-order Magnus step (Blanes, Casas, Oteo & Ros, *Physics Reports* 470, 2009, eq. 253), exact when
the stiffness is constant on each segment; and ``"ivp"``, the state-transition matrix integrated by
:func:`scipy.integrate.solve_ivp` (DOP853) at tight tolerance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from mechdyn.checks import check_array, check_count, check_number
from mechdyn.errors import ModelError
from mechdyn.results import Result, Table

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["FloquetResult", "StabilityChart", "floquet", "monodromy", "stability_chart"]

Boundary = Literal["prescribed", "free", "motor"]
Integrator = Literal["magnus", "ivp"]

#: The largest order of a mesh frequency over the common fundamental accepted before the common
#: period is given up for the dominant mesh's period (a 1:89 tooth ratio would need 89 mesh periods).
MAX_COMMON_ORDER = 64
#: Multipliers above 1 + this are unstable (1e-9 allows for the rounding of an undamped system's
#: multipliers, which lie on the unit circle where stable).
UNSTABLE_MARGIN = 1e-9
_RATIONAL = 1e-9  # relative: a mesh frequency ratio this close to a fraction is that fraction
_ATOL_PER_RTOL = 1e-3  # solve_ivp's absolute tolerance per relative one (the states are of order 1)
#: The most Magnus segments per period the accuracy rule of :func:`segments` adds up to.
MAX_SEGMENTS = 1 << 16


# -- the linear periodic model on the reduced coordinates -------------------------------------------
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


def interpolant_harmonics(samples: np.ndarray, orders: np.ndarray) -> np.ndarray:
    """Exact Fourier coefficients of the periodic linear interpolant of samples.

    The interpolant is the samples convolved with the hat function of width 2/P, so its coefficient of
    order h is the discrete Fourier coefficient S_(h mod P) times sinc²(h/P) (e.g. Bracewell, *The
    Fourier Transform and Its Applications*, 3rd ed., 2000, ch. 10); f(τ) = Σ_h c_h exp(2πi h τ).

    Parameters
    ----------
    samples : ndarray
        (P,) values at τ = i/P, in their own unit.
    orders : ndarray
        Integer orders h (negative ones included), dimensionless.
    """
    P = samples.size
    S = np.fft.fft(samples) / P
    h = np.asarray(orders, int)
    return S[np.mod(h, P)] * np.sinc(h / P) ** 2


def _moments(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """I_k(θ) = ∫₀¹ u^k exp(−iθu) du for k = 0, 1, 2 (series near θ = 0, recursion elsewhere)."""
    th = np.asarray(theta, float)
    small = np.abs(th) < 0.5
    out = []
    z = -1j * th
    e = np.exp(z)
    with np.errstate(divide="ignore", invalid="ignore"):
        I0 = np.where(small, 0.0, (e - 1.0) / np.where(small, 1.0, z))
        I1 = np.where(small, 0.0, (e - I0) / np.where(small, 1.0, z))
        I2 = np.where(small, 0.0, (e - 2.0 * I1) / np.where(small, 1.0, z))
    for k, moment in enumerate((I0, I1, I2)):
        series = np.zeros(th.shape, complex)
        term = np.ones(th.shape, complex)
        for n in range(24):  # Σ (−iθ)^n / (n! (n + k + 1)), |θ| < 0.5: 24 terms reach 1e-30
            series = series + term / (n + k + 1)
            term = term * z / (n + 1)
        out.append(np.where(small, series, moment))
    return out[0], out[1], out[2]


def product_harmonics(a: np.ndarray, b: np.ndarray, orders: np.ndarray) -> np.ndarray:
    """Exact Fourier coefficients of the product of the periodic linear interpolants of two sample
    sets taken at the same phases τ = i/P.

    On each interval the product is a quadratic a_i + b_i u + c_i u² in u = Pτ − i, so its coefficient
    of order h is Σ_k DFT(coefficient k)_h · I_k(2πh/P) with I_k(θ) = ∫₀¹ u^k exp(−iθu) du (direct
    integration; with b ≡ 1 it reduces to :func:`interpolant_harmonics`).

    Parameters
    ----------
    a, b : ndarray
        (P,) samples of the two factors, in their own units (the product carries both).
    orders : ndarray
        Integer orders h, dimensionless.
    """
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    P = a.size
    da, db = np.roll(a, -1) - a, np.roll(b, -1) - b
    c0, c1, c2 = a * b, a * db + b * da, da * db
    h = np.asarray(orders, int)
    I0, I1, I2 = _moments(2 * np.pi * h / P)
    idx = np.mod(h, P)
    out: np.ndarray = (
        np.fft.fft(c0)[idx] / P * I0 + np.fft.fft(c1)[idx] / P * I1 + np.fft.fft(c2)[idx] / P * I2
    )
    return out


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


def _phases(lin: LinearPeriodic, plan: PeriodPlan, t_over_T: np.ndarray) -> np.ndarray:
    """(J, N) mesh phases τ_j at fractions of the period (meshes held at mean: phase 0)."""
    return (plan.signs * plan.orders)[:, None] * np.asarray(t_over_T, float)[None, :]


def _stiffness_matrices(lin: LinearPeriodic, plan: PeriodPlan, t_over_T: np.ndarray) -> np.ndarray:
    """(N, m, m) K(t) at fractions of the period."""
    tau = _phases(lin, plan, t_over_T)
    K = np.broadcast_to(lin.K, (tau.shape[1], lin.m, lin.m)).copy()
    for j in range(len(lin.names)):
        k = lin.mean_stiffness[j] * (interpolate(lin.profiles[j], tau[j]) if plan.orders[j] else 1.0)
        K += np.multiply.outer(np.broadcast_to(k, tau.shape[1]), np.outer(lin.G[j], lin.G[j]))
    return K


def _excitation(lin: LinearPeriodic, plan: PeriodPlan, speed: float, t_over_T: np.ndarray) -> np.ndarray:
    """(N, m) F(t): constant load plus Σ_j g_j (k_j e_j + c_j ė_j) at fractions of the period, N·m."""
    tau = _phases(lin, plan, t_over_T)
    F = np.broadcast_to(lin.force(speed), (tau.shape[1], lin.m)).copy()
    omega0 = plan.fundamental * speed  # fundamental in cycles per second
    for j in range(len(lin.names)):
        if not plan.orders[j] or not np.any(lin.errors[j]):
            continue
        k = lin.mean_stiffness[j] * interpolate(lin.profiles[j], tau[j])
        e = interpolate(lin.errors[j], tau[j])
        rate = plan.signs[j] * plan.orders[j] * omega0  # dτ/dt, cycles/s
        e_dot = interpolated_slope(lin.errors[j], tau[j]) * rate
        F += np.multiply.outer(k * e + lin.mesh_damping[j] * e_dot, lin.G[j])
    return F


def system_matrices(
    lin: LinearPeriodic, plan: PeriodPlan, speed: float, t_over_T: np.ndarray, *, forced: bool
) -> np.ndarray:
    """(N, d, d) first-order system matrices A(t) at fractions of the period.

    The state is y = (x, ẋ); A = [[0, I], [−M⁻¹K(t), −M⁻¹C]]; with ``forced`` the state is augmented
    by a constant 1 and the last column carries (0, M⁻¹F(t)), so that one propagator holds both the
    state-transition matrix and the particular solution.

    Parameters
    ----------
    lin : LinearPeriodic
    plan : PeriodPlan
    speed : float
        Reference speed Ω, rad/s.
    t_over_T : ndarray
        Times as fractions of the period, dimensionless.
    forced : bool
        Augment by the forcing column.
    """
    m = lin.m
    N = np.asarray(t_over_T).size
    d = 2 * m + (1 if forced else 0)
    A = np.zeros((N, d, d))
    Minv = np.linalg.inv(lin.M)
    A[:, :m, m : 2 * m] = np.eye(m)
    A[:, m : 2 * m, :m] = -Minv @ _stiffness_matrices(lin, plan, t_over_T)
    A[:, m : 2 * m, m : 2 * m] = -Minv @ lin.C
    if forced:
        A[:, m : 2 * m, 2 * m] = _excitation(lin, plan, speed, t_over_T) @ Minv.T
    return A


# -- propagators ------------------------------------------------------------------------------------
_PADE13 = (
    64764752532480000.0,
    32382376266240000.0,
    7771770303897600.0,
    1187353796428800.0,
    129060195264000.0,
    10559470521600.0,
    670442572800.0,
    33522128640.0,
    1323241920.0,
    40840800.0,
    960960.0,
    16380.0,
    182.0,
    1.0,
)


def expm_stack(A: np.ndarray) -> np.ndarray:
    """Matrix exponentials of a stack of square matrices, (N, d, d).

    Scaling and squaring with the [13/13] Padé approximant (Higham, *SIAM J. Matrix Anal. Appl.* 26,
    2005, Algorithm 2.3), one scaling for the whole stack; vectorised, unlike a loop of
    :func:`scipy.linalg.expm` calls.

    Parameters
    ----------
    A : ndarray
        (N, d, d) matrices, in the unit of their entries times time (dimensionless).
    """
    A = np.asarray(A, float)
    if A.size == 0:
        return A.copy()
    d = A.shape[-1]
    norm = float(np.abs(A).sum(axis=-2).max())
    s = max(0, math.ceil(math.log2(norm / 5.371920351148152))) if norm > 0 else 0
    A = A / 2.0**s
    b = _PADE13
    eye = np.broadcast_to(np.eye(d), A.shape)
    A2 = A @ A
    A4 = A2 @ A2
    A6 = A4 @ A2
    U = A @ (A6 @ (b[13] * A6 + b[11] * A4 + b[9] * A2) + b[7] * A6 + b[5] * A4 + b[3] * A2 + b[1] * eye)
    V = A6 @ (b[12] * A6 + b[10] * A4 + b[8] * A2) + b[6] * A6 + b[4] * A4 + b[2] * A2 + b[0] * eye
    R = np.linalg.solve(V - U, V + U)
    for _ in range(s):
        R = R @ R
    return R


def ordered_product(E: np.ndarray) -> np.ndarray:
    """E[N−1] ⋯ E[1] E[0] of a stack (N, d, d), by pairwise products (log₂ N vectorised steps).

    Parameters
    ----------
    E : ndarray
        (N, d, d) propagators of consecutive segments, dimensionless.
    """
    E = np.asarray(E)
    while E.shape[0] > 1:
        if E.shape[0] % 2:
            last = E[-1:]
            E = np.concatenate([E[1:-1:2] @ E[0:-1:2], last], axis=0)
        else:
            E = E[1::2] @ E[0::2]
    return E[0]


def segments(lin: LinearPeriodic, plan: PeriodPlan, substeps: int, speed: float | None = None) -> int:
    """Segments per period for the Magnus product.

    Every profile sample interval of every mesh is a whole number of segments where the lengths allow
    (then the product is exact for piecewise constant and fourth-order for piecewise linear
    stiffness), at least ``substeps`` per interval; at ``speed`` the count is raised (by whole
    multiples, up to :data:`MAX_SEGMENTS`) until a segment spans at most 0.1 rad of the highest
    natural frequency, where the fourth-order error of a varying segment falls below about 1e-8.

    Parameters
    ----------
    lin : LinearPeriodic
    plan : PeriodPlan
    substeps : int
        Segments per profile sample interval, a count.
    speed : float, optional
        Reference speed Ω, rad/s.
    """
    counts = [
        p.size * int(o)
        for p, e, o in zip(lin.profiles, lin.errors, plan.orders, strict=True)
        if o and (np.ptp(p) > 0 or np.ptp(e) > 0)
    ]
    if not counts:
        return max(1, substeps)
    common = math.lcm(*counts)
    n = substeps * (common if common <= 16 * max(counts) else max(counts))
    if speed is not None:
        need = _highest_frequency(lin) * plan.period(speed) / 0.1
        n *= max(1, min(math.ceil(need / n), MAX_SEGMENTS // n))
    return n


def _highest_frequency(lin: LinearPeriodic) -> float:
    """Highest natural frequency of the system at its stiffest mesh phase bound, rad/s."""
    k_top = np.array([k * p.max() for k, p in zip(lin.mean_stiffness, lin.profiles, strict=True)])
    K = lin.K + (lin.G.T * k_top) @ lin.G
    w2 = np.linalg.eigvals(np.linalg.solve(lin.M, K)).real
    return float(np.sqrt(max(w2.max(), 0.0))) if w2.size else 0.0


def propagators(
    lin: LinearPeriodic, plan: PeriodPlan, speed: float, n_segments: int, *, forced: bool
) -> np.ndarray:
    """(N, d, d) fourth-order Magnus propagators of N uniform segments of one period.

    exp(Ω_k) with Ω_k = h/2 (A₁ + A₂) + (√3/12) h² [A₂, A₁], A at the two Gauss points of the segment
    (Blanes, Casas, Oteo & Ros, *Physics Reports* 470, 2009, eq. 253); exact when A is constant on it.

    Parameters
    ----------
    lin : LinearPeriodic
    plan : PeriodPlan
    speed : float
        Reference speed Ω, rad/s.
    n_segments : int
        Segments per period, a count.
    forced : bool
        Augment by the forcing (see :func:`system_matrices`).
    """
    T = plan.period(speed)
    h = 1.0 / n_segments
    start = np.arange(n_segments) * h
    g1, g2 = 0.5 - math.sqrt(3) / 6, 0.5 + math.sqrt(3) / 6
    A1 = system_matrices(lin, plan, speed, start + g1 * h, forced=forced)
    A2 = system_matrices(lin, plan, speed, start + g2 * h, forced=forced)
    dt = T * h
    Om = 0.5 * dt * (A1 + A2) + (math.sqrt(3) / 12) * dt**2 * (A2 @ A1 - A1 @ A2)
    return expm_stack(Om)


def ivp_propagators(
    lin: LinearPeriodic, plan: PeriodPlan, speed: float, n_segments: int, *, forced: bool, rtol: float = 1e-11
) -> np.ndarray:
    """(N, d, d) state-transition matrices of N uniform segments of one period, by solve_ivp.

    Each segment is integrated on its own (DOP853 from the identity), so that no step straddles a
    corner of the piecewise linear stiffness when the segments follow the profile samples
    (:func:`segments` with ``substeps=1``).

    Parameters
    ----------
    lin : LinearPeriodic
    plan : PeriodPlan
    speed : float
        Reference speed Ω, rad/s.
    n_segments : int
        Segments per period, a count.
    forced : bool
        Augment by the forcing (see :func:`system_matrices`).
    rtol : float
        Relative tolerance of the integration, dimensionless.
    """
    from scipy.integrate import solve_ivp

    T = plan.period(speed)
    d = 2 * lin.m + (1 if forced else 0)
    out = np.empty((n_segments, d, d))
    edges = T * np.arange(n_segments + 1) / n_segments

    # A(t) = A₀ + Σ_j k_j(t) B_j (+ the forcing column), its parts computed once
    m = lin.m
    A0 = system_matrices(
        lin, replace(plan, orders=np.zeros_like(plan.orders)), speed, np.zeros(1), forced=forced
    )[0]
    Minv = np.linalg.inv(lin.M)
    A0[m : 2 * m, :m] = -Minv @ lin.K
    if forced:
        A0[m : 2 * m, 2 * m] = Minv @ lin.force(speed)
    B = [-(Minv @ np.outer(g, g)) for g in lin.G]
    MG = [Minv @ g for g in lin.G]
    f0 = plan.fundamental * speed
    o = plan.orders * plan.signs

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        A = A0.copy()
        for j in range(len(B)):
            tau = o[j] * f0 * t
            k = lin.mean_stiffness[j] * (float(interpolate(lin.profiles[j], tau)) if o[j] else 1.0)
            A[m : 2 * m, :m] += k * B[j]
            if forced and o[j] and lin.errors[j].any():
                e = float(interpolate(lin.errors[j], tau))
                e_dot = float(interpolated_slope(lin.errors[j], tau)) * o[j] * f0
                A[m : 2 * m, 2 * m] += (k * e + lin.mesh_damping[j] * e_dot) * MG[j]
        return (A @ y.reshape(d, d)).ravel()

    for k in range(n_segments):
        sol = solve_ivp(
            rhs,
            (edges[k], edges[k + 1]),
            np.eye(d).ravel(),
            method="DOP853",
            rtol=rtol,
            atol=rtol * _ATOL_PER_RTOL,
        )
        if not sol.success:  # pragma: no cover - DOP853 on a linear system with bounded coefficients
            raise ModelError(f"the state-transition matrix could not be integrated: {sol.message}")
        out[k] = sol.y[:, -1].reshape(d, d)
    return out


def _check_speed(field: str, speed: Any) -> float:
    return check_number("gear dynamics", field, speed, "rad/s", positive=True, what="speed")


def _check_method(method: str) -> None:
    if method not in ("magnus", "ivp"):
        raise ModelError(
            f"method {method!r}: give 'magnus' (product of matrix exponentials) or 'ivp' (solve_ivp)",
            element="gear dynamics",
            field="method",
        )


def _monodromy(
    lin: LinearPeriodic, plan: PeriodPlan, speed: float, method: str, substeps: int, rtol: float = 1e-11
) -> np.ndarray:
    if method == "ivp":
        return ordered_product(
            ivp_propagators(lin, plan, speed, segments(lin, plan, 1), forced=False, rtol=rtol)
        )
    return ordered_product(propagators(lin, plan, speed, segments(lin, plan, substeps, speed), forced=False))


def monodromy(
    system: Any,
    speed: float,
    *,
    reference: str,
    boundary: Boundary = "prescribed",
    method: Integrator = "magnus",
    substeps: int = 4,
) -> np.ndarray:
    """The monodromy matrix Φ(T) of a drivetrain's linear vibration at a constant speed.

    Parameters
    ----------
    system : GearSystem
        The time-varying system of a drivetrain (backlash ignored: teeth in contact).
    speed : float
        Speed Ω of the reference disk, rad/s, positive.
    reference : str
        The disk turning at Ω.
    boundary : {"prescribed", "free"}
        How the rigid-body motion is removed (see :func:`linear_periodic`).
    method : {"magnus", "ivp"}
        Product of fourth-order Magnus exponentials over uniform segments, or solve_ivp (DOP853,
        rtol 1e-11) on the state-transition matrix.
    substeps : int
        Magnus segments per profile sample interval, a count from 1 to 1000.

    Returns
    -------
    ndarray
        (2m, 2m) Φ(T) on the state (x, ẋ), dimensionless and 1/s, s blocks; T is the common mesh
        period (:func:`period_plan`).

    Notes
    -----
    Floquet theory of linear periodic systems: Nayfeh & Mook, *Nonlinear Oscillations* (1979), §5.2.
    """
    _check_method(method)
    substeps = check_count("gear dynamics", "substeps", substeps, low=1, high=1000, what="substeps")
    lin = linear_periodic(system, reference=reference, boundary=boundary)
    speed = _check_speed("speed", speed)
    return _monodromy(lin, period_plan(lin), speed, method, substeps)


def _spectral(Phi: np.ndarray, lin: LinearPeriodic | None = None) -> tuple[np.ndarray, float]:
    """Floquet multipliers (largest first) and spectral radius of ``Phi``, without the rigid-body
    angle's multiplier of ``lin`` where it is in the state."""
    mu = np.linalg.eigvals(lin.deflate(Phi) if lin is not None else Phi)
    mu = mu[np.argsort(-np.abs(mu), kind="stable")]
    return mu, float(np.abs(mu[0])) if mu.size else 0.0


@dataclass(frozen=True, repr=False)
class FloquetResult(Result):
    """Floquet multipliers of a drivetrain's linear vibration over speed.

    Attributes
    ----------
    speeds : ndarray
        (n_s,) reference speeds Ω, rad/s.
    multipliers : ndarray
        (n_s, 2m) complex Floquet multipliers, largest modulus first, dimensionless.
    periods : ndarray
        (n_s,) the period T of the monodromy matrix, s.
    mesh_names : tuple of str
    mesh_cycles : ndarray
        (J,) mesh cycles per radian of the reference disk (ω_mesh = 2π · cycles · Ω), dimensionless.
    natural_frequencies_hz : ndarray
        Natural frequencies of the mean system with the same boundary, Hz.
    reference : str
    boundary : str
    method : str
    notes : tuple of str
    """

    speeds: np.ndarray
    multipliers: np.ndarray
    periods: np.ndarray
    mesh_names: tuple[str, ...]
    mesh_cycles: np.ndarray
    natural_frequencies_hz: np.ndarray
    reference: str
    boundary: str
    method: str
    notes: tuple[str, ...] = field(default=())

    @property
    def spectral_radius(self) -> np.ndarray:
        """ρ(Ω), the largest modulus of the multipliers, dimensionless."""
        return np.abs(self.multipliers[:, 0]) if self.multipliers.size else np.zeros(self.speeds.size)

    @property
    def growth_rate(self) -> np.ndarray:
        """ln ρ / T, 1/s: the exponential rate at which the free vibration grows (> 0) or decays."""
        return np.log(self.spectral_radius) / self.periods

    @property
    def unstable(self) -> np.ndarray:
        """True where ρ > 1 (parametric instability)."""
        return self.spectral_radius > 1.0 + UNSTABLE_MARGIN

    def unstable_ranges(self) -> list[tuple[float, float]]:
        """Speed ranges (rad/s) of consecutive unstable samples, as (first, last)."""
        out, start = [], None
        for i, bad in enumerate(self.unstable):
            if bad and start is None:
                start = i
            if start is not None and (not bad or i == self.speeds.size - 1):
                last = i if bad else i - 1
                out.append((float(self.speeds[start]), float(self.speeds[last])))
                start = None
        return out

    def summary(self) -> dict[str, Any]:
        """Speed range (rad/s), largest spectral radius and where, unstable speed ranges (rad/s)."""
        rho = self.spectral_radius
        i = int(np.argmax(rho))
        return {
            "reference": self.reference,
            "boundary": self.boundary,
            "speed_min_rad_s": float(self.speeds.min()),
            "speed_max_rad_s": float(self.speeds.max()),
            "spectral_radius_max_ratio": float(rho[i]),
            "spectral_radius_max_at_rad_s": float(self.speeds[i]),
            "unstable_ranges_rad_s": [list(r) for r in self.unstable_ranges()],
            "natural_frequencies_hz": self.natural_frequencies_hz.tolist(),
        }

    def to_frame(self) -> pd.DataFrame:
        """One row per speed: speed (rad/s, rpm), mesh frequencies (Hz), ρ, growth rate, unstable."""
        import pandas as pd

        from mechdyn.units import convert

        cols: dict[str, Any] = {
            "speed_rad_s": self.speeds,
            "speed_rpm": np.asarray(convert(self.speeds, "rad/s", "rpm")),
        }
        for name, c in zip(self.mesh_names, self.mesh_cycles, strict=True):
            cols[f"{name}_mesh_frequency_hz"] = np.abs(c) * self.speeds
        cols["spectral_radius_ratio"] = self.spectral_radius
        cols["growth_rate_per_s"] = self.growth_rate
        cols["unstable"] = self.unstable
        return pd.DataFrame(cols)

    def tables(self, **display_units: str) -> list[Table]:
        """The summary, and the unstable speed ranges in rpm."""
        from mechdyn.results import summary_table
        from mechdyn.units import convert

        rows = [
            [float(convert(a, "rad/s", "rpm")), float(convert(b, "rad/s", "rpm"))]
            for a, b in self.unstable_ranges()
        ]
        return [
            summary_table(self.summary(), display_units=display_units),
            Table(
                "parametric instability: speed ranges where the largest Floquet multiplier exceeds 1",
                ["from [rpm]", "to [rpm]"],
                rows or [["none", "none"]],
                note=" ".join(self.notes),
            ),
        ]

    def plots(self, **display_units: str) -> dict[str, Any]:
        """``floquet.png``: the spectral radius over speed, unstable ranges shaded."""
        from mechdyn.gear_dynamics.sweep_plots import plot_floquet

        return {"floquet.png": lambda: plot_floquet(self)}

    @property
    def warnings(self) -> tuple[str, ...]:
        """How the period was chosen where the meshes have no common one."""
        return self.notes


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


def floquet(
    system: Any,
    speeds: Any,
    *,
    reference: str,
    boundary: Boundary = "prescribed",
    method: Integrator = "magnus",
    substeps: int = 4,
) -> FloquetResult:
    """Floquet multipliers and parametric stability of a drivetrain over speed.

    Parameters
    ----------
    system : GearSystem
        The time-varying system of a drivetrain (teeth in contact: backlash is ignored).
    speeds : array_like
        Speeds Ω of the reference disk, rad/s, positive.
    reference : str
        The disk turning at Ω (a motor disk).
    boundary : {"prescribed", "free"}
        ``"prescribed"`` holds the reference disk at Ω (its coordinate leaves the state, and with it
        the rigid-body multipliers); ``"free"`` projects the rigid-body motion out.
    method : {"magnus", "ivp"}
        How Φ(T) is computed (:func:`monodromy`).
    substeps : int
        Magnus segments per profile sample interval, a count from 1 to 1000.

    Returns
    -------
    FloquetResult

    Notes
    -----
    The system is unstable where the spectral radius ρ of Φ(T) exceeds 1 (Nayfeh & Mook, *Nonlinear
    Oscillations*, 1979, §5.2); for one mesh of stiffness k̄ (1 + ε cos ω_m t) the principal
    instability lies near ω_m = 2 ω_n / k, k = 1, 2, … (the Mathieu equation, ibid. §5.3).
    """
    _check_method(method)
    substeps = check_count("gear dynamics", "substeps", substeps, low=1, high=1000, what="substeps")
    lin = linear_periodic(system, reference=reference, boundary=boundary)
    s = _speeds(speeds)
    plan = period_plan(lin)
    mus, periods = [], []
    for speed in s:
        mu, _ = _spectral(_monodromy(lin, plan, float(speed), method, substeps), lin)
        mus.append(mu)
        periods.append(plan.period(float(speed)))
    return FloquetResult(
        speeds=s,
        multipliers=np.array(mus).reshape(s.size, -1),
        periods=np.array(periods),
        mesh_names=lin.names,
        mesh_cycles=lin.cycles,
        natural_frequencies_hz=_natural_frequencies(lin),
        reference=reference,
        boundary=boundary,
        method=method,
        notes=(plan.note,) if plan.note else (),
    )


@dataclass(frozen=True, repr=False)
class StabilityChart(Result):
    """Spectral radius over speed and mesh stiffness variation (an Ince–Strutt chart in gear terms).

    Attributes
    ----------
    speeds : ndarray
        (n_s,) reference speeds, rad/s.
    amplitudes : ndarray
        (n_e,) relative stiffness variation ε of the chosen mesh (k = k̄ (1 + ε · shape)), dimensionless.
    spectral_radius : ndarray
        (n_e, n_s) ρ, dimensionless.
    mesh : str
        The mesh whose variation is scaled.
    mesh_cycles : float
        Its mesh cycles per radian of the reference disk, dimensionless.
    natural_frequencies_hz : ndarray
        Of the mean system with the same boundary, Hz.
    reference : str
    """

    speeds: np.ndarray
    amplitudes: np.ndarray
    spectral_radius: np.ndarray
    mesh: str
    mesh_cycles: float
    natural_frequencies_hz: np.ndarray
    reference: str

    @property
    def unstable(self) -> np.ndarray:
        """(n_e, n_s) True where ρ > 1."""
        return self.spectral_radius > 1.0 + UNSTABLE_MARGIN

    def critical_speeds(self, orders: int = 2) -> np.ndarray:
        """Speeds (rad/s) where the mesh frequency is 2 f_n / k, k = 1 … ``orders``, for every natural
        frequency (the centres of the principal and secondary instability regions).

        Parameters
        ----------
        orders : int
            How many k, a count.
        """
        f = self.natural_frequencies_hz[self.natural_frequencies_hz > 0]
        k = np.arange(1, orders + 1)
        return np.sort((2 * f[:, None] / k[None, :]).ravel() / abs(self.mesh_cycles))

    def summary(self) -> dict[str, Any]:
        """Ranges of speed (rad/s) and ε, share of unstable points, the principal critical speeds."""
        return {
            "mesh": self.mesh,
            "speed_min_rad_s": float(self.speeds.min()),
            "speed_max_rad_s": float(self.speeds.max()),
            "amplitude_max_ratio": float(self.amplitudes.max()),
            "unstable_share_ratio": float(self.unstable.mean()),
            "principal_critical_speeds_rad_s": self.critical_speeds(1).tolist(),
        }

    def to_frame(self) -> pd.DataFrame:
        """One row per (ε, speed): speed (rad/s), ε, ρ and whether unstable."""
        import pandas as pd

        e, s = np.meshgrid(self.amplitudes, self.speeds, indexing="ij")
        return pd.DataFrame(
            {
                "speed_rad_s": s.ravel(),
                "amplitude_ratio": e.ravel(),
                "spectral_radius_ratio": self.spectral_radius.ravel(),
                "unstable": self.unstable.ravel(),
            }
        )

    def plots(self, **display_units: str) -> dict[str, Any]:
        """``stability_chart.png``: unstable regions shaded over speed and ε."""
        from mechdyn.gear_dynamics.sweep_plots import plot_stability_chart

        return {"stability_chart.png": lambda: plot_stability_chart(self)}


def stability_chart(
    system: Any,
    speeds: Any,
    amplitudes: Any,
    *,
    reference: str,
    mesh: str | None = None,
    boundary: Boundary = "prescribed",
    substeps: int = 4,
) -> StabilityChart:
    """Parametric stability over speed and the stiffness variation of one mesh.

    The mesh's stiffness becomes k̄ (1 + ε s(τ)), s its own profile's variation scaled to a half
    peak-to-peak of 1 (a cosine where its stiffness is constant), for every ε in ``amplitudes``; the
    other meshes keep theirs. Φ(T) by the Magnus product (:func:`monodromy`).

    Parameters
    ----------
    system : GearSystem
        The time-varying system of a drivetrain.
    speeds : array_like
        Speeds Ω of the reference disk, rad/s, positive.
    amplitudes : array_like
        Relative stiffness variations ε, dimensionless, from 0 to below 1 (k stays positive).
    reference : str
        The disk turning at Ω.
    mesh : str, optional
        The mesh whose variation is scaled (default: the first flexible mesh).
    boundary : {"prescribed", "free"}
        How the rigid-body motion is removed (see :func:`linear_periodic`).
    substeps : int
        Magnus segments per profile sample interval, a count from 1 to 1000.

    Returns
    -------
    StabilityChart

    Notes
    -----
    For a single mesh this is the Ince–Strutt chart of the damped Mathieu equation (Nayfeh & Mook,
    *Nonlinear Oscillations*, 1979, §5.3 and fig. 5-3), in speed instead of δ = (ω_n / ω_m)².
    """
    substeps = check_count("gear dynamics", "substeps", substeps, low=1, high=1000, what="substeps")
    lin = linear_periodic(system, reference=reference, boundary=boundary)
    if not lin.names:
        raise ModelError("the drivetrain has no flexible mesh", element="gear dynamics", field="mesh")
    if mesh is None:
        mesh = lin.names[0]
    if mesh not in lin.names:
        raise ModelError(
            f"mesh {mesh!r} is not a flexible mesh; give one of {', '.join(lin.names)}",
            element="gear dynamics",
            field="mesh",
        )
    eps = np.atleast_1d(
        check_array("gear dynamics", "amplitudes", amplitudes, low=0.0, high=1.0, high_open=True)
    )
    s = _speeds(speeds)
    j = lin.names.index(mesh)
    p = lin.profiles[j]
    if np.ptp(p) > 0:
        shape = (p - p.mean()) / (0.5 * np.ptp(p))
    else:
        shape = np.cos(2 * np.pi * np.arange(p.size) / max(p.size, 64))
        if p.size < 64:
            shape = np.cos(2 * np.pi * np.arange(64) / 64)
    rho = np.empty((eps.size, s.size))
    for a, e in enumerate(eps):
        profiles = list(lin.profiles)
        profiles[j] = 1.0 + e * shape
        lin_e = lin.with_profiles(tuple(profiles))
        plan = period_plan(lin_e)
        for b, speed in enumerate(s):
            rho[a, b] = _spectral(_monodromy(lin_e, plan, float(speed), "magnus", substeps), lin_e)[1]
    return StabilityChart(
        speeds=s,
        amplitudes=eps,
        spectral_radius=rho,
        mesh=mesh,
        mesh_cycles=float(lin.cycles[j]),
        natural_frequencies_hz=_natural_frequencies(lin),
        reference=reference,
    )
