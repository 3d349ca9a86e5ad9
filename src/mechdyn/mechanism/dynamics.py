"""Inverse dynamics: joint reactions, driving torque, inertia forces, shaking force and moment.

Newton–Euler equations of every body in body coordinates, M q̈ + Φ_qᵀ λ = Q (Nikravesh 1988,
ch. 6), solved for the Lagrange multipliers λ at every crank angle; the mechanism is kinematically
determined, so Φ_qᵀ is square. The load that joint k puts on one of its bodies b is −J_bᵀ λ_k
(force and moment about b's centre of mass); the frame's share, −J_frameᵀ λ, is the shaking force and
moment (the motor's reaction −T included). With no external load the shaking force is −Σ mᵢ a_Gᵢ.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from mechdyn.mechanism.kinematics import KinematicsResult, angle_order, kinematics, output_position
from mechdyn.mechanism.linalg import solve_with_det
from mechdyn.mechanism.model import GROUND, GearJoint, Mechanism, _point
from mechdyn.mechanism.motion import mechanism_dyads, motion_columns, rocker_link
from mechdyn.results import Result, Table

if TYPE_CHECKING:
    from pathlib import Path

    import pandas as pd

__all__ = ["DynamicsResult", "applied_forces", "inverse_dynamics"]


# the summary's keys of a press's rating (tonnage, energy, reverse load): a table of their own
_RATING = (
    "rated_",
    "tonnage_",
    "process_",
    "crank_angle_at_process",
    "breakthrough_",
    "press_stiffness",
    "frame_",
    "reverse_",
)


@dataclass(frozen=True, repr=False)  # the short repr of Result
class DynamicsResult(Result):
    """Inverse dynamics over one crank revolution (all arrays over the N crank angles).

    Attributes
    ----------
    kinematics : KinematicsResult
    multipliers : ndarray
        (N, m) λ, one per constraint equation.
    applied : ndarray
        (N, n) generalised applied forces Q (gravity and process forces).
    load_jacobian : (ndarray, ndarray), optional
        The constraint Jacobians with gear flanks chosen by the load (rows per constraint, columns per
        coordinate: dimensionless for angles, m for lengths).
    trace : tuple of str
        Drawing points whose motion the table gives and whose paths (coupler curves) the plots draw.
    field_velocity : (float, float), optional
        Velocity of the field under the machine, m/s (the trajectory plot adds it to the paths).
    rated_torque : float, optional
        A press's rated crank torque, N·m: with a slide output, the tonnage curve, the energy per
        stroke and the capacity check (:mod:`mechdyn.mechanism.tonnage`) join the summary, the tables,
        the columns and the plots (see :meth:`with_rating`).
    rated_force : float, optional
        The press's rated force, N: the rated point (the distance before BDC from which it is
        available) is reported with it.
    frame : Frame, optional
        The press's stiffness (N/m), reverse capacity and damping ratio (dimensionless)
        (:class:`mechdyn.mechanism.tonnage.Frame`): the reverse load at break-through is reported.
    """

    kinematics: KinematicsResult
    multipliers: np.ndarray
    applied: np.ndarray
    load_jacobian: tuple[np.ndarray, np.ndarray] | None = None  # with gear flanks chosen by the load
    trace: tuple[str, ...] = ()
    field_velocity: tuple[float, float] | None = None
    rated_torque: float | None = None
    rated_force: float | None = None
    frame: Any = None

    def with_rating(self, rated_torque: Any, rated_force: Any = None, frame: Any = None) -> DynamicsResult:
        """The same cycle with a press's rating, for the tonnage curve and the capacity check.

        Parameters
        ----------
        rated_torque : float or quantity
            The rated crank torque, N·m (e.g. ``"1600 kN*m"``), positive.
        rated_force : float or quantity, optional
            The rated press force, N (e.g. ``"10 MN"``), positive.
        frame : mechdyn.mechanism.tonnage.Frame, optional
            The press's stiffness and reverse-load capacity: the reverse load at break-through is
            reported.

        Returns
        -------
        DynamicsResult

        Raises
        ------
        MechdynError
            For a value that is not a positive torque or force.
        """

        from mechdyn.units import si_field

        T = si_field("press rating", "rated_torque", rated_torque, "N*m", positive=True)
        F = (
            None
            if rated_force is None
            else si_field("press rating", "rated_force", rated_force, "N", positive=True)
        )
        return replace(self, rated_torque=T, rated_force=F, frame=frame)

    @property
    def mechanism(self) -> Mechanism:
        return self.kinematics.mechanism

    @property
    def angle(self) -> np.ndarray:
        """Crank angle from the datum, rad."""
        return self.kinematics.angle

    # -- loads -----------------------------------------------------------------------------------
    @cached_property
    def _constraint_loads(self) -> tuple[np.ndarray, np.ndarray]:
        J, Jg = self.load_jacobian or self.kinematics.evaluation.load_jacobian
        lam = self.multipliers
        # per row r: generalised load on the moving bodies −J[r]ᵀ λ_r and on the frame −Jg[r]ᵀ λ_r
        on_bodies = -J * lam[..., None]  # (N, m, n)
        on_frame = -Jg * lam[..., None]  # (N, m, 3)
        return on_bodies, on_frame

    @property
    def driving_torque(self) -> np.ndarray:
        """Torque the motor applies to the crank, N·m."""
        return -self.multipliers[:, -1]

    def joint_load(self, joint: str, body: str) -> np.ndarray:
        """(N, 3) force (x, y, N) and moment (N·m, about the body's centre of mass, or the origin
        for the frame) that ``joint`` puts on ``body``.

        Parameters
        ----------
        joint : str
            The joint's name.
        body : str
            One of the two bodies it joins."""
        m = self.mechanism
        names = [j.name for j in m.joints]
        if joint not in names:
            raise KeyError(joint)
        k = names.index(joint)
        on_bodies, on_frame = self._constraint_loads
        rows = m.joint_rows[k]
        if body == GROUND:
            return on_frame[:, rows, :].sum(axis=1)
        i = m.body_index[body]
        return on_bodies[:, rows, 3 * i : 3 * i + 3].sum(axis=1)

    @property
    def frame_load(self) -> np.ndarray:
        """(N, 3) total load on the frame: force (x, y) and moment about the origin, N and N·m.

        The motor's reaction torque is included in the moment."""
        return self._constraint_loads[1].sum(axis=1)

    @property
    def shaking_force(self) -> np.ndarray:
        """(N, 2) force the mechanism exerts on the frame, N."""
        return self.frame_load[:, :2]

    def shaking_moment(self, about: Any = (0.0, 0.0)) -> np.ndarray:
        """(N,) moment the mechanism exerts on the frame about a point, N·m (motor reaction included).

        Parameters
        ----------
        about : (float, float)
            The point, m, in the drawing's axes (each coordinate at most 1e3 m in magnitude).
        """
        px, py = _point("shaking moment", "about", about)
        F = self.frame_load
        return F[:, 2] - (px * F[:, 1] - py * F[:, 0])

    @property
    def inertia_forces(self) -> np.ndarray:
        """(N, n_bodies, 2) d'Alembert force −m a_G of every body, N."""
        k = self.kinematics
        nb = len(self.mechanism.bodies)
        a = k.qdd.reshape(-1, nb, 3)[:, :, :2]
        return -self.mechanism.masses[None, :, None] * a

    @property
    def inertia_force(self) -> np.ndarray:
        """(N, 2) total inertia force −Σ m a_G, N."""
        return self.inertia_forces.sum(axis=1)

    # -- checks and derived quantities ------------------------------------------------------
    @property
    def power_balance_residual(self) -> np.ndarray:
        """T θ̇ + P_applied − dE_kin/dt, W; zero to round-off for a consistent solution."""
        k, m = self.kinematics, self.mechanism
        nb = len(m.bodies)
        mass = np.repeat(m.masses, 3).reshape(nb, 3)
        mass[:, 2] = m.inertias
        dE = np.sum(mass.ravel() * k.qd * k.qdd, axis=1)
        return self.driving_torque * self.crank_speed + np.sum(self.applied * k.qd, axis=1) - dE

    @property
    def power_scale(self) -> float:
        """The power the balance is judged against, W: the largest power that flows.

        The largest over the cycle of ``|T θ̇| + Σ|F·v| + Σ|m v·a|`` (each term of
        :attr:`power_balance_residual` taken apart, so that terms cancelling each other do not hide
        their size), and at least the kinetic energy times the crank's angular speed, the power a
        round-off of the energy makes in one radian: a balanced rotor at constant speed, where every
        term is zero, gets a residual relative to that and reads as round-off (about 1e-16), not as
        the ratio of two round-offs.
        """
        k, m = self.kinematics, self.mechanism
        nb = len(m.bodies)
        mass = np.repeat(m.masses, 3).reshape(nb, 3)
        mass[:, 2] = m.inertias
        terms = (
            np.abs(self.driving_torque * self.crank_speed)
            + np.sum(np.abs(self.applied * k.qd), axis=1)
            + np.sum(np.abs(mass.ravel() * k.qd * k.qdd), axis=1)
        )
        energy = 0.5 * np.sum(mass.ravel() * k.qd**2, axis=1)
        floor = float(np.max(energy * np.abs(self.crank_speed)))
        return max(float(terms.max()), floor, 1e-300)

    @property
    def crank_speed(self) -> np.ndarray:
        """θ̇ at every angle, rad/s."""
        return self.kinematics.qd[:, 3 * self.mechanism.body_index[self.mechanism.driver.body] + 2]

    @property
    def output_position(self) -> np.ndarray | None:
        """Output point along its prismatic axis, m (the axis points up: BDC is the minimum)."""
        k = self.kinematics
        return output_position(self.mechanism, k.q)

    @property
    def process_torque(self) -> np.ndarray:
        """The torque the process forces ask of the crank in the sense it turns, −P divided by the
        crank speed's magnitude, N·m.

        P is the power of the process forces on the linkage (Σ F·v over their points); positive where
        they resist the motion. Quasi-static: the linkage's inertia and gravity are not in it.
        """
        m, k = self.mechanism, self.kinematics
        P = np.zeros(self.angle.size)
        if m.process_forces:
            s_out = output_position(m, k.q)
            for pf in m.process_forces:
                _, v, _ = k.point(pf.body, pf.point)
                fx, fy = pf.values(k.angle, s_out if s_out is not None else np.zeros(self.angle.size))
                P += fx * v[:, 0] + fy * v[:, 1]
        return -P / np.abs(self.crank_speed)

    @cached_property
    def _tonnage(self) -> tuple[dict[str, Any], dict[str, np.ndarray]] | None:
        """The tonnage figures and columns (:func:`mechdyn.mechanism.tonnage.tonnage_figures`), with a
        rated torque and a slide output; None otherwise."""
        s = self.output_position
        if self.rated_torque is None or s is None:
            return None
        from mechdyn.mechanism.process import process_path
        from mechdyn.mechanism.tonnage import tonnage_figures

        v = self._slide_motion[0]
        path = process_path(self.kinematics) if self.mechanism.process_forces else None
        figures, columns = tonnage_figures(
            self.angle,
            s,
            v,
            self.crank_speed,
            self.process_torque,
            self.rated_torque,
            self.rated_force,
            path=path,
        )
        if self.frame is not None and path is not None:
            from mechdyn.mechanism.tonnage import breakthrough

            m = self.mechanism
            j = m.output_joint()
            assert j is not None  # a slide position comes from one
            slide = j.bodies[1] if j.bodies[0] == GROUND else j.bodies[0]
            mass = float(m.masses[m.body_index[slide]])
            speed = float(np.mean(np.abs(self.crank_speed)))
            figures.update(breakthrough(path, self.frame, mass, speed, self.rated_force))
        return figures, columns

    @cached_property
    def _slide_motion(self) -> tuple[np.ndarray, np.ndarray]:
        """The output slide's velocity (m/s) and acceleration (m/s²) along its axis."""
        k = self.kinematics
        slide = self.mechanism.output_joint()
        assert slide is not None  # an output position comes from a slide
        moving = slide.bodies[1] if slide.bodies[0] == GROUND else slide.bodies[0]
        _, v, a = k.point(moving, slide.point)
        u = np.array([math.cos(slide.axis), math.sin(slide.axis)])
        return v @ u, a @ u

    def summary(self) -> dict[str, Any]:
        """Stroke, dead centres, inertia-force extremes, torque, power balance (SI, angles in degrees);
        with a rated torque and a slide, the tonnage figures (:mod:`mechdyn.mechanism.tonnage`)."""
        return copy.deepcopy(self._summary)  # worked out once: the tables and every plot ask for it

    @cached_property
    def _summary(self) -> dict[str, Any]:
        from mechdyn.mechanism.extrema import load_figures, output_figures

        deg = np.degrees(self.angle)
        T = self.driving_torque
        out: dict[str, Any] = {
            key: float(v) for key, v in load_figures(T, self.shaking_force, self.shaking_moment()).items()
        }
        out["power_balance_residual_relative"] = float(
            np.abs(self.power_balance_residual).max() / self.power_scale
        )
        s = self.output_position
        j = self.mechanism.output_joint()
        if s is not None and j is not None:
            u = np.array([math.cos(j.axis), math.sin(j.axis)])
            figures = output_figures(deg, s, self.inertia_force @ u, self.mechanism.angle_datum == "bdc")
            out.update({key: float(v) for key, v in figures.items()})
        ends = self.mechanism.output_link()
        if ends is not None and j is not None:
            from mechdyn.mechanism.extrema import layout_figures

            m, kin = self.mechanism, self.kinematics
            a, b = ends
            body = next(x.name for x in m.bodies if a in x.points and b in x.points)
            za, zb = (kin.point(body, p)[0] @ np.array([1.0, 1j]) for p in (a, b))
            pivot = complex(*m.points[m.driver.pivot])
            figures = layout_figures(zb - za, j.axis, np.asarray(pivot), np.asarray(zb[0]))
            out.update({key: float(v) for key, v in figures.items()})
        out.update(self._motion_figures())
        peaks = self.joint_force_peaks
        out["joint_force_peak_N"] = peaks
        gears = self.gear_pairs
        if gears:
            out["tooth_force_max_N"] = max(peaks[g] for g in gears)
            out["gear_pairs"] = gears
        if self._tonnage is not None:
            out.update(self._tonnage[0])
        out["n_angles"] = int(self.angle.size)
        return out

    def _motion_figures(self) -> dict[str, Any]:
        """The smallest transmission angle (overall and per dyad) and a rocker output's swing: the
        same functions as the batch's :meth:`~mechdyn.mechanism.dyads.CycleBatch.summary`."""
        from mechdyn.mechanism.extrema import bdc_origin, swing_figures, transmission_figures

        deg = np.degrees(self.angle)
        s = self.output_position
        origin = bdc_origin(deg, s) if s is not None and self.mechanism.angle_datum == "bdc" else None
        out: dict[str, Any] = {}
        angles = self.kinematics.transmission_angles
        if angles:
            mu = np.degrees(np.stack(list(angles.values()), axis=-1))
            figures, lowest, at = transmission_figures(deg, mu, origin)
            out.update({key: float(v) for key, v in figures.items()})
            out["dyads"] = {
                d.joint: {
                    "kind": d.kind,
                    "links": f"{d.links[0]}, {d.links[1]}",
                    "transmission_angle_min_deg": float(lowest[i]),
                    "crank_angle_at_transmission_angle_min_deg": float(at[i]),
                    "transmission_angle_max_deg": float(mu[:, i].max()),
                }
                for i, d in enumerate(mechanism_dyads(self.mechanism))
            }
        link = rocker_link(self.kinematics)
        if link is not None:
            swing = swing_figures(deg, link, origin)
            if np.isfinite(swing["output_swing_deg"]):  # a link that turns right round is no rocker
                out.update({key: float(v) for key, v in swing.items()})
        return out

    @cached_property
    def joint_force_peaks(self) -> dict[str, float]:
        """Largest force magnitude over the cycle in each joint (on its second body), N."""
        return {
            j.name: float(np.linalg.norm(self.joint_load(j.name, j.bodies[1])[:, :2], axis=1).max())
            for j in self.mechanism.joints
        }

    @cached_property
    def gear_pairs(self) -> dict[str, dict[str, Any]]:
        """For each gear joint: centre distance, mean ratio, convexity, pressure-angle range
        (:func:`mechdyn.mechanism.pitch.report`)."""
        from mechdyn.mechanism.pitch import report

        m = self.mechanism
        joints = {j.name: cast(GearJoint, j) for j in m.joints if j.name in m.gear_laws}
        return {name: report(law, joints[name].pressure_angle) for name, law in m.gear_laws.items()}

    @property
    def warnings(self) -> tuple[str, ...]:
        """A concave pitch curve (its teeth would be undercut)."""
        return tuple(
            f"gear pair {name!r}: a pitch curve is concave; its teeth would be undercut"
            for name, rep in self.gear_pairs.items()
            if not rep["convex"]
        )

    def tables(self, **display_units: str) -> list[Table]:
        """The summary with units, the joint-force peaks and the gear pairs.

        ``length_unit`` (default ``"mm"``) shows the gears' centre distances.
        """
        from mechdyn.results import summary_table
        from mechdyn.units import convert

        length = display_units.get("length_unit", "mm")
        summary = self.summary()
        numbers = {k: v for k, v in summary.items() if not isinstance(v, str)}
        rating = {k: v for k, v in numbers.items() if k.startswith(_RATING)}
        tables = [
            summary_table(
                {k: v for k, v in numbers.items() if k not in rating},
                skip=("n_angles",),
                display_units=display_units,
            ),
            *(
                [replace(summary_table(rating, display_units=display_units), title="press rating")]
                if rating
                else []
            ),
            Table(
                "joint forces (largest over the cycle)",
                ["joint", "force [N]"],
                [[k, v] for k, v in self.joint_force_peaks.items()],
            ),
        ]
        if summary.get("dyads"):
            tables.append(
                Table(
                    "transmission angles of the dyads",
                    ["dyad", "links", "smallest [deg]", "at crank angle [deg]", "largest [deg]"],
                    [
                        [
                            f"{joint} ({d['kind']})",
                            d["links"],
                            d["transmission_angle_min_deg"],
                            d["crank_angle_at_transmission_angle_min_deg"],
                            d["transmission_angle_max_deg"],
                        ]
                        for joint, d in summary["dyads"].items()
                    ],
                    note="the acute angle between the coupler and the output link (a slide: the normal to "
                    "its travel) at their joint; 90° transmits best, 0° locks",
                )
            )
        if self.gear_pairs:
            tables.append(
                Table(
                    "gear pairs",
                    [
                        "pair",
                        f"centre distance [{length}]",
                        "mean ratio",
                        "convex",
                        "φ min [deg]",
                        "φ max [deg]",
                    ],
                    [
                        [
                            n,
                            convert(r["centre_distance_m"], "m", length),
                            r["mean_ratio"],
                            r["convex"],
                            r["pressure_angle_min_deg"],
                            r["pressure_angle_max_deg"],
                        ]
                        for n, r in self.gear_pairs.items()
                    ],
                )
            )
        if self._tonnage is not None:
            from mechdyn.mechanism.tonnage import tonnage_table

            tables.append(tonnage_table(self._tonnage[0], self._tonnage[1], length, self.mechanism.name))
        from mechdyn.mechanism.summary import model_tables

        tables += model_tables(self.mechanism)
        return tables

    def plots(self, **display_units: str) -> dict[str, Any]:
        """Output motion (a slide's or a rocker's), inertia forces, torque, frames, joint forces,
        shaking force polar, the dyads' transmission angles, the coupler curves, and the traced paths
        over the field (when the model names points to trace)."""
        from mechdyn.mechanism import plots as mp

        out: dict[str, Any] = {}
        if self.output_position is not None or "output_swing_deg" in self.summary():
            out["output_motion.png"] = lambda: mp.plot_output_motion(self)
        out |= {
            "inertia_forces.png": lambda: mp.plot_inertia_forces(self),
            "driving_torque.png": lambda: mp.plot_torque(self),
            "frames.png": lambda: mp.plot_frames(self),
            "joint_forces.png": lambda: mp.plot_joint_forces(self),
            "shaking_force_polar.png": lambda: mp.plot_shaking_polar(self),
        }
        if self.kinematics.transmission_angles:
            out["transmission_angle.png"] = lambda: mp.plot_transmission_angle(self)
        if mp.coupler_points(self):
            out["coupler_curves.png"] = lambda: mp.plot_coupler_curves(self)
        if self.trace:
            out["trajectory.png"] = lambda: mp.plot_trajectory(self, list(self.trace), self.field_velocity)
        if self._tonnage is not None:
            out["tonnage.png"] = lambda: mp.plot_tonnage(self)
        return out

    def animate(
        self, path: str | Path | None = None, frames: int = 72, *, period: float = 4.8, dpi: int = 80
    ) -> Any:
        """The linkage animated over one crank cycle, written to ``path`` when one is given.

        The links as the frame sheet draws them, the frame's pivots and guides, the coupler curves
        traced as the crank turns and the crank angle, on equal axes in mm whose limits hold the whole
        motion (:func:`mechdyn.mechanism.animation.animate`).

        Parameters
        ----------
        path : str or Path, optional
            A ``.gif`` (written with Pillow) or an ``.mp4`` (needs ffmpeg).
        frames : int
            Number of frames (count): equally spaced crank angles, at most one per sampled angle.
        period : float
            Playing time of one crank cycle, s.
        dpi : int
            Resolution, dots per inch (the figure is 5 inches wide).

        Returns
        -------
        matplotlib.animation.FuncAnimation
            Showing the first frame; with a ``path``, written and its figure closed.

        Raises
        ------
        MechdynError
            For a path that is not a ``.gif`` or ``.mp4``, or an ``.mp4`` where ffmpeg is not
            installed (before anything is drawn).
        """
        from mechdyn.mechanism.animation import animate

        return animate(self, path, frames, period=period, dpi=dpi)

    def to_frame(self) -> pd.DataFrame:
        """Per-angle table; every column names its unit."""
        import pandas as pd

        return pd.DataFrame(self._columns)

    @cached_property
    def _columns(self) -> dict[str, np.ndarray]:
        """The per-angle table's columns, worked out once: the CSV and the plots read them (the plots
        without pandas, which a process drawing figures would otherwise import for half a second)."""
        cols: dict[str, Any] = {"angle_deg": np.degrees(self.angle), "time_s": self.kinematics.time}
        s = self.output_position
        if s is not None:
            v, a = self._slide_motion
            cols.update(output_position_m=s, output_velocity_m_per_s=v, output_acceleration_m_per_s2=a)
            if self._tonnage is not None:
                cols.update(self._tonnage[1])
        cols["driving_torque_Nm"] = self.driving_torque
        cols["shaking_force_x_N"] = self.shaking_force[:, 0]
        cols["shaking_force_y_N"] = self.shaking_force[:, 1]
        cols["shaking_moment_Nm"] = self.shaking_moment()
        cols["inertia_force_x_N"] = self.inertia_force[:, 0]
        cols["inertia_force_y_N"] = self.inertia_force[:, 1]
        for i, b in enumerate(self.mechanism.bodies):
            cols[f"inertia_force_{b.name}_x_N"] = self.inertia_forces[:, i, 0]
            cols[f"inertia_force_{b.name}_y_N"] = self.inertia_forces[:, i, 1]
        for j in self.mechanism.joints:
            load = self.joint_load(j.name, j.bodies[1])
            cols[f"joint_{j.name}_force_x_N"] = load[:, 0]
            cols[f"joint_{j.name}_force_y_N"] = load[:, 1]
        cols["power_balance_residual_W"] = self.power_balance_residual
        cols |= motion_columns(self.kinematics, self.trace)
        return cols


def applied_forces(mechanism: Mechanism, k: KinematicsResult) -> np.ndarray:
    """The generalised applied forces on the body coordinates at every sample: gravity on each body's
    centre of mass and the process forces at their points, N (and N·m on the rotations).

    Parameters
    ----------
    mechanism : Mechanism
        Its gravity (m/s²) and process forces.
    k : KinematicsResult
        Its kinematics (positions, for the process forces' points and the output's position).

    Returns
    -------
    ndarray
        (N, n) Q_q, in the order of the body coordinates (x_G, y_G, ψ per body); the virtual work of
        the forces (d'Alembert's principle: Q_q · δq).
    """
    N, n = k.q.shape
    Q = np.zeros((N, n))
    Q.reshape(N, -1, 3)[:, :, :2] = mechanism.masses[:, None] * np.asarray(mechanism.gravity)
    if not mechanism.process_forces:
        return Q
    s_out = output_position(mechanism, k.q)
    for pf in mechanism.process_forces:
        i = mechanism.body_index[pf.body]
        pos, _, _ = k.point(pf.body, pf.point)
        fx, fy = pf.values(k.angle, s_out if s_out is not None else np.zeros(N))
        F = np.stack((fx, fy), axis=-1)
        arm = pos - k.q[:, 3 * i : 3 * i + 2]
        Q[:, 3 * i : 3 * i + 2] += F
        Q[:, 3 * i + 2] += arm[:, 0] * F[:, 1] - arm[:, 1] * F[:, 0]
    return Q


def inverse_dynamics(
    mechanism: Mechanism | KinematicsResult, n_angles: int = 360, method: Any = "auto"
) -> DynamicsResult:
    """Joint reactions, driving torque and frame loads over one crank revolution.

    Parameters
    ----------
    mechanism : Mechanism or KinematicsResult
        A kinematics result is reused as it is.
    n_angles : int
        Crank angles per revolution (when a Mechanism is given), a whole number from 4 to 100 000.
    method : {"auto", "dyads", "newton"} or callable
        The motion solver, see :func:`~mechdyn.mechanism.kinematics.kinematics`; the loads follow
        from whichever motion it gives, here.

    Returns
    -------
    DynamicsResult

    Examples
    --------
    A slider-crank of 100 mm crank: its stroke is twice the crank, and the power the motor puts in
    equals the rate of change of kinetic energy at every angle.

    >>> from mechdyn.mechanism import Body, Driver, Mechanism, Prismatic, Revolute, inverse_dynamics
    >>> crank = Mechanism(
    ...     points={"O": (0.0, 0.0), "A": ("100 mm", "0 mm"), "B": ("500 mm", "0 mm")},
    ...     bodies=(
    ...         Body("crank", ("O", "A"), "2 kg", "0.002 kg*m^2"),
    ...         Body("rod", ("A", "B"), "3 kg", "0.04 kg*m^2"),
    ...         Body("slider", ("B",), "5 kg"),
    ...     ),
    ...     joints=(
    ...         Revolute("O", ("ground", "crank"), "O"),
    ...         Revolute("A", ("crank", "rod"), "A"),
    ...         Revolute("B", ("rod", "slider"), "B"),
    ...         Prismatic("guide", ("slider", "ground"), "B", "0 deg"),
    ...     ),
    ...     driver=Driver("crank", "O", "A", "100 rad/s"),
    ... )
    >>> summary = inverse_dynamics(crank, 72).summary()
    >>> round(summary["stroke_m"], 6), summary["power_balance_residual_relative"] < 1e-9
    (0.2, True)
    """
    k = mechanism if isinstance(mechanism, KinematicsResult) else kinematics(mechanism, n_angles, method)
    mech = k.mechanism
    nb = len(mech.bodies)
    mass = np.repeat(mech.masses, 3).reshape(nb, 3)
    mass[:, 2] = mech.inertias
    Q = applied_forces(mech, k)
    if k.dyads is not None:  # joint forces group by group, without the full Jacobian
        order = angle_order(k.dyads.angle[0])
        return DynamicsResult(k, k.dyads.multipliers[0][order], Q)
    rhs = Q - mass.ravel() * k.qdd
    J, Jg = k.evaluation.load_jacobian
    lam, _ = solve_with_det(np.swapaxes(J, -1, -2), rhs)
    cs = k.constraints
    rows = cs.load_dependent_rows
    if rows.size:
        # a joint whose force law depends on the sign of its own multiplier (gear teeth push apart
        # on whichever flank the tangential force loads): choose the side by the sign and solve
        # again until the choice holds (it settles in a pass or two)
        for _ in range(8):
            flank = np.where(lam[:, rows] < 0, -1.0, 1.0)
            ev = cs.evaluate(k.q, k.crank_angle, forces=True, flank=flank)
            J, Jg = ev.load_jacobian
            lam, _ = solve_with_det(np.swapaxes(J, -1, -2), rhs)
            if np.array_equal(np.where(lam[:, rows] < 0, -1.0, 1.0), flank):
                break
        return DynamicsResult(k, lam, Q, (J, Jg))
    return DynamicsResult(k, lam, Q)
