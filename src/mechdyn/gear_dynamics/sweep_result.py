"""The result of a speed sweep: mesh forces, dynamic factors, DTE, resonances, jumps over speed.

:class:`SpeedSweepResult` holds what :func:`.sweep.speed_sweep` computed at each speed (force extremes
and RMS, static force, DTE amplitude, convergence, Floquet spectral radius, closure, period multiple)
and derives from it the dynamic factor K_v, the resonances (the prominent peaks of the force
amplitude, :func:`_peaks`, refined by a parabola), where the train's modes meet the mesh orders
(:mod:`._resonance`), and with a down sweep the band of the jump (:meth:`SpeedSweepResult.hysteresis`),
its edges the folds of the branches followed by continuation (:attr:`SpeedSweepResult.branches`,
:class:`.continuation.ContinuedBranch`); with backlash also what ran at each speed and its CPU time;
its tables, notes and plots (:mod:`.sweep_plots`) say so in words.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.gear_dynamics._harmonics import truncation_warning
from mechdyn.gear_dynamics._resonance import crossings, iso_note
from mechdyn.gear_dynamics._stability import UNSTABLE_MARGIN
from mechdyn.gear_dynamics.continuation import ContinuedBranch
from mechdyn.results import Result, Table

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["SpeedSweepResult"]

#: A local maximum of a sweep's force amplitude is a resonance where its prominence (the height
#: above the higher of the two minima that separate it from higher ground, as
#: :func:`scipy.signal.find_peaks`) is at least this fraction of the peak's own height.
PEAK_PROMINENCE = 0.02
#: The up and down sweeps differ (a jump, hysteresis) where their force amplitudes differ by more than
#: this fraction of the larger.
HYSTERESIS_RTOL = 0.01


@dataclass(frozen=True, repr=False)
class SpeedSweepResult(Result):
    """Periodic steady state of a drivetrain over speed: mesh forces, dynamic factors, DTE, resonances.

    Attributes
    ----------
    speeds : ndarray
        (n_s,) reference speeds Ω, rad/s, ascending (the given ones and those added near peaks).
    reference : str
        The disk whose speed is Ω.
    mesh_names : tuple of str
    mesh_cycles : ndarray
        (J,) mesh cycles per radian of the reference disk (f_mesh = cycles · Ω), dimensionless.
    force_max, force_min, force_rms : ndarray
        (n_s, J) largest, smallest and root-mean-square mesh force over a period, N.
    static_force : ndarray
        (n_s, J) mesh force of the mean load at mean stiffness, N.
    dte_amplitude : ndarray
        (n_s, J) half peak-to-peak dynamic transmission error along the line of action, m.
    iso_dynamic_factor : ndarray
        (n_s, J) ISO 6336-1 K_v of the meshes whose gear data were given (NaN for the others),
        dimensionless.
    converged : ndarray
        (n_s,) False where Newton's method (backlash) did not converge.
    spectral_radius : ndarray
        (n_s,) largest Floquet multiplier modulus of the periodic solution (the teeth-in-contact
        system for harmonic balance; the orbit's own monodromy for shooting), dimensionless; NaN
        where not computed.
    method : str
    harmonics : int
        Harmonics of each mesh frequency (harmonic balance; 0 for shooting), count.
    harmonics_error : float
        The estimated largest relative error of K_v from the truncation, from doubling the harmonics
        at the lowest speed and at the speed of the largest K_v, dimensionless; NaN for shooting.
    notes : tuple of str
        What the user should know (the period chosen, a missing load): the result's warnings.
    assumptions : tuple of str
        What ISO 6336-1's K_v took where the gear data do not say (an accuracy grade's deviations, no
        tip relief): stated under the table, not warnings.
    closure : ndarray or None
        (n_s,) with backlash: how far each orbit misses itself after one period, the largest mismatch
        of the deflections and of the speeds relative to their largest values, dimensionless (NaN
        where Newton failed and without backlash).
    direction : str
        ``"up"`` or ``"down"``: the order in which the speeds were visited (continuation).
    down : SpeedSweepResult or None
        With ``direction="both"``: the down sweep over the same speeds (None otherwise).
    drive : str
        How the train was driven at each speed, in words (the motor free on its curve, a constant
        torque, or the reference disk held).
    iso_resonance_speed : ndarray or None
        (J,) the reference speed at which ISO 6336-1's pair alone resonates (its n_E1 over the
        pinion's speed ratio), rad/s; NaN for meshes without gear data.
    natural_frequencies_hz : ndarray or None
        The train's natural frequencies with the meshes at mean stiffness and the sweep's drive
        (no rigid-body mode), Hz: where the mesh orders meet them the computed K_v peaks
        (:meth:`train_resonances`).
    period_multiple : ndarray or None
        (n_s,) the periods T of each speed's orbit: 1, or 2 where the orbit of one period is unstable
        (past a flip) and the period-doubled orbit is the one shown (backlash).
    jump_speeds : tuple of float
        With backlash: where the branch the sweep followed ends and it jumps to another, rad/s: a fold
        (or a loss of stability) located by pseudo-arclength continuation to within
        :data:`.continuation.FOLD_RTOL` of the speed, or, where the continuation failed (the fallback,
        stated in :attr:`notes`), the end bisected to within :data:`.sweep.EDGE_RTOL`.
    branches : tuple of ContinuedBranch
        With backlash: the branches followed by pseudo-arclength continuation where the sweep's branch
        ended between two of its speeds (:class:`.continuation.ContinuedBranch`): each from the last
        orbit the sweep found to the fold, and through it along the unstable branch to the next fold,
        every point with its Floquet multipliers, Newton iterations and CPU time.
    solve_paths : tuple of str
        With backlash: per speed, what ran to find its orbit, in words (Newton from the orbit before,
        continuation to a fold and the jump, a point of a continuation, the bisection fallback).
    solve_cpu : ndarray or None
        With backlash: (n_s,) CPU time spent on each speed, s (a continuation's counted at the speed
        that started it, less its points kept as speeds, which carry their own).
    """

    speeds: np.ndarray
    reference: str
    mesh_names: tuple[str, ...]
    mesh_cycles: np.ndarray
    force_max: np.ndarray
    force_min: np.ndarray
    force_rms: np.ndarray
    static_force: np.ndarray
    dte_amplitude: np.ndarray
    iso_dynamic_factor: np.ndarray
    converged: np.ndarray
    spectral_radius: np.ndarray
    method: str
    harmonics: int
    notes: tuple[str, ...] = field(default=())
    assumptions: tuple[str, ...] = field(default=())
    harmonics_error: float = float("nan")
    closure: np.ndarray | None = None
    direction: str = "up"
    down: SpeedSweepResult | None = None
    drive: str = ""
    iso_resonance_speed: np.ndarray | None = None
    natural_frequencies_hz: np.ndarray | None = None
    period_multiple: np.ndarray | None = None
    jump_speeds: tuple[float, ...] = ()
    branches: tuple[ContinuedBranch, ...] = ()
    solve_paths: tuple[str, ...] = ()
    solve_cpu: np.ndarray | None = None

    @property
    def stable(self) -> np.ndarray:
        """(n_s,) False where the periodic solution is unstable (largest Floquet multiplier above 1:
        a parametric resonance, where the steady state shown is not reached); True where ρ ≤ 1 or not
        computed."""
        return ~(self.spectral_radius > 1.0 + UNSTABLE_MARGIN)

    @property
    def dynamic_factor(self) -> np.ndarray:
        """(n_s, J) K_v = max dynamic mesh force / static mesh force (in the static force's sense),
        dimensionless; NaN where there is no load."""
        sense = np.sign(self.static_force)
        extreme = np.where(sense >= 0, self.force_max, -self.force_min)
        loaded = np.abs(self.static_force) > 1e-9 * np.maximum(np.abs(self.force_max), np.abs(self.force_min))
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(loaded, extreme / np.abs(self.static_force), np.nan)

    @property
    def force_amplitude(self) -> np.ndarray:
        """(n_s, J) half peak-to-peak mesh force, N."""
        return 0.5 * (self.force_max - self.force_min)

    @property
    def mesh_frequencies_hz(self) -> np.ndarray:
        """(n_s, J) mesh frequencies, Hz."""
        return np.abs(self.mesh_cycles)[None, :] * self.speeds[:, None]

    def resonances(self) -> dict[str, list[float]]:
        """Per mesh, the speeds (rad/s) of the peaks of its force amplitude, each refined by a parabola
        through the peak sample and its neighbours: the local maxima whose prominence is at least
        :data:`PEAK_PROMINENCE` of their height (so that ripples are not listed)."""
        out: dict[str, list[float]] = {}
        s = self.speeds
        for j, name in enumerate(self.mesh_names):
            y = self.force_amplitude[:, j]
            peaks = []
            for i in _peaks(y):
                x0, x1, x2 = s[i - 1 : i + 2]
                y0, y1, y2 = y[i - 1 : i + 2]
                den = (x0 - x1) * (x0 - x2) * (x1 - x2)
                a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / den
                b = (x2**2 * (y0 - y1) + x1**2 * (y2 - y0) + x0**2 * (y1 - y2)) / den
                peaks.append(float(-b / (2 * a)) if a < 0 and x0 < -b / (2 * a) < x2 else float(x1))
            out[name] = peaks
        return out

    def train_resonances(self) -> dict[str, list[tuple[int, int, float, float]]]:
        """Per mesh, where an order (1, 2) of its frequency meets a natural frequency of the train
        within the swept range: (mode number, order, frequency in Hz, reference speed in rad/s)
        (:func:`mechdyn.gear_dynamics._resonance.crossings`); empty without natural frequencies."""
        if self.natural_frequencies_hz is None:
            return {n: [] for n in self.mesh_names}
        low, high = float(self.speeds.min()), float(self.speeds.max())
        return {
            n: crossings(self.natural_frequencies_hz, self.mesh_cycles[j], low, high)
            for j, n in enumerate(self.mesh_names)
        }

    @property
    def fold_speeds(self) -> tuple[float, ...]:
        """The folds located by continuation in this sweep and its down sweep, rad/s, ascending (the
        same fold met by both counted once, :data:`.continuation.KNOWN_RTOL`)."""
        from mechdyn.gear_dynamics.continuation import KNOWN_RTOL

        found: list[float] = []
        for sweep in (self, self.down):
            for branch in sweep.branches if sweep is not None else ():
                for f in branch.folds:
                    if not any(abs(f - g) <= KNOWN_RTOL * f for g in found):
                        found.append(float(f))
        return tuple(sorted(found))

    def hysteresis(self) -> dict[str, tuple[float, float] | None]:
        """With a down sweep (``direction="both"``): per mesh, the lowest and highest speed (rad/s) at
        which the up and the down sweep, both converged and stable, differ in force amplitude by more than
        :data:`HYSTERESIS_RTOL` of the larger (the band of the jump phenomenon), or None where they
        agree; empty without a down sweep. Where the sweeps jumped at the band's ends, the edges are
        the speeds of those jumps: the folds located by continuation (:attr:`jump_speeds`), not the
        grid's speeds."""
        if self.down is None:
            return {}
        common, iu, idn = np.intersect1d(self.speeds, self.down.speeds, return_indices=True)
        # an unstable orbit is no branch a machine runs on: it never counts in the band
        ok = self.converged[iu] & self.down.converged[idn] & self.stable[iu] & self.down.stable[idn]
        out: dict[str, tuple[float, float] | None] = {}
        for j, name in enumerate(self.mesh_names):
            a, b = self.force_amplitude[iu, j], self.down.force_amplitude[idn, j]
            differ = ok & (np.abs(a - b) > HYSTERESIS_RTOL * np.maximum(np.abs(a), np.abs(b)))
            if not differ.any():
                out[name] = None
                continue
            low, high = float(common[differ].min()), float(common[differ].max())
            # the edges where the branches end, located by bisection, where the sweeps jumped there
            down_jumps = [v for v in self.down.jump_speeds if v <= low]
            up_jumps = [v for v in self.jump_speeds if v >= high]
            out[name] = (max(down_jumps) if down_jumps else low, min(up_jumps) if up_jumps else high)
        return out

    def _doubling_notes(self) -> list[str]:
        """The speeds where a period-doubled orbit is shown, in words (rpm)."""
        from mechdyn.units import convert

        out = []
        for sweep in (self, self.down):
            if sweep is None or sweep.period_multiple is None or not (sweep.period_multiple == 2).any():
                continue
            doubled = sweep.speeds[sweep.period_multiple == 2]
            low, high = (float(convert(v, "rad/s", "rpm")) for v in (doubled.min(), doubled.max()))
            out.append(
                f"Swept {sweep.direction}, the orbit of one mesh period is unstable at {doubled.size} speeds "
                f"from {low:.4g} to {high:.4g} rpm (a flip: a Floquet multiplier below −1): there the "
                "period-doubled orbit, of two mesh periods, is shown."
            )
        return out

    def _hysteresis_notes(self) -> list[str]:
        """The jump in words, where a down sweep was made (rpm)."""
        if self.down is None:
            return []
        from mechdyn.units import convert

        out = []
        for name, band in self.hysteresis().items():
            if band is None:
                out.append(f"Swept up and down, {name!r} has one branch (no jump).")
            else:
                low, high = (float(convert(v, "rad/s", "rpm")) for v in band)
                out.append(
                    f"Swept up and down, {name!r} has two branches from {low:.4g} to {high:.4g} rpm (the "
                    "jump): the table is the up sweep's."
                )
        return out

    def summary(self) -> dict[str, Any]:
        """Speed range (rad/s), method, and per mesh the largest K_v and where (rad/s), the static
        force (N), the largest DTE amplitude (m) and the resonance speeds (rad/s); with a down sweep
        also the speeds (rad/s) between which the up and down sweeps differ."""
        kv = self.dynamic_factor
        res = self.resonances()
        meshes = {}
        for j, name in enumerate(self.mesh_names):
            finite = np.isfinite(kv[:, j])
            i = int(np.nanargmax(np.where(finite, kv[:, j], -np.inf))) if finite.any() else 0
            meshes[name] = {
                "dynamic_factor_max_ratio": float(kv[i, j]) if finite.any() else float("nan"),
                "dynamic_factor_max_at_rad_s": float(self.speeds[i]),
                "static_force_N": float(self.static_force[0, j]),
                "force_max_N": float(self.force_max[:, j].max()),
                "dte_amplitude_max_m": float(self.dte_amplitude[:, j].max()),
                "resonance_speeds_rad_s": res[name],
            }
            if self.down is not None:
                band = self.hysteresis()[name]
                meshes[name]["hysteresis_speeds_rad_s"] = list(band) if band else []
            if self.branches or (self.down is not None and self.down.branches):
                meshes[name]["fold_speeds_rad_s"] = list(self.fold_speeds)
            meshes[name]["train_resonance_speeds_rad_s"] = [c[3] for c in self.train_resonances()[name]]
            if np.isfinite(self.iso_dynamic_factor[:, j]).any():
                meshes[name]["iso_dynamic_factor_max_ratio"] = float(np.nanmax(self.iso_dynamic_factor[:, j]))
                if self.iso_resonance_speed is not None:
                    meshes[name]["iso_resonance_speed_rad_s"] = float(self.iso_resonance_speed[j])
        return {
            "reference": self.reference,
            "drive": self.drive,
            "method": self.method,
            "harmonics": int(self.harmonics),
            "harmonics_error_ratio": float(self.harmonics_error),
            "speed_min_rad_s": float(self.speeds.min()),
            "speed_max_rad_s": float(self.speeds.max()),
            "points": int(self.speeds.size),
            "unstable_points": int((~self.stable).sum()),
            "period_doubled_points": (
                int((self.period_multiple == 2).sum()) if self.period_multiple is not None else 0
            ),
            "meshes": meshes,
        }

    def to_frame(self) -> pd.DataFrame:
        """One row per speed: speed (rad/s, rpm) and per mesh its frequency (Hz), force max, min, RMS
        and static (N), K_v, ISO K_v and DTE amplitude (m)."""
        import pandas as pd

        from mechdyn.units import convert

        cols: dict[str, Any] = {
            "speed_rad_s": self.speeds,
            "speed_rpm": np.asarray(convert(self.speeds, "rad/s", "rpm")),
        }
        kv = self.dynamic_factor
        for j, n in enumerate(self.mesh_names):
            cols[f"{n}_mesh_frequency_hz"] = self.mesh_frequencies_hz[:, j]
            cols[f"{n}_force_max_N"] = self.force_max[:, j]
            cols[f"{n}_force_min_N"] = self.force_min[:, j]
            cols[f"{n}_force_rms_N"] = self.force_rms[:, j]
            cols[f"{n}_static_force_N"] = self.static_force[:, j]
            cols[f"{n}_dynamic_factor_ratio"] = kv[:, j]
            cols[f"{n}_iso_dynamic_factor_ratio"] = self.iso_dynamic_factor[:, j]
            cols[f"{n}_dte_amplitude_m"] = self.dte_amplitude[:, j]
        cols["converged"] = self.converged
        cols["spectral_radius_ratio"] = self.spectral_radius
        cols["stable"] = self.stable
        if self.solve_cpu is not None:
            cols["solve_cpu_s"] = self.solve_cpu
        return pd.DataFrame(cols)

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        """The columns of :meth:`to_frame`, and of each continued branch's table prefixed
        ``branch_K_`` (K from 0; the down sweep's after the up sweep's)."""
        from mechdyn.results import frame_arrays

        out = frame_arrays(self.to_frame())
        branches = self.branches + (self.down.branches if self.down is not None else ())
        for k, branch in enumerate(branches):
            for name, value in frame_arrays(branch.to_frame()).items():
                out[f"branch_{k}_{name}"] = value
        return out

    def tables(self, **display_units: str) -> list[Table]:
        """Per mesh: largest K_v and where (rpm), static force, largest DTE amplitude, resonances (rpm);
        then where the train's modes meet the mesh orders, beside ISO's pair resonance."""
        from mechdyn.units import convert, readable

        force_unit = display_units.get("force_unit")
        rows = []
        s = self.summary()["meshes"]
        for name, m in s.items():
            f = m["static_force_N"]
            f_shown = (float(convert(f, "N", force_unit)), force_unit) if force_unit else readable(f, "N")
            dte, dte_unit = readable(m["dte_amplitude_max_m"], "m")
            rpm = [f"{float(convert(v, 'rad/s', 'rpm')):.5g}" for v in m["resonance_speeds_rad_s"]]
            rows.append(
                [
                    name,
                    m["dynamic_factor_max_ratio"],
                    float(convert(m["dynamic_factor_max_at_rad_s"], "rad/s", "rpm")),
                    m.get("iso_dynamic_factor_max_ratio"),
                    f"{f_shown[0]:.4g} {f_shown[1]}",
                    f"{dte:.4g} {dte_unit}",
                    ", ".join(rpm) or "none",
                ]
            )
        return [
            Table(
                f"speed sweep of disk {self.reference!r}: dynamic mesh forces",
                [
                    "mesh",
                    "K_v max",
                    "at [rpm]",
                    "ISO K_v max (pair alone)",
                    "static force",
                    "DTE amplitude max",
                    "resonances [rpm]",
                ],
                rows,
                note=" ".join(
                    (
                        f"Computed by {self.method}.",
                        *((f"Drive: {self.drive}.",) if self.drive else ()),
                        *self._hysteresis_notes(),
                        *self._doubling_notes(),
                        *(n.rstrip(".") + "." for n in self.notes + self.assumptions),
                    )
                ),
            ),
            *self._resonance_table(),
            *self._continuation_tables(),
        ]

    def _continuation_tables(self) -> list[Table]:
        """With backlash: how each speed's orbit was found and its CPU time (grouped), and each branch
        followed by continuation: from where, its folds, its points and their cost."""
        from mechdyn.units import convert

        def rpm(v: float) -> float:
            return float(convert(v, "rad/s", "rpm"))

        sweeps = [w for w in (self, self.down) if w is not None and w.solve_cpu is not None]
        if self.down is not None and self.down.solve_cpu is self.solve_cpu:
            sweeps = sweeps[:1]
        if not sweeps:
            return []
        rows: list[list[Any]] = []
        for w in sweeps:
            assert w.solve_cpu is not None
            for path in dict.fromkeys(w.solve_paths):
                pick = np.array([p == path for p in w.solve_paths], bool)
                cpu = w.solve_cpu[pick]
                rows.append(
                    [w.direction, path, int(pick.sum()), float(np.nanmean(cpu)), float(np.nansum(cpu))]
                )
        tables = []
        cpu_all = np.concatenate([np.asarray(w.solve_cpu, float) for w in sweeps])
        tables.append(
            Table(
                "how each speed's periodic orbit was found (backlash), and its CPU time",
                ["swept", "what ran", "speeds", "CPU per speed [s]", "CPU in all [s]"],
                rows,
                note=(
                    f"{np.nansum(cpu_all):.3g} s of CPU over {cpu_all.size} speeds: "
                    f"{np.nansum(cpu_all) / max(cpu_all.size, 1):.3g} s a speed."
                ),
            )
        )
        branch_rows: list[list[Any]] = []
        for w in sweeps:
            for b in w.branches:
                unstable = int((~b.stable & np.array([k == "point" for k in b.kinds])).sum())
                branch_rows.append(
                    [
                        w.direction,
                        rpm(float(b.speeds[0])),
                        ", ".join(f"{rpm(f):.6g}" for f in b.folds) or "none",
                        int(b.speeds.size),
                        unstable,
                        float(b.cpu_seconds.sum() / max(b.speeds.size, 1)),
                        float(b.cpu_seconds.sum()),
                        b.end,
                    ]
                )
        if branch_rows:
            tables.append(
                Table(
                    "branches followed through their folds by pseudo-arclength continuation",
                    [
                        "swept",
                        "from [rpm]",
                        "folds [rpm]",
                        "points",
                        "unstable points",
                        "CPU per point [s]",
                        "CPU in all [s]",
                        "stopped",
                    ],
                    branch_rows,
                    note=(
                        "Where the sweep's branch ended between two speeds it was followed from the last "
                        "orbit by pseudo-arclength continuation: the folds (a real Floquet multiplier "
                        "through +1) are the edges of the jump band, not the grid's speeds; the branch "
                        "between them is unstable, drawn dashed and never counted in the band."
                    ),
                )
            )
        return tables

    def _resonance_table(self) -> list[Table]:
        """The train's resonances within the range per mesh, beside ISO's pair resonance."""
        from mechdyn.units import convert

        rows: list[list[Any]] = []
        with_iso = []
        for j, (name, found) in enumerate(self.train_resonances().items()):
            iso = self.iso_resonance_speed[j] if self.iso_resonance_speed is not None else np.nan
            iso_rpm = float(convert(iso, "rad/s", "rpm")) if np.isfinite(iso) else None
            if iso_rpm is not None:
                with_iso.append(name)
            for mode, order, f, speed in found or [(0, 0, np.nan, np.nan)]:
                rows.append(
                    [
                        name,
                        f"{mode}" if mode else "none in range",
                        f if mode else None,
                        f"{order} × mesh" if mode else None,
                        float(convert(speed, "rad/s", "rpm")) if mode else None,
                        iso_rpm,
                    ]
                )
        if not rows:
            return []
        return [
            Table(
                "where the train's modes meet the mesh frequency, and ISO 6336-1's pair alone",
                [
                    "mesh",
                    "train mode",
                    "frequency [Hz]",
                    "excited by",
                    "at [rpm]",
                    "ISO pair resonance [rpm]",
                ],
                rows,
                note=iso_note(with_iso),
            )
        ]

    def plots(self, **display_units: str) -> dict[str, Any]:
        """``speed_sweep.png``: K_v (and ISO K_v) over speed per mesh; ``speed_sweep_dte.png``: DTE."""
        from mechdyn.gear_dynamics.sweep_plots import plot_speed_sweep, plot_sweep_dte

        return {
            "speed_sweep.png": lambda: plot_speed_sweep(self, **display_units),
            "speed_sweep_dte.png": lambda: plot_sweep_dte(self, **display_units),
        }

    @property
    def warnings(self) -> tuple[str, ...]:
        """The period chosen, missing loads, speeds where Newton did not converge."""
        out = list(self.notes)
        for sweep in (self, self.down):
            if sweep is not None and not sweep.converged.all():
                bad = sweep.speeds[~sweep.converged]
                out.append(
                    f"Newton's method did not converge at {bad.size} speeds (from {bad.min():.4g} rad/s)"
                    + (" sweeping down" if sweep is self.down else "")
                )
        out.extend(truncation_warning(self.harmonics, self.harmonics_error))
        if not self.stable.all():
            bad = self.speeds[~self.stable]
            out.append(
                f"the periodic solution is unstable (parametric resonance, Floquet ρ > 1) at {bad.size} "
                f"speeds between {bad.min():.4g} and {bad.max():.4g} rad/s: there the forces shown are not "
                "reached"
            )
        return tuple(out)


def _peaks(y: np.ndarray) -> np.ndarray:
    """Indices of the interior local maxima of ``y`` whose prominence (:func:`scipy.signal.find_peaks`)
    is at least :data:`PEAK_PROMINENCE` of their own value, and above 1e-9 of the largest value."""
    from scipy.signal import find_peaks

    y = np.asarray(y, float)
    finite = np.isfinite(y)
    if y.size < 3 or not finite.any():
        return np.zeros(0, int)
    y = np.where(finite, y, y[finite].min())  # a speed where Newton failed is no peak
    idx, props = find_peaks(y, prominence=0.0)
    scale = np.abs(y).max()
    keep = (props["prominences"] >= PEAK_PROMINENCE * np.abs(y[idx])) & (np.abs(y[idx]) > 1e-9 * scale)
    return idx[keep] if scale > 0 else idx[:0]
