"""A geared drivetrain in time: the structure, and each flexible mesh as a time-varying spring.

The drivetrain's reduced coordinates q are those of its assembly (rigid meshes reduced out exactly,
θ_disks = T q, :mod:`mechdyn.drivetrain.assembly`). Every flexible gear mesh j becomes a
:class:`MeshLink`: its deflection along the line of action δ_j = g_j · q (external mesh
δ = r_a θ_a + r_b θ_b, internal mesh δ = r_a θ_a − r_b θ_b, r base radii, the sign convention of
:mod:`mechdyn.drivetrain.elements`), its stiffness k_j(τ_j) over the mesh cycle, its static transmission
error e_j(τ_j) and its backlash. The mesh phase τ_j = z_a θ_a / (2π) counts mesh cycles (one cycle per
tooth of gear a). The equation of motion is

.. math:: M \\ddot q + C \\dot q + K q + \\sum_j g_j f_j = Q(t, q, \\dot q),

with K and C the structure without the flexible meshes and f_j the mesh force of
:meth:`MeshLink.force` (Kahraman & Singh, "Non-linear dynamics of a spur gear pair", J. Sound Vib.
142 (1990) 49–75, extended to a drivetrain as in Özgüven & Houser, "Mathematical models used in gear
dynamics", J. Sound Vib. 121 (1988) 383–411).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.checks import check_array, check_count
from mechdyn.drivetrain.gear_mesh import GearMesh
from mechdyn.drivetrain.model import Drivetrain
from mechdyn.errors import ModelError
from mechdyn.gears.mesh import MeshCycle
from mechdyn.units import si_field

__all__ = ["DEFAULT_SAMPLES", "GearSystem", "MeshLink", "rectangular_profile"]

DEFAULT_SAMPLES = 360
"""Samples per mesh cycle of a profile given by its shape (rectangular wave, sine error)."""


def _periodic_interp(values: np.ndarray, tau: Any) -> Any:
    """Periodic linear interpolation of samples at τ = i/P, i = 0..P−1, at phases ``tau`` (cycles)."""
    p = values.size
    x = np.asarray(tau, dtype=float) * p
    base = np.floor(x)
    frac = x - base
    i = base.astype(np.int64) % p
    out = values[i] * (1.0 - frac) + values[(i + 1) % p] * frac
    return float(out) if out.ndim == 0 else out


def _periodic_slope(values: np.ndarray, tau: Any) -> Any:
    """d/dτ of the periodic linear interpolant (per cycle), the slope of the segment holding τ."""
    p = values.size
    x = np.asarray(tau, dtype=float) * p
    i = np.floor(x).astype(np.int64) % p
    out = (values[(i + 1) % p] - values[i]) * p
    return float(out) if out.ndim == 0 else out


def rectangular_profile(
    fluctuation: float, contact_ratio: float, samples: int = DEFAULT_SAMPLES
) -> np.ndarray:
    """The classic single/double contact mesh stiffness wave, k(τ)/k̄, sampled at τ = i/P.

    Two tooth pairs carry the load for 0 ≤ τ < ε − 1, one pair for the rest of the cycle; the wave
    has mean 1 and peak-to-peak ``fluctuation``: k/k̄ = 1 + f (2 − ε) in double contact and
    1 − f (ε − 1) in single contact.

    Parameters
    ----------
    fluctuation : float
        Peak-to-peak (k_max − k_min) / k̄, dimensionless, in [0, 1) for a wave that stays positive.
    contact_ratio : float
        Transverse contact ratio ε, dimensionless, 1 ≤ ε ≤ 2.
    samples : int
        Samples per cycle P, count.

    Returns
    -------
    ndarray
        (P,) k(τ)/k̄, dimensionless.

    Notes
    -----
    Rectangular-wave mesh stiffness of a spur pair with 1 < ε < 2: e.g. Kahraman & Singh, "Interactions
    between time-varying mesh stiffness and clearance non-linearities in a geared system", J. Sound
    Vib. 146 (1991) 135–156; Özgüven & Houser (1988).
    """
    f = si_field("mesh profile", "fluctuation", fluctuation, "", low=0.0, high=2.0, high_open=True)
    eps = si_field("mesh profile", "contact_ratio", contact_ratio, "", low=1.0, high=2.0)
    p = check_count("mesh profile", "samples", samples, low=4, high=1_000_000, what="samples")
    d = eps - 1.0
    tau = np.arange(p) / p
    high, low = 1.0 + f * (2.0 - eps), 1.0 - f * d
    if low <= 0.0:
        raise ModelError(
            f"fluctuation {f:g} with contact ratio {eps:g} makes the single-contact stiffness "
            f"{low:g} k̄, not positive; give a smaller fluctuation",
            element="mesh profile",
            field="fluctuation",
        )
    return np.where(tau < d - 1e-12, high, low)


@dataclass(frozen=True, eq=False)
class MeshLink:
    """One flexible gear mesh in the time-varying system.

    Attributes
    ----------
    name : str
        The :class:`~mechdyn.drivetrain.GearMesh` it is.
    g : ndarray
        (n,) δ = g · q: the mesh deflection along the line of action per unit reduced coordinate, m/rad.
        g = Tᵀ v with v = (r_a, ±r_b) on the mesh's two disks (+ external, − internal).
    mean_stiffness : float
        k̄, N/m (the GearMesh's stiffness; the mean of a gear pair's mesh cycle when from gear data).
    damping : float
        c_m, N·s/m along the line of action.
    teeth : int
        z_a, teeth of gear a (count); the mesh phase is τ = z_a θ_a / (2π) cycles. 0 when the mesh gives
        no teeth (then the stiffness is constant and there is no error: the phase does not matter).
    phase_row : ndarray
        (n,) θ_a = phase_row · q, rad per unit coordinate.
    profile : ndarray
        (P,) k(τ)/k̄ at τ = i/P, i = 0..P−1 (periodic, mean 1), dimensionless; all ones = constant.
    error : ndarray
        (P,) static transmission error e(τ) at the same phases, m; zeros = none.
    backlash : float or None
        Total backlash b along the line of action, m; None = the teeth never separate.
    phase : float
        The mesh's clocking φ, mesh cycles in [0, 1): :attr:`profile` and :attr:`error` are the
        unclocked cycle's read at τ + φ (a whole number of samples: φ is the given phase rounded to
        1/P), so that the cycle starts (a pair entering contact) at τ = −φ.
    """

    name: str
    g: np.ndarray
    mean_stiffness: float
    damping: float
    teeth: int
    phase_row: np.ndarray
    profile: np.ndarray
    error: np.ndarray
    backlash: float | None
    phase: float = 0.0

    @property
    def samples(self) -> int:
        """P, the samples per mesh cycle (count)."""
        return int(self.profile.size)

    @property
    def varies(self) -> bool:
        """True when the stiffness or the error changes over the cycle."""
        return bool(np.ptp(self.profile) > 0.0 or np.ptp(self.error) > 0.0)

    def stiffness(self, tau: Any) -> Any:
        """Mesh stiffness k(τ), N/m, by periodic linear interpolation of :attr:`profile`.

        Parameters
        ----------
        tau : float or ndarray
            Mesh phase τ, cycles (count of mesh cycles; any real number, periodic with period 1).
        """
        return self.mean_stiffness * _periodic_interp(self.profile, tau)

    def transmission_error(self, tau: Any) -> Any:
        """Static transmission error e(τ), m, by periodic linear interpolation of :attr:`error`.

        Parameters
        ----------
        tau : float or ndarray
            Mesh phase τ, cycles (count of mesh cycles).
        """
        return _periodic_interp(self.error, tau)

    def harmonics(self, orders: int) -> np.ndarray:
        """Fourier coefficients c_0 … c_H of k(τ)/k̄ (the interpolated profile, exactly).

        k(τ)/k̄ = Re Σ_{h=0}^{H} c_h exp(2πi h τ): c_0 is the mean (1), and c_h for h ≥ 1 is twice the
        two-sided coefficient (1/P) Σ_i p_i exp(−2πi h i/P) · sinc²(h/P), the sinc² being the
        spectrum of the linear interpolation between the samples (a triangle kernel).

        Parameters
        ----------
        orders : int
            H, the highest mesh order (count).

        Returns
        -------
        ndarray
            (H + 1,) complex, dimensionless.

        Notes
        -----
        Linear interpolation is the convolution of the sample comb with a triangle of base 2/P, whose
        transform is sinc²: e.g. Oppenheim & Schafer, *Discrete-Time Signal Processing*, §4.6.
        """
        h_max = check_count(self.name, "orders", orders, low=0, high=10_000_000, what="orders")
        p = self.samples
        h = np.arange(h_max + 1)
        i = np.arange(p)
        dft = np.exp(-2j * np.pi * np.outer(h, i) / p) @ self.profile / p
        c = dft * np.sinc(h / p) ** 2
        c[1:] *= 2.0
        return c

    def force(self, delta: float, delta_rate: float, tau: float, tau_rate: float) -> float:
        """Mesh force along the line of action, N.

        f = k(τ) h(x) + c_m (δ̇ − e′(τ) τ̇) · [in contact], x = δ − e(τ), with the backlash function
        h(x) = x for x > 0, 0 for −b ≤ x ≤ 0, x + b for x < −b (h(x) = x without backlash); in contact
        means x > 0 (drive side) or x < −b (back side).

        Parameters
        ----------
        delta : float
            δ, mesh deflection along the line of action, m.
        delta_rate : float
            dδ/dt, m/s.
        tau : float
            Mesh phase τ, cycles (dimensionless).
        tau_rate : float
            dτ/dt, cycles/s (1/s).

        Notes
        -----
        Kahraman & Singh (1990), the dynamic transmission error form of a spur pair with clearance: the
        contact law :func:`mechdyn.gear_dynamics._contact.mesh_force`, the one every solver uses.
        """
        from mechdyn.gear_dynamics._contact import BY_SIGN, NO_BACKLASH, mesh_force

        k = float(self.stiffness(tau))
        x = float(delta - self.transmission_error(tau))
        rate = float(delta_rate - _periodic_slope(self.error, tau) * tau_rate)
        gap = NO_BACKLASH if self.backlash is None else float(self.backlash)
        return float(mesh_force(k, float(self.damping), x, rate, gap, BY_SIGN)[0])


def _profile_from(name: str, value: Any) -> np.ndarray:
    """k(τ)/k̄ samples (mean 1) from a MeshCycle, an array or a rectangular-wave description."""
    if value is None:
        return np.ones(1)
    if isinstance(value, MeshCycle):  # its own k/k̄ at τ = i/P, τ = 0 where a pair enters contact
        own = np.asarray(value.profile(), dtype=float)
        return own / own.mean()
    if isinstance(value, Mapping):
        unknown = set(value) - {"fluctuation", "contact_ratio", "samples"}
        if unknown or "fluctuation" not in value or "contact_ratio" not in value:
            raise ModelError(
                f"{dict(value)!r}: give {{'fluctuation': peak-to-peak k/k̄, 'contact_ratio': ε}} "
                "(optionally 'samples'), a MeshCycle or an array of k/k̄ over one cycle",
                element=name,
                field="mesh_profiles",
            )
        return rectangular_profile(
            value["fluctuation"], value["contact_ratio"], value.get("samples", DEFAULT_SAMPLES)
        )
    arr = check_array(name, "mesh_profiles", value, "", positive=True, what="relative stiffness")
    if arr.ndim != 1 or arr.size < 2:
        raise ModelError(
            f"an array of k/k̄ over one mesh cycle needs at least 2 samples in one row, got shape {arr.shape}",
            element=name,
            field="mesh_profiles",
        )
    return arr / arr.mean()


def _error_from(name: str, value: Any, samples: int) -> np.ndarray:
    if value is None:
        return np.zeros(1)
    if isinstance(value, Mapping):
        if set(value) - {"amplitude", "samples"} or "amplitude" not in value:
            raise ModelError(
                f"{dict(value)!r}: give {{'amplitude': m}} (a sine at the mesh frequency) or an array "
                "of e(τ) in m over one mesh cycle",
                element=name,
                field="errors",
            )
        amp = si_field(name, "errors", value["amplitude"], "m", nonnegative=True, what="error amplitude")
        p = check_count(name, "samples", value.get("samples", max(samples, DEFAULT_SAMPLES)), low=4)
        return amp * np.sin(2.0 * np.pi * np.arange(p) / p)
    arr = check_array(name, "errors", value, "m", what="transmission error")
    if arr.ndim != 1 or arr.size < 2:
        raise ModelError(
            f"an array of e(τ) in m over one mesh cycle needs at least 2 samples in one row, got shape "
            f"{arr.shape}",
            element=name,
            field="errors",
        )
    return arr


def _phase_from(name: str, value: Any, teeth: int) -> float:
    """A mesh's clocking in mesh cycles from a number of cycles or an angle of gear a (a quantity:
    z_a · angle / 2π cycles), in [0, 1)."""
    from mechdyn.units import si_field

    if isinstance(value, str) or hasattr(value, "units"):  # a quantity: an angle of gear a
        angle = si_field(name, "phases", value, "rad", what="clocking angle of gear a")
        cycles = teeth * angle / (2.0 * math.pi)
    else:
        cycles = si_field(name, "phases", value, "", what="clocking in mesh cycles")
    return float(np.mod(cycles, 1.0))


def _clocked(values: np.ndarray, phase: float) -> tuple[np.ndarray, float]:
    """Samples over one cycle read at τ + φ: rolled by the whole number of samples nearest φ P, and
    the phase that applies (φ rounded to 1/P)."""
    shift = round(phase * values.size) % values.size
    return np.roll(values, -shift), shift / values.size


def _resample(values: np.ndarray, samples: int) -> np.ndarray:
    if values.size == samples:
        return values
    if values.size == 1:
        return np.full(samples, values[0])
    return np.asarray(_periodic_interp(values, np.arange(samples) / samples))


def _dof_index(drivetrain: Drivetrain) -> dict[str, int]:
    """Row of every degree of freedom: the disks, then any nodes inside divided shafts."""
    return dict(drivetrain.dof_index)


def _dof_names(drivetrain: Drivetrain) -> tuple[str, ...]:
    return tuple(drivetrain.dof_names)


def _check_names(
    drivetrain: Drivetrain, flexible: set[str], given: Mapping[str, Any] | None, field: str
) -> None:
    for key in given or {}:
        if key not in flexible:
            known = ", ".join(sorted(flexible)) or "none"
            raise ModelError(
                f"{key!r} is not a flexible gear mesh of drivetrain {drivetrain.name!r}; flexible meshes: "
                f"{known}",
                element=str(key),
                field=field,
            )


@dataclass(frozen=True, eq=False)
class GearSystem:
    """A geared drivetrain with time-varying, possibly separating meshes, in reduced coordinates.

    Attributes
    ----------
    drivetrain : Drivetrain
        The model it was built from.
    coordinate_names : tuple of str
        The disk each reduced coordinate q is (as :attr:`Assembly.coordinate_names`).
    T : ndarray
        (n_dofs, n) θ = T q, rad per unit coordinate: one row per disk, then (where the drivetrain
        divides shafts into elements) per node inside a shaft.
    M : ndarray
        (n, n) mass matrix, kg·m² (the assembly's: diagonal unless a shaft carries consistent inertia).
    K : ndarray
        (n, n) structural stiffness without the flexible meshes, N·m/rad.
    C : ndarray
        (n, n) structural damping without the meshes' damping, N·m·s/rad.
    meshes : tuple of MeshLink
        The flexible meshes, in the drivetrain's order.
    rigid_body : ndarray
        (n, r) rigid-body motions of the whole system (meshes at mean stiffness), rad per unit motion.
    """

    drivetrain: Drivetrain
    coordinate_names: tuple[str, ...]
    T: np.ndarray
    M: np.ndarray
    K: np.ndarray
    C: np.ndarray
    meshes: tuple[MeshLink, ...]
    rigid_body: np.ndarray

    @classmethod
    def from_drivetrain(
        cls,
        drivetrain: Drivetrain,
        *,
        mesh_profiles: Mapping[str, Any] | None = None,
        errors: Mapping[str, Any] | None = None,
        backlash: Mapping[str, Any] | None = None,
        phases: Mapping[str, Any] | None = None,
    ) -> GearSystem:
        """The time-domain system of a drivetrain, its flexible meshes varying over the mesh cycle.

        Parameters
        ----------
        drivetrain : Drivetrain
            The model; its flexible meshes (those with a stiffness) become :class:`MeshLink`.
        mesh_profiles : mapping of str, optional
            Mesh name → its stiffness over one mesh cycle: a :class:`mechdyn.gears.MeshCycle`
            (resampled uniformly over the cycle), an array (P,) of k/k̄ (dimensionless, normalised to
            mean 1), or ``{"fluctuation": peak-to-peak k/k̄, "contact_ratio": ε}`` for the rectangular
            wave of :func:`rectangular_profile`. The mean stiffness stays the GearMesh's. Default:
            constant.
        errors : mapping of str, optional
            Mesh name → static transmission error over one cycle: an array (P,) in m, or
            ``{"amplitude": m}`` (a sine at the mesh frequency; a quantity such as ``"5 um"``).
        backlash : mapping of str, optional
            Mesh name → total backlash along the line of action, m (or a quantity). Default: none.
        phases : mapping of str, optional
            Mesh name → its clocking: how far its mesh cycle stands ahead when gear a's angle is 0, in
            mesh cycles (a number; 0.25 = a quarter of a base pitch), or an angle of gear a (a quantity
            such as ``"4.7 deg"``: z_a · angle / 360° cycles). It shifts the mesh's stiffness cycle and
            transmission error against the other meshes' (by a whole number of the profile's samples:
            the phase is rounded to 1/P cycle). Default: 0, every mesh's cycle starting together.

        Returns
        -------
        GearSystem

        Raises
        ------
        mechdyn.errors.ModelError
            Naming the mesh and the field for a name that is not a flexible mesh, a bad profile, error
            or backlash, or a varying profile or error on a mesh without teeth.
        """
        asm = drivetrain.assembly
        T = np.asarray(asm.T.toarray(), dtype=float)
        n = T.shape[1]
        idx = _dof_index(drivetrain)
        flexible = [e for e in drivetrain.elements if isinstance(e, GearMesh) and not e.rigid]
        names = {m.name for m in flexible}
        for given, field in (
            (mesh_profiles, "mesh_profiles"),
            (errors, "errors"),
            (backlash, "backlash"),
            (phases, "phases"),
        ):
            _check_names(drivetrain, names, given, field)
        # structure without the flexible meshes, assembled like the drivetrain's own matrices
        n_disks = T.shape[0]
        K_full = np.zeros((n_disks, n_disks))
        C_full = np.zeros((n_disks, n_disks))
        for e, b in drivetrain.element_blocks:
            if isinstance(e, GearMesh) and not e.rigid:
                continue
            dofs = [idx[d] for d in b.disks]
            if b.stiffness is not None:
                K_full[np.ix_(dofs, dofs)] += b.stiffness
            if b.damping is not None:
                C_full[np.ix_(dofs, dofs)] += b.damping
        links = []
        for mesh in flexible:
            ra, rb = mesh.base_radii  # type: ignore[misc]  # a flexible mesh has them
            sign = 1.0 if mesh.kind == "external" else -1.0
            ia, ib = idx[mesh.disks[0]], idx[mesh.disks[1]]
            v = np.zeros(n_disks)
            v[ia] += ra
            v[ib] += sign * rb
            k = float(mesh.stiffness)  # type: ignore[arg-type]
            profile = _profile_from(mesh.name, (mesh_profiles or {}).get(mesh.name))
            error = _error_from(mesh.name, (errors or {}).get(mesh.name), profile.size)
            p = max(profile.size, error.size)
            profile, error = _resample(profile, p), _resample(error, p)
            teeth = mesh.teeth[0] if mesh.teeth is not None else 0
            if teeth == 0 and (np.ptp(profile) > 0 or np.ptp(error) > 0):
                raise ModelError(
                    "a stiffness varying over the mesh cycle or a transmission error needs the gears' "
                    "teeth (the mesh phase counts teeth); give teeth = (z_a, z_b)",
                    element=mesh.name,
                    field="teeth",
                )
            phase = 0.0
            if (phases or {}).get(mesh.name) is not None:
                given_phase = _phase_from(mesh.name, phases[mesh.name], int(teeth))  # type: ignore[index]
                if given_phase and teeth == 0:
                    raise ModelError(
                        "a clocking phase shifts the mesh cycle, which the teeth count; give teeth = "
                        "(z_a, z_b)",
                        element=mesh.name,
                        field="phases",
                    )
                profile, phase = _clocked(profile, given_phase)
                error, _ = _clocked(error, given_phase)
            gap = (backlash or {}).get(mesh.name)
            b_si = None if gap is None else si_field(mesh.name, "backlash", gap, "m", positive=True)
            links.append(
                MeshLink(
                    name=mesh.name,
                    g=T.T @ v,
                    mean_stiffness=k,
                    damping=float(mesh.damping),
                    teeth=int(teeth),
                    phase_row=T[ia].copy(),
                    profile=profile,
                    error=error,
                    backlash=b_si,
                    phase=phase,
                )
            )
        first = [idx[c] for c in asm.coordinate_names]
        rigid = np.asarray(asm.rigid_body_vectors, dtype=float)[first, :]
        M = asm.M.toarray()  # the reduced mass matrix (diagonal unless a shaft has its own inertia)
        return cls(
            drivetrain=drivetrain,
            coordinate_names=tuple(asm.coordinate_names),
            T=T,
            M=np.asarray(M, dtype=float),
            K=T.T @ K_full @ T,
            C=T.T @ C_full @ T,
            meshes=tuple(links),
            rigid_body=rigid.reshape(n, -1),
        )

    @property
    def n(self) -> int:
        """Number of reduced coordinates (count)."""
        return self.M.shape[0]

    @property
    def K_mean(self) -> np.ndarray:
        """K + Σ k̄_j g_j g_jᵀ, N·m/rad: the drivetrain assembly's K."""
        out = self.K.copy()
        for m in self.meshes:
            out += m.mean_stiffness * np.outer(m.g, m.g)
        return out

    @property
    def C_mean(self) -> np.ndarray:
        """C + Σ c_m,j g_j g_jᵀ, N·m·s/rad: the drivetrain assembly's C."""
        out = self.C.copy()
        for m in self.meshes:
            out += m.damping * np.outer(m.g, m.g)
        return out

    def K_at(self, taus: Any) -> np.ndarray:
        """K + Σ k_j(τ_j) g_j g_jᵀ at the mesh phases ``taus`` (teeth in contact), N·m/rad.

        Parameters
        ----------
        taus : array_like
            (m,) mesh phase of each mesh, cycles (dimensionless).
        """
        t = np.atleast_1d(np.asarray(taus, dtype=float))
        if t.shape != (len(self.meshes),):
            raise ModelError(
                f"give one mesh phase per flexible mesh ({len(self.meshes)}), got shape {t.shape}",
                element=self.drivetrain.name,
                field="taus",
            )
        out = self.K.copy()
        for m, tau in zip(self.meshes, t, strict=True):
            out += m.stiffness(tau) * np.outer(m.g, m.g)
        return out

    def mesh_phases(self, q: np.ndarray) -> np.ndarray:
        """τ_j = z_a θ_a / (2π) of every mesh at coordinates ``q``, cycles.

        Parameters
        ----------
        q : ndarray
            (n,) reduced coordinates, rad.
        """
        return np.array([m.teeth * (m.phase_row @ q) / (2.0 * math.pi) for m in self.meshes])

    def disk(self, name: str) -> int:
        """Row of disk ``name`` in :attr:`T` (count): the disks in order, then the nodes inside divided
        shafts where the drivetrain has them.

        Parameters
        ----------
        name : str
            A disk of the drivetrain.
        """
        idx = _dof_index(self.drivetrain)
        if name not in idx:
            raise ModelError(
                f"{name!r} is not a disk of drivetrain {self.drivetrain.name!r}; disks: "
                f"{', '.join(self.drivetrain.disk_names)}",
                element=str(name),
                field="disk",
            )
        return idx[name]

    def input_vector(self, disk: str) -> np.ndarray:
        """Generalised force in q of a unit torque on ``disk``: Tᵀ e_disk, rad per unit coordinate.

        Parameters
        ----------
        disk : str
            The disk the torque acts on.
        """
        return self.T[self.disk(disk)].copy()

    def speed_ratios(self, reference: str) -> np.ndarray:
        """Rigid rotation q per unit rotation of the reference disk, rad/rad (signed).

        Parameters
        ----------
        reference : str
            The disk whose angle is 1.

        Raises
        ------
        mechdyn.errors.ModelError
            When the reference disk cannot turn freely (a grounded branch).
        """
        row = self.T[self.disk(reference)]
        amp = row @ self.rigid_body
        if amp.size == 0 or np.max(np.abs(amp)) == 0.0:
            raise ModelError(
                "this disk does not turn freely (its branch is grounded), so it has no rigid rotation; "
                "pick a disk of a free branch",
                element=reference,
                field="reference",
            )
        j = int(np.argmax(np.abs(amp)))
        return self.rigid_body[:, j] / amp[j]
