"""The balancing analysis in the registry: ``balance`` (counterweights on a mechanism's links that cut
its shaking force, or the floor force through its support)."""

from __future__ import annotations

import math
from typing import Any

from mechdyn.registry import Analysis, Option, Output, register

__all__: list[str] = []

_OBJECTIVES = (
    "shaking_force_rms, shaking_force_peak, shaking_force_range, shaking_moment_rms|peak|range, "
    "driving_torque_rms|peak|range, floor_force_rms|peak|range (with a support)"
)


def _objective(text: str | None, floor: bool) -> Any:
    """``name`` or ``name=weight,name=weight`` → the objective of :func:`mechdyn.balance.balance`."""
    if text is None:
        return "floor_force_range" if floor else "shaking_force_rms"
    if "=" not in text:
        return text.strip()
    from mechdyn.errors import MechdynError

    weights = {}
    for part in text.split(","):
        name, _, w = part.partition("=")
        try:
            weights[name.strip()] = float(w)
        except ValueError:
            raise MechdynError(
                f"--objective {text!r}: {part!r} must be name=weight, e.g. shaking_force_rms=1"
            ) from None
    return weights


def _support_file(path: str) -> Any:
    from mechdyn.errors import MechdynError
    from mechdyn.io import load_model

    loaded = load_model(path)
    if loaded.type != "support":
        raise MechdynError(f"--support {path}: a {loaded.type!r} model; give a support model file")
    return loaded


def _balance(
    loaded: Any,
    links: list[str] | None = None,
    objective: str | None = None,
    mass_max: float | None = None,
    radius_max: float | None = None,
    support: str | None = None,
    angles: int | None = None,
    max_added_mass: float | None = None,
    max_added_inertia: float | None = None,
    slack: float | None = None,
) -> Any:
    from mechdyn.balance.design import balance
    from mechdyn.balance.solve import CounterweightSlot
    from mechdyn.errors import MechdynError

    machine = placement = None
    sup = _support_file(support) if support is not None else None
    if sup is not None:
        from mechdyn.support.schema import MechanismExcitation

        e = getattr(sup.settings, "excitation", None)
        if not isinstance(e, MechanismExcitation):
            where = sup.source.path if sup.source is not None else "the support model"
            raise MechdynError(
                f"{where}: [excitation] is not a mechanism; balancing needs a support file whose load is a "
                "mechanism (excitation.mechanism = FILE)"
            )
        machine, placement = sup.model, e.placement
        mechanism = loaded.model
        n = angles or e.angles
    else:
        mechanism = loaded.model
        spec = loaded.settings
        n = angles or getattr(spec, "n_angles", None) or 360
    names = list(links) if links else [mechanism.driver.body]
    moving = float(mechanism.masses.sum()) or 1.0
    slots = []
    for name in names:
        reach = radius_max
        if reach is None:
            from mechdyn.balance.influence import reference_point

            ref = mechanism.points[reference_point(mechanism, name)]
            body = mechanism.bodies[mechanism.body_index[name]]
            reach = max(math.dist(mechanism.points[p], ref) for p in body.points) or 1.0
        slots.append(
            CounterweightSlot(name, (0.0, mass_max if mass_max is not None else moving), (0.0, reach))
        )
    return balance(
        mechanism,
        slots,
        _objective(objective, machine is not None),
        support=machine,
        placement=placement,
        n_angles=n,
        max_added_mass=max_added_mass,
        max_added_inertia=max_added_inertia,
        slack=0.0 if slack is None else slack,
    )


register(
    Analysis(
        "balance",
        ("mechanism", "planting_mechanism"),
        _balance,
        "counterweights on a mechanism's links that cut the shaking force or the floor force",
        headline=("counterweight_mass_total_kg", "objective_ratio"),
        options=(
            Option(
                "links",
                "names",
                "links that may carry a counterweight (default: the crank)",
                metavar="LINK",
            ),
            Option(
                "objective",
                "text",
                f"what to minimise: one of {_OBJECTIVES}, or weights name=w,name=w (default: "
                "floor_force_range with a support, else shaking_force_rms)",
            ),
            Option(
                "mass_max",
                "quantity",
                "heaviest counterweight per link (default: the mechanism's moving mass)",
                unit="kg",
            ),
            Option(
                "radius_max",
                "quantity",
                "farthest a counterweight sits from its link's pivot (default: the link's reach)",
                unit="m",
            ),
            Option(
                "support",
                "text",
                "support model file whose load is this mechanism: minimise the floor force on its mounts",
                metavar="FILE",
            ),
            Option("angles", "int", "crank angles per revolution (default: the file's, else 360)", minimum=8),
            Option(
                "max_added_mass",
                "quantity",
                "largest total mass of all the counterweights together (default: each link's limit alone)",
                unit="kg",
            ),
            Option(
                "max_added_inertia",
                "quantity",
                "largest total rotary inertia Σ m r² of the counterweights, each about its link's pivot",
                unit="kg*m^2",
            ),
            Option(
                "slack",
                "float",
                "the lightest design within this fraction of the best objective (default 0: of equal ones)",
                minimum=0.0,
            ),
        ),
        outputs=(
            Output("counterweight_mass_total_kg", "mass of all the counterweights found"),
            Output(
                "counterweight_inertia_total_kg_m2",
                "their rotary inertia Σ m r², each about its link's reference point",
            ),
            Output("max_added_mass_kg", "the total mass allowed (when limited)"),
            Output("max_added_inertia_kg_m2", "the total rotary inertia allowed (when limited)"),
            Output(
                "active_bounds",
                "the bounds and budgets the design sits on (a link's mass or radius, the totals), or none",
                "",
            ),
            Output("objective", "what was minimised (a metric, or a weighted sum of metrics)", ""),
            Output("objective_ratio", "the objective with the counterweights over without", "1"),
            Output(
                "optimality_gap_ratio",
                "an exact design's metric less its certified lower bound, over that bound (slack included)",
                "1",
            ),
            Output("slack_ratio", "the fraction of the best objective given up for less mass", "1"),
            Output(
                "mass_for_90_percent_of_gain_kg",
                "the total mass that buys 90 % of the reduction, from the mass front (linear between rows)",
            ),
            *(
                Output(
                    f"{q}_{s}_{tag}_{u}", f"{s} of the {q.replace('_', ' ')}'s fluctuation {tag} balancing"
                )
                for q, u in (
                    ("shaking_force", "N"),
                    ("shaking_moment", "Nm"),
                    ("driving_torque", "Nm"),
                    ("floor_force", "N"),
                )
                for s in ("rms", "peak", "range")
                for tag in ("before", "after")
            ),
            Output(
                "counterweights",
                "per link: mass_kg, radius_m and angle_deg from its reference point (from_point), x_m, y_m",
                "",
            ),
            Output("method", "how the counterweights were found (exact solve, or SLSQP from it)", ""),
            Output("exact", "whether the design is the exact optimum of the linear problem", ""),
            Output("setup_time_s", "time to build the linear maps (one inverse dynamics)"),
            Output("solve_time_s", "time to optimise"),
        ),
        examples=(
            "mechdyn balance examples/press_link_drive.toml --links crank rocker --radius-max '1.5 m'",
            "mechdyn balance examples/press_link_drive.toml --support examples/press_on_mounts.toml "
            "--links crank rocker --mass-max '60 t' --radius-max '1.5 m'",
            "mechdyn balance examples/fourbar.toml --links crank rocker --objective shaking_force_rms=1,"
            "driving_torque_rms=0.5",
            "mechdyn balance examples/press_link_drive.toml --support examples/press_on_mounts.toml "
            "--links crank rocker --mass-max '60 t' --radius-max '1.5 m' --objective floor_force_peak "
            "--max-added-mass '40 t'",
        ),
    )
)
