"""Floquet multipliers of a geared drivetrain with time-varying mesh stiffness: parametric stability.

The vibration about the nominal rotation at a constant speed obeys the linear time-periodic system of
:mod:`.periodic` (teeth in contact, no backlash),

    M ẍ + C ẋ + K(t) x = F(t),  K(t) = K_s + Σ_j k_j(τ_j(t)) g_j g_jᵀ,

whose stability follows from the monodromy matrix Φ(T), the state-transition matrix over one period
T (Floquet's theorem; Nayfeh & Mook, *Nonlinear Oscillations*, 1979, §5.2): the free vibration grows
where the spectral radius ρ, the largest modulus of its eigenvalues μ (the Floquet multipliers),
exceeds 1, at the rate ln ρ / T. Φ(T) comes from :mod:`.propagators` (the Magnus product or
solve_ivp); the rigid-body multiplier is removed by the model's boundary (:mod:`.periodic`).

:func:`floquet` gives the multipliers over speed (:class:`FloquetResult`), :func:`stability_chart`
the spectral radius over speed and one mesh's stiffness variation (:class:`StabilityChart`, an
Ince–Strutt chart); the steady-state solvers judge the orbits they find by the same margin and
multipliers (:mod:`._stability`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.checks import check_array, check_count
from mechdyn.errors import ModelError

# UNSTABLE_MARGIN and _spectral, and PeriodPlan, interpolate, segments and product_harmonics, were defined
# here before the stability margin, the periodic model, its propagators and harmonic balance had modules
# of their own: importable from here still
from mechdyn.gear_dynamics._stability import UNSTABLE_MARGIN as UNSTABLE_MARGIN
from mechdyn.gear_dynamics._stability import _spectral as _spectral
from mechdyn.gear_dynamics.harmonic_balance import product_harmonics as product_harmonics
from mechdyn.gear_dynamics.periodic import (
    Boundary,
    _natural_frequencies,
    _speeds,
    linear_periodic,
    period_plan,
)
from mechdyn.gear_dynamics.periodic import PeriodPlan as PeriodPlan
from mechdyn.gear_dynamics.periodic import interpolate as interpolate
from mechdyn.gear_dynamics.propagators import Integrator, _check_method, _monodromy, monodromy
from mechdyn.gear_dynamics.propagators import segments as segments
from mechdyn.results import Result, Table

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["FloquetResult", "StabilityChart", "floquet", "monodromy", "stability_chart"]


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
        How Φ(T) is computed (:func:`.propagators.monodromy`).
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
    other meshes keep theirs. Φ(T) by the Magnus product (:func:`.propagators.monodromy`).

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
        How the rigid-body motion is removed (see :func:`.periodic.linear_periodic`).
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
