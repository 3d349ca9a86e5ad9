"""The result of a time simulation of a geared drivetrain (:func:`mechdyn.gear_dynamics.simulate`)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.results import Result, Table, summary_table

if TYPE_CHECKING:
    import pandas as pd

    from mechdyn.gear_dynamics.system import GearSystem

__all__ = ["ContactLoss", "SimulationResult"]

#: Static mesh forces below this fraction of the peak define no dynamic factor (a free vibration).
STATIC_SHARE = 1e-6


@dataclass(frozen=True)
class ContactLoss:
    """One interval in which a mesh's loaded flanks are apart (the flanks the inputs press together at
    the start of the run, else at its end, by the sign of the quasi-static mesh force: the drive side,
    or the back side of a mesh whose driving gear turns the negative way or under a reversed load).

    Attributes
    ----------
    mesh : str
        The mesh.
    start : float
        When the loaded flanks parted, s.
    end : float or None
        When it closed again, s; None if still open at the end of the run.
    back_impacts : int
        Impacts on the opposite flanks in the interval (count): back-side impacts of a drive-side load.
    """

    mesh: str
    start: float
    end: float | None
    back_impacts: int

    @property
    def length(self) -> float | None:
        """end − start, s (None while open)."""
        return None if self.end is None else self.end - self.start


@dataclass(frozen=True, repr=False, eq=False)
class SimulationResult(Result):
    """Time histories of a geared drivetrain.

    Attributes
    ----------
    system : GearSystem
        The simulated system.
    time : ndarray
        (N,) sample times, s.
    angles, speeds : ndarray
        (n_dofs, N) disk angles, rad, and speeds, rad/s (global sense), rows as :attr:`disk_names`.
    mesh_forces : ndarray
        (n_meshes, N) mesh forces along the line of action, N (positive: drive-side contact).
    dte : ndarray
        (n_meshes, N) dynamic transmission error δ − e along the line of action, m.
    element_torques : dict of str → ndarray
        Torque of every shaft and grounded spring over time, N·m (the elements' load rows).
    contact_modes : ndarray
        (n_meshes, N) 0 drive-side contact, 1 in the backlash, 2 back-side contact.
    contact_losses : tuple of ContactLoss
        The intervals of lost drive-side contact, per mesh in time order.
    energy : dict of str → ndarray
        ``kinetic``, ``strain`` (J) and, integrated from t = 0, ``input_work``, ``dissipated`` and
        ``parametric_work`` (the work of the varying stiffness and of the transmission error), J.
    static_mesh_forces : ndarray or None
        (n_meshes,) quasi-static mesh forces under the inputs at the end of the run, N; None without
        inputs.
    method : str
        The integrator.
    stats : dict
        ``wall_s`` (s), ``segments``, ``rhs_calls``, ``contact_changes`` (counts).
    """

    system: GearSystem
    time: np.ndarray
    angles: np.ndarray
    speeds: np.ndarray
    mesh_forces: np.ndarray
    dte: np.ndarray
    element_torques: dict[str, np.ndarray]
    contact_modes: np.ndarray
    contact_losses: tuple[ContactLoss, ...]
    energy: dict[str, np.ndarray]
    static_mesh_forces: np.ndarray | None
    method: str
    stats: dict[str, Any]

    @property
    def disk_names(self) -> tuple[str, ...]:
        """The rows of :attr:`angles` and :attr:`speeds`: the disks in the drivetrain's order, then any
        nodes inside divided shafts."""
        from mechdyn.gear_dynamics.system import _dof_names

        return _dof_names(self.system.drivetrain)

    @property
    def mesh_names(self) -> tuple[str, ...]:
        """The flexible meshes, in the system's order."""
        return tuple(m.name for m in self.system.meshes)

    def speed(self, disk: str) -> np.ndarray:
        """Speed of ``disk`` over time, rad/s.

        Parameters
        ----------
        disk : str
            A disk of the drivetrain.
        """
        return self.speeds[self.system.disk(disk)]

    def mesh_force(self, mesh: str) -> np.ndarray:
        """Force of ``mesh`` along its line of action over time, N.

        Parameters
        ----------
        mesh : str
            A flexible mesh of the drivetrain.
        """
        return self.mesh_forces[self._mesh(mesh)]

    def _mesh(self, mesh: str) -> int:
        if mesh not in self.mesh_names:
            from mechdyn.errors import ModelError

            raise ModelError(
                f"{mesh!r} is not a flexible mesh; flexible meshes: {', '.join(self.mesh_names) or 'none'}",
                element=str(mesh),
                field="mesh",
            )
        return self.mesh_names.index(mesh)

    @property
    def energy_balance(self) -> np.ndarray:
        """(N,) kinetic + strain + dissipated − input work − parametric work, J: constant in exact
        arithmetic (the residual of the integration, once its initial value is taken off)."""
        e = self.energy
        return e["kinetic"] + e["strain"] + e["dissipated"] - e["input_work"] - e["parametric_work"]

    def _rms(self, values: np.ndarray) -> float:
        t = self.time
        if t.size < 2 or t[-1] == t[0]:
            return float(np.sqrt(np.mean(values**2)))
        return float(np.sqrt(np.trapezoid(values**2, t) / (t[-1] - t[0])))

    def dynamic_factors(self) -> dict[str, float]:
        """Peak mesh force over the static mesh force, per mesh with a static load (dimensionless ratio).

        The static force is that of the quasi-static deflection under the inputs at the end of the run
        (:func:`mechdyn.gear_dynamics.static_deflection`, ISO 6336-1's K_v in spirit: dynamic over
        static tooth load).
        """
        if self.static_mesh_forces is None:
            return {}
        out = {}
        for j, name in enumerate(self.mesh_names):
            f = self.mesh_forces[j]
            static = float(self.static_mesh_forces[j])
            peak = float(np.max(np.abs(f))) if f.size else 0.0
            if abs(static) > STATIC_SHARE * max(peak, np.finfo(float).tiny):
                out[name] = float(np.max(f * np.sign(static)) / abs(static))
        return out

    def summary(self) -> dict[str, Any]:
        """Duration, speeds, mesh force peaks and RMS, dynamic factors, contact losses, energy residual."""
        out: dict[str, Any] = {
            "duration_s": float(self.time[-1] - self.time[0]),
            "samples": int(self.time.size),
            "method": self.method,
            "max_speed_rad_s": {
                d: float(np.max(np.abs(self.speeds[i]))) for i, d in enumerate(self.disk_names)
            },
            "final_speed_rad_s": {d: float(self.speeds[i, -1]) for i, d in enumerate(self.disk_names)},
        }
        if self.mesh_names:
            out["mesh_force_peak_N"] = {
                n: float(np.max(np.abs(self.mesh_forces[j]))) for j, n in enumerate(self.mesh_names)
            }
            out["mesh_force_rms_N"] = {
                n: self._rms(self.mesh_forces[j]) for j, n in enumerate(self.mesh_names)
            }
            out["dte_peak_to_peak_m"] = {n: float(np.ptp(self.dte[j])) for j, n in enumerate(self.mesh_names)}
            if self.static_mesh_forces is not None:
                out["static_mesh_force_N"] = {
                    n: float(self.static_mesh_forces[j]) for j, n in enumerate(self.mesh_names)
                }
            factors = self.dynamic_factors()
            if factors:
                out["dynamic_factor"] = factors
            out["contact_losses"] = {
                n: sum(1 for c in self.contact_losses if c.mesh == n) for n in self.mesh_names
            }
            first: dict[str, float] = {}
            for c in self.contact_losses:
                first.setdefault(c.mesh, c.start)
            if first:
                out["first_contact_loss_s"] = first
        balance = self.energy_balance
        out["energy_residual_J"] = float(np.max(np.abs(balance - balance[0])))
        out["input_work_J"] = float(self.energy["input_work"][-1])
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row per sample: time (s); per disk its angle (rad) and speed (rad/s); per mesh its force
        (N), dynamic transmission error (m) and contact mode; per shaft its torque (N·m)."""
        import pandas as pd

        cols: dict[str, np.ndarray] = {"time_s": self.time}
        for i, d in enumerate(self.disk_names):
            cols[f"{d}_angle_rad"] = self.angles[i]
            cols[f"{d}_speed_rad_s"] = self.speeds[i]
        for j, n in enumerate(self.mesh_names):
            cols[f"{n}_force_N"] = self.mesh_forces[j]
            cols[f"{n}_dte_m"] = self.dte[j]
            cols[f"{n}_contact_mode"] = self.contact_modes[j]
        for n, v in self.element_torques.items():
            cols[f"{n}_torque_Nm"] = v
        return pd.DataFrame(cols)

    def tables(self, **display_units: str) -> list[Table]:
        """The summary's scalars; each disk's largest and final speed; per mesh its force peak, RMS, static
        force and dynamic factor; the contact-loss intervals.

        Parameters
        ----------
        **display_units : str
            ``force_unit``, ``length_unit``: see :func:`mechdyn.results.summary_table`.
        """
        from mechdyn.units import convert, readable

        summary = self.summary()
        tables = [summary_table(summary, display_units=display_units)]
        speeds = [
            [
                disk,
                float(convert(summary["max_speed_rad_s"][disk], "rad/s", "rpm")),
                float(convert(summary["final_speed_rad_s"][disk], "rad/s", "rpm")),
            ]
            for disk in summary["final_speed_rad_s"]
        ]
        tables.append(
            Table(
                "speeds",
                ["disk", "top speed [rpm]", "at the end [rpm]"],
                speeds,
                note="The top speed is a magnitude; the speed at the end is signed in the drivetrain's one "
                "sense of rotation (a disk beyond an external mesh turns the negative way).",
            )
        )
        if self.mesh_names:
            s = self.summary()
            force_unit = display_units.get("force_unit", "N")
            rows = []
            for n in self.mesh_names:
                static = s.get("static_mesh_force_N", {}).get(n)
                rows.append(
                    [
                        n,
                        float(convert(s["mesh_force_peak_N"][n], "N", force_unit)),
                        float(convert(s["mesh_force_rms_N"][n], "N", force_unit)),
                        None if static is None else float(convert(static, "N", force_unit)),
                        s.get("dynamic_factor", {}).get(n),
                        readable(s["dte_peak_to_peak_m"][n], "m")[0],
                        s["contact_losses"][n],
                    ]
                )
            unit = readable(max(s["dte_peak_to_peak_m"].values()), "m")[1]
            tables.append(
                Table(
                    "meshes",
                    [
                        "mesh",
                        f"peak force [{force_unit}]",
                        f"RMS force [{force_unit}]",
                        f"static force [{force_unit}]",
                        "dynamic factor",
                        f"DTE peak-to-peak [{unit}]",
                        "contact losses",
                    ],
                    rows,
                    note="Dynamic factor: peak mesh force over the quasi-static force under the inputs "
                    "at the end of the run.",
                )
            )
        if self.contact_losses:
            rows = []
            for n in dict.fromkeys(c.mesh for c in self.contact_losses):
                lost = [c for c in self.contact_losses if c.mesh == n]
                ends = [c.end if c.end is not None else float(self.time[-1]) for c in lost]
                rows.append(
                    [
                        n,
                        len(lost),
                        float(convert(sum(e - c.start for c, e in zip(lost, ends, strict=True)), "s", "ms")),
                        float(convert(max(e - c.start for c, e in zip(lost, ends, strict=True)), "s", "ms")),
                        float(convert(lost[0].start, "s", "ms")),
                        float(convert(ends[-1], "s", "ms")),
                        sum(c.back_impacts for c in lost),
                    ]
                )
            tables.append(
                Table(
                    "contact losses",
                    [
                        "mesh",
                        "intervals",
                        "apart in all [ms]",
                        "longest [ms]",
                        "first from [ms]",
                        "last until [ms]",
                        "back-side impacts",
                    ],
                    rows,
                    note="Every interval is in the result's contact_losses and its to_frame(); a last "
                    "interval still open when the run ended counts to the end.",
                )
            )
        return tables

    def plots(self, **display_units: str) -> dict[str, Callable[[], Any]]:
        """``speeds.png``, and with flexible meshes ``mesh_forces.png`` and ``dte.png``.

        Parameters
        ----------
        **display_units : str
            ``force_unit`` (e.g. ``"kN"``) and ``length_unit`` (e.g. ``"um"``).
        """
        from mechdyn.gear_dynamics import plots as p

        out: dict[str, Callable[[], Any]] = {"speeds.png": lambda: p.plot_speeds(self)}
        if self.mesh_names:
            force_unit = display_units.get("force_unit")
            length_unit = display_units.get("length_unit")
            out["mesh_forces.png"] = lambda: p.plot_mesh_forces(self, unit=force_unit)
            out["dte.png"] = lambda: p.plot_dte(self, unit=length_unit)
        return out

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        """The time histories with their units, and the energy terms (J)."""
        out = super().arrays()
        for k, v in self.energy.items():
            out[f"energy_{k}_J"] = (v, "J")
        return out
