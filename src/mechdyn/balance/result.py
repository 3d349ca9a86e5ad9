"""The result of :func:`mechdyn.balance.balance`: the counterweights found, what they buy and cost,
the trade-off front and the mass front."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.balance.exact import GAP, Budget
from mechdyn.balance.fronts import gain_mass
from mechdyn.balance.influence import Influence
from mechdyn.balance.objectives import split
from mechdyn.plotting import legend
from mechdyn.results import Result, Table, summary_table

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["BalanceResult"]

_REPORTED = (
    "shaking_force_rms",
    "shaking_force_peak",
    "shaking_force_range",
    "shaking_moment_rms",
    "shaking_moment_range",
    "driving_torque_rms",
    "driving_torque_range",
)
_FLOOR = ("floor_force_rms", "floor_force_peak", "floor_force_range")


def _front_column(key: str, values: list[Any]) -> tuple[str, list[Any]]:
    """A front column's header and values, in the unit a designer reads its largest value in:
    ``weight_shaking_moment_rms_ratio`` → "weight shaking moment rms", ``floor_force_rms_N`` →
    "floor force rms [kN]" with its values in kN."""
    from mechdyn.units import convert, key_label, key_unit, readable_unit

    label, unit = key_label(key)
    si = key_unit(key)
    numbers = [abs(float(v)) for v in values if isinstance(v, (int, float)) and not isinstance(v, bool)]
    if unit in ("", "1") or si is None or not numbers:
        return label, values
    display, shown = readable_unit(max(numbers), unit)
    factor = float(convert(1.0, si, display))
    return f"{label} [{shown}]", [v * factor if isinstance(v, float) else v for v in values]


def _mass_words(kg: float) -> str:
    """A mass as a designer says it: "40.8 t", "350 kg"."""
    from mechdyn.units import convert

    return f"{float(convert(kg, 'kg', 't')):.3g} t" if kg >= 1e3 else f"{kg:.3g} kg"


def _same(a: dict[str, float], b: dict[str, float]) -> bool:
    """Whether two front rows hold the same design and values, to 0.1 % (weights aside)."""
    return all(
        math.isclose(a[k], b[k], rel_tol=1e-3, abs_tol=1e-9 * max(abs(a[k]), abs(b[k]), 1.0))
        for k in a
        if not k.startswith("weight")
    )


def _unit(name: str) -> str:
    return "N" if split(name)[0] in ("shaking_force", "floor_force") else "Nm"


@dataclass(frozen=True, repr=False)
class BalanceResult(Result):
    """Counterweights found for a mechanism, before and after.

    Attributes
    ----------
    influence : Influence
        The linear maps (shaking force, moment, driving torque) the design was found on.
    floor : FloorMap or None
        The floor force through the support model, when one was given.
    slots : tuple of CounterweightSlot
        The links and their bounds.
    objective : dict
        Metric → weight (one metric: weight 1).
    design : ndarray
        (L, 3) per link: mass (kg), radius (m) and angle β (rad, from +x of the drawing) from its
        reference point.
    method : str
        How it was found.
    exact : bool
        Whether the design is the exact optimum of a linear problem (no bound cut it).
    front : tuple of dict
        The trade-off front: one row per weighting.
    setup_seconds, solve_seconds : float
        Time to build the linear maps (one inverse dynamics, the support responses) and to optimise, s.
    budget : Budget
        Total added mass (kg) and rotary inertia (kg·m²) allowed, and the slack (dimensionless)
        traded for less mass.
    bound : float
        Certified lower bound of the objective's metric when ``exact`` (N), else NaN.
    mass_front : tuple of dict
        The objective against the total added mass allowed (:func:`mechdyn.balance.fronts.mass_front`).
    """

    influence: Influence
    floor: Any
    slots: tuple[Any, ...]
    objective: dict[str, float]
    design: np.ndarray
    method: str
    exact: bool
    front: tuple[dict[str, float], ...] = ()
    setup_seconds: float = 0.0
    solve_seconds: float = 0.0
    budget: Budget = field(default_factory=Budget)
    bound: float = math.nan
    mass_front: tuple[dict[str, float], ...] = ()

    @property
    def counterweights(self) -> tuple[Any, ...]:
        """The counterweights found (:class:`mechdyn.mechanism.Counterweight`, drawing positions)."""
        return self.influence.counterweights(self._uv)

    @property
    def _uv(self) -> np.ndarray:
        m, r, b = self.design.T
        return np.column_stack([m, r * np.cos(b), r * np.sin(b)])

    @property
    def mechanism(self) -> Any:
        """The mechanism with the counterweights found added (:class:`mechdyn.mechanism.Mechanism`)."""
        m = self.influence.mechanism
        return replace(m, counterweights=m.counterweights + self.counterweights)

    @cached_property
    def _x(self) -> np.ndarray:
        from mechdyn.balance.solve import Evaluator

        return Evaluator(self.influence).coefficients(self.design)

    def _metrics(self, x: np.ndarray) -> dict[str, float]:
        from mechdyn.balance.solve import Evaluator

        names = list(_REPORTED) + (list(_FLOOR) if self.floor is not None else [])
        vals = Evaluator(self.influence, self.floor).metrics(x, names)
        return {n: float(v) for n, v in vals.items()}

    @cached_property
    def before(self) -> dict[str, float]:
        """Every metric without the counterweights found, SI (N, N·m)."""
        return self._metrics(np.zeros_like(self._x))

    @cached_property
    def after(self) -> dict[str, float]:
        """Every metric with them, SI (N, N·m)."""
        return self._metrics(self._x)

    @property
    def added_inertia(self) -> float:
        """Σ m r² of the counterweights found, each about its link's reference point, kg·m²."""
        return float(np.sum(self.design[:, 0] * self.design[:, 1] ** 2))

    @property
    def active_bounds(self) -> tuple[str, ...]:
        """The bounds and budgets the design found sits on (within 1e-4), in words."""
        from mechdyn.units import readable

        mass = _mass_words

        def length(m: float) -> str:
            v, u = readable(m, "m")
            return f"{v:.4g} {u}"

        tol = 1e-4
        out = []
        for s, (m, r, _) in zip(self.slots, self.design, strict=True):
            (m_lo, m_hi), (r_lo, r_hi) = s.mass, s.radius
            if m >= m_hi * (1 - tol):
                out.append(f"{s.link} mass ≤ {mass(m_hi)}")
            elif m_lo > 0 and m <= m_lo * (1 + tol):
                out.append(f"{s.link} mass ≥ {mass(m_lo)}")
            if m > 0 and r >= r_hi * (1 - tol):
                out.append(f"{s.link} radius ≤ {length(r_hi)}")
            elif m > 0 and r_lo > 0 and r <= r_lo * (1 + tol):
                out.append(f"{s.link} radius ≥ {length(r_lo)}")
        b = self.budget
        if math.isfinite(b.mass) and self.design[:, 0].sum() >= b.mass * (1 - tol):
            out.append(f"total mass ≤ {mass(b.mass)}")
        if math.isfinite(b.inertia) and self.added_inertia >= b.inertia * (1 - tol):
            out.append(f"total inertia ≤ {b.inertia:.4g} kg·m²")
        return tuple(out)

    def summary(self) -> dict[str, Any]:
        """Counterweight mass and inertia, the bounds they sit on, each metric before and after, the
        objective's ratio, what the added mass buys, timings (SI)."""
        out: dict[str, Any] = {
            "counterweight_mass_total_kg": float(self.design[:, 0].sum()),
            "counterweight_inertia_total_kg_m2": self.added_inertia,
        }
        if math.isfinite(self.budget.mass):
            out["max_added_mass_kg"] = float(self.budget.mass)
        if math.isfinite(self.budget.inertia):
            out["max_added_inertia_kg_m2"] = float(self.budget.inertia)
        out["active_bounds"] = "; ".join(self.active_bounds) or "none"
        out["objective"] = " + ".join(
            n if w == 1 and len(self.objective) == 1 else f"{w:g}·{n}" for n, w in self.objective.items()
        )
        out["objective_ratio"] = self._objective_ratio()
        if self.exact and math.isfinite(self.bound):
            name = next(iter(self.objective))  # over the bound; a complete balance's is round-off
            floor = max(self.bound, GAP * self.before[name], 1e-300)
            out["optimality_gap_ratio"] = (self.after[name] - self.bound) / floor
        out["slack_ratio"] = float(self.budget.slack)
        if self.mass_front:
            out["mass_for_90_percent_of_gain_kg"] = gain_mass(self.mass_front, 0.9)
        for n in self.before:
            u = _unit(n)
            out[f"{n}_before_{u}"] = self.before[n]
            out[f"{n}_after_{u}"] = self.after[n]
        cw = {}
        for k, s in enumerate(self.slots):
            m, r, b = (float(v) for v in self.design[k])
            p = self.influence.origin(k) + r * np.array([math.cos(b), math.sin(b)])
            cw[s.link] = {
                "mass_kg": m,
                "radius_m": r,
                "angle_deg": math.degrees(b) % 360.0,
                "x_m": float(p[0]),
                "y_m": float(p[1]),
                "from_point": self.influence.points[k],
            }
        out["counterweights"] = cw
        out["method"] = self.method
        out["exact"] = bool(self.exact)
        out["setup_time_s"] = float(self.setup_seconds)
        out["solve_time_s"] = float(self.solve_seconds)
        return out

    def _objective_ratio(self) -> float:
        num = sum(w * self.after[n] / max(self.before[n], 1e-300) for n, w in self.objective.items())
        return float(num / sum(self.objective.values()))

    @cached_property
    def _columns(self) -> dict[str, np.ndarray]:
        from mechdyn.balance.solve import Evaluator

        ev = Evaluator(self.influence)
        b0, b1 = ev.infl.channels(np.zeros_like(self._x)), ev.infl.channels(self._x)
        cols: dict[str, np.ndarray] = {"angle_deg": np.degrees(self.influence.angle)}
        for j, name in enumerate(("shaking_force_x", "shaking_force_y", "shaking_moment", "driving_torque")):
            u = "N" if j < 2 else "Nm"
            cols[f"{name}_before_{u}"] = b0[:, j]
            cols[f"{name}_after_{u}"] = b1[:, j]
        if self.floor is not None:
            f0, f1 = self.floor.force(np.zeros_like(self._x)), self.floor.force(self._x)
            inv = np.empty_like(self.floor.order)
            inv[self.floor.order] = np.arange(inv.size)  # back to the crank angles' order
            if f0.shape[0] == inv.size:
                for j, axis in enumerate("xyz"):
                    cols[f"floor_force_{axis}_before_N"] = f0[inv, j]
                    cols[f"floor_force_{axis}_after_N"] = f1[inv, j]
        return cols

    def to_frame(self) -> pd.DataFrame:
        """Per crank angle: shaking force, moment, driving torque (and floor force) before and after."""
        import pandas as pd

        return pd.DataFrame(self._columns)

    def front_frame(self) -> pd.DataFrame:
        """The trade-off front, one row per weighting (weights, mass kg, metrics N and N·m)."""
        import pandas as pd

        return pd.DataFrame(list(self.front))

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        """The per-angle columns and the design (mass kg, radius m, angle rad per link)."""
        from mechdyn.results import frame_arrays

        out = frame_arrays(self.to_frame())
        out["design"] = (np.asarray(self.design), "kg, m, rad")
        return out

    def tables(self, **display_units: str) -> list[Table]:
        """The summary, the counterweights, the trade-off front and the mass front."""
        s = self.summary()
        cw = s.pop("counterweights")
        objective, method = s.pop("objective", None), s.pop("method", None)
        said = []
        if objective is not None:
            said.append(f"Objective: {str(objective).replace('_', ' ')}")
        if method is not None:
            said.append(f"found by {method}")
        summary = summary_table(s, display_units=display_units)
        tables = [replace(summary, note=", ".join(said) + "." if said else summary.note)]
        tables.append(
            Table(
                "counterweights found",
                ["link", "mass [kg]", "radius [mm]", "angle [deg]", "x [mm]", "y [mm]", "from point"],
                [
                    [
                        link,
                        d["mass_kg"],
                        d["radius_m"] * _MM,
                        d["angle_deg"],
                        d["x_m"] * _MM,
                        d["y_m"] * _MM,
                        d["from_point"],
                    ]
                    for link, d in cw.items()
                ],
                note="Positions in the drawing; radius and angle from the link's reference point.",
            )
        )
        if self.front:
            tables.append(self._front_table())
        if self.mass_front:
            tables.append(self._mass_table())
        return tables

    def _front_table(self) -> Table:
        keys = list(self.front[0])
        moved = [k for k in keys if k.startswith(("shaking_moment", "driving_torque"))]
        still = all(
            math.isclose(row[k], self.front[0][k], rel_tol=1e-9, abs_tol=1e-9)
            for row in self.front
            for k in moved
        )
        front: tuple[dict[str, float], ...] = self.front
        if still:  # one row per distinct design (to 0.1 %) that the force asks for
            distinct: list[dict[str, float]] = []
            for row in self.front:
                if row[keys[0]] > 0 and not any(_same(row, kept) for kept in distinct):
                    distinct.append(row)
            front = tuple(distinct) or self.front[:1]
        columns = [_front_column(k, [row[k] for row in front]) for k in keys]
        note = (
            "Each row: the lightest counterweights minimising the weighted sum of the three RMS values, "
            "each relative to its value without counterweights."
        )
        if still:
            asked = sum(1 for row in self.front if row[keys[0]] > 0)
            note += (
                f" Every one of the {asked} weightings with a weight on the force finds "
                + ("this same design" if len(front) == 1 else f"one of these {len(front)} designs")
                + ", and those without one add no counterweight: the shaking moment and the driving torque "
                "do not change with these counterweights here, so there is no trade-off to make."
            )
        return Table(
            "trade-off front (weights of force, shaking moment, driving torque RMS)",
            [header for header, _ in columns],
            [list(row) for row in zip(*(values for _, values in columns), strict=True)],
            note=note,
        )

    def _mass_table(self) -> Table:
        rows = self.mass_front
        keys = list(rows[0])
        columns = [_front_column(k, [row[k] for row in rows]) for k in keys]
        need = gain_mass(rows, 0.9)
        total = rows[-1]["counterweight_mass_kg"]
        return Table(
            "mass front (the objective's optimum for each total added mass allowed)",
            [header for header, _ in columns],
            [list(row) for row in zip(*(values for _, values in columns), strict=True)],
            note=f"Each row: the lightest counterweights minimising the objective with at most that total "
            f"mass; the objective relative to its value without counterweights; the share of the design's "
            f"reduction it buys. 90 % of the reduction takes {_mass_words(need)} of the design's "
            f"{_mass_words(total)} ({need / max(total, 1e-300):.0%}; linear between rows: an upper bound "
            "for a force objective).",
        )

    def plots(self, **display_units: str) -> dict[str, Any]:
        """Shaking force (polar) and driving torque before and after, the trade-off front and the mass
        front."""
        out = {
            "balance_shaking_force.png": self._plot_force,
            "balance_torque_moment.png": self._plot_torque,
        }
        if self.front:
            out["balance_front.png"] = self._plot_front
        if self.mass_front:
            out["balance_mass_front.png"] = self._plot_mass_front
        return out

    def _plot_force(self) -> Any:
        import matplotlib.pyplot as plt

        c = self._columns
        _fig, ax = plt.subplots(figsize=(5, 5))
        for tag in ("before", "after"):
            ax.plot(c[f"shaking_force_x_{tag}_N"], c[f"shaking_force_y_{tag}_N"], label=tag)
        ax.set_xlabel("shaking force x [N]")
        ax.set_ylabel("shaking force y [N]")
        ax.set_aspect("equal", adjustable="datalim")
        legend(ax)
        return ax

    def _plot_torque(self) -> Any:
        import matplotlib.pyplot as plt

        c = self._columns
        _fig, axes = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
        for tag in ("before", "after"):
            axes[0].plot(c["angle_deg"], c[f"driving_torque_{tag}_Nm"], label=tag)
            axes[1].plot(c["angle_deg"], c[f"shaking_moment_{tag}_Nm"], label=tag)
        axes[0].set_ylabel("driving torque [N·m]")
        axes[1].set_ylabel("shaking moment [N·m]")
        axes[1].set_xlabel("crank angle [deg]")
        legend(axes[0])
        return axes[0]

    def _plot_front(self) -> Any:
        import matplotlib.pyplot as plt

        rows = self.front
        force = next(k for k in rows[0] if k.endswith("_N"))
        fig, ax = plt.subplots(figsize=(6, 4.5))
        x = [r[force] for r in rows]
        y = [r["shaking_moment_rms_Nm"] for r in rows]
        sc = ax.scatter(x, y, c=[r["driving_torque_range_Nm"] for r in rows])
        fig.colorbar(sc, ax=ax, label="driving torque range [N·m]")
        ax.set_xlabel(force.replace("_", " ").removesuffix(" N") + " [N]")
        ax.set_ylabel("shaking moment rms [N·m]")
        return ax

    def _plot_mass_front(self) -> Any:
        import matplotlib.pyplot as plt

        from mechdyn.units import convert, readable_unit

        rows = self.mass_front
        names = [k for k in rows[0] if k.endswith("_N")]
        mass_label, mass = _front_column("counterweight_mass_kg", [r["counterweight_mass_kg"] for r in rows])
        display, shown = readable_unit(max(abs(r[n]) for r in rows for n in names), "N")
        factor = float(convert(1.0, "N", display))
        _fig, ax = plt.subplots(figsize=(6, 4.5))
        for n in names:
            ax.plot(mass, [r[n] * factor for r in rows], "o-", label=n.removesuffix("_N").replace("_", " "))
        ax.set_xlabel(mass_label.replace("counterweight mass", "total counterweight mass"))
        ax.set_ylabel(f"after balancing [{shown}]")
        legend(ax)
        return ax


_MM = 1.0  # replaced below by the unit registry's factor (no hand-typed unit factors)


def _mm_factor() -> float:
    from mechdyn.units import convert

    return float(convert(1.0, "m", "mm"))


_MM = _mm_factor()
