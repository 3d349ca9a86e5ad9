"""The tables of a mount analysis (:meth:`mechdyn.mounts.analysis.MountResult.tables`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from mechdyn.results import Table
from mechdyn.units import convert, key_label

if TYPE_CHECKING:
    from mechdyn.mounts.analysis import MountResult

__all__ = ["mount_tables"]


def _rows(d: dict[str, Any]) -> list[list[Any]]:
    """The scalar and text parts of a breakdown as (quantity, value, unit) rows, in words."""
    rows = []
    for k, v in d.items():
        if isinstance(v, bool):
            v = "yes" if v else "no"
        elif not isinstance(v, (int, float, str)):
            continue
        label, unit = key_label(k)
        rows.append([label, v, unit])
    return rows


def mount_tables(
    result: MountResult, length_unit: str = "mm", pressure_unit: str = "MPa", stiffness_unit: str = "N/m"
) -> list[Table]:
    """The estimate, frusta, FE convergence, contact pressure, calibration, FRF fit and isolation,
    lengths, pressures and stiffnesses in the given display units."""
    s = result.data

    def K(v: float) -> float:
        return float(convert(v, "N/m", stiffness_unit))

    def L(v: float | None) -> float | None:
        return None if v is None else float(convert(v, "m", length_unit))

    def P(v: float) -> float:
        return float(convert(v, "Pa", pressure_unit))

    tables = [
        Table(
            f"{result.name} ({result.kind})",
            ["quantity", "value", "unit"],
            [
                ["stiffness along the main axis", K(s["stiffness_N_per_m"]), stiffness_unit],
                *_rows({"adjusts_height": s["adjusts_height"], "damps": s["damps"]}),
                *_rows(s["breakdown"]),
            ],
        )
    ]
    frusta = s["breakdown"].get("frusta") if isinstance(s["breakdown"], dict) else None
    if frusta:
        tables.append(
            Table(
                "pressure-cone frusta (in series)",
                ["layer", "material", f"t [{length_unit}]", f"D [{length_unit}]", f"k [{stiffness_unit}]"],
                [
                    [
                        f["layer"] + 1,
                        f["material"],
                        L(f["thickness_m"]),
                        L(f["diameter_m"]),
                        K(f["stiffness_N_per_m"]),
                    ]
                    for f in frusta
                ],
            )
        )
    if "fe_convergence" in s:
        tables.append(
            Table(
                "finite-element reference (mesh convergence)",
                [
                    "elements through thickness",
                    "elements",
                    "unknowns",
                    f"stiffness [{stiffness_unit}]",
                    "observed order",
                    f"extrapolated [{stiffness_unit}]",
                ],
                [
                    [
                        r["elements_through_thickness"],
                        r["elements"],
                        r["dofs"],
                        K(r["stiffness_N_per_m"]),
                        r.get("observed_order_ratio"),
                        None if r.get("extrapolated_N_per_m") is None else K(r["extrapolated_N_per_m"]),
                    ]
                    for r in s["fe_convergence"]
                ],
            )
        )
    if "contact" in s:
        tables.append(
            Table(
                "contact pressure, base plate on concrete",
                [
                    "preload [N]",
                    f"max [{pressure_unit}]",
                    f"under the washer [{pressure_unit}]",
                    f"above threshold to r [{length_unit}]",
                ],
                [
                    [
                        c["preload_N"],
                        P(c["pressure_max_Pa"]),
                        P(c["head_pressure_Pa"]),
                        L(c["radius_above_threshold_m"]),
                    ]
                    for c in s["contact"]
                ],
            )
        )
    if "calibration" in s:
        tables.append(Table("calibration", ["quantity", "value", "unit"], _rows(s["calibration"])))
    if "frf_fit" in s:
        tables.append(Table("fit to the measured FRF", ["quantity", "value", "unit"], _rows(s["frf_fit"])))
    if "isolation" in s:
        iso = s["isolation"]
        T = iso["transmissibility"]
        verdict = (
            f"isolates: {100 * (1 - T):.0f} % of the disturbing force is kept from the floor"
            if T < 1
            else f"amplifies: the floor gets {T:.2f} times the disturbing force (the disturbing frequency "
            "is below √2 times the natural frequency; a softer mount would isolate)"
        )
        rows = [*_rows(iso), ["verdict", verdict, ""]]
        tables.append(Table("isolation on the given load", ["quantity", "value", "unit"], rows))
    return tables
