"""The tables of a mount analysis (:meth:`mechdyn.mounts.analysis.MountResult.tables`)."""

from __future__ import annotations

from typing import Any, Protocol

from mechdyn.results import Table
from mechdyn.units import convert, key_label, readable, readable_unit

__all__ = ["isolation_verdict", "mount_tables"]


class MountData(Protocol):
    """What the tables read of a mount analysis (:class:`mechdyn.mounts.analysis.MountResult`): the
    result is passed as it is.

    Attributes
    ----------
    name : str
        The mount.
    kind : str
        Its type (``"bolted"``, ``"pad"``, …).
    data : dict
        The figures, SI units by their keys (``stiffness_N_per_m``, ``breakdown``, ``fe_convergence``,
        ``contact``, ``calibration``, ``frf_fit``, ``isolation`` where they apply).
    """

    @property
    def name(self) -> str: ...
    @property
    def kind(self) -> str: ...
    @property
    def data(self) -> dict[str, Any]: ...


def _rows(d: dict[str, Any]) -> list[list[Any]]:
    """The scalar and text parts of a breakdown as (quantity, value, unit) rows, in words, each value
    in the unit its size reads best in (:func:`mechdyn.units.readable`: kN/mm, MPa, mm)."""
    rows = []
    for k, v in d.items():
        label, unit = key_label(k)
        if isinstance(v, bool):
            v = "yes" if v else "no"
        elif isinstance(v, float):
            v, unit = readable(v, unit)
        elif not isinstance(v, (int, str)):
            continue
        rows.append([label, v, unit])
    return rows


_LONG = 40  # a text longer than this is a sentence: it goes under the table, not into a cell


def _table(title: str, rows: list[list[Any]], note: str = "") -> Table:
    """A (quantity, value, unit) table whose sentences (a provenance, a verdict) are written under it."""
    sentences = [f"{r[0]}: {r[1]}" for r in rows if isinstance(r[1], str) and len(r[1]) > _LONG]
    kept = [r for r in rows if not (isinstance(r[1], str) and len(r[1]) > _LONG)]
    return Table(
        title, ["quantity", "value", "unit"], kept, " ".join([*(s + "." for s in sentences), note]).strip()
    )


def isolation_verdict(transmissibility: float, frequency_ratio: float | None = None) -> str:
    """What a mount does to the disturbing force, as a sentence: isolates (T < 1), amplifies (T > 1),
    or passes it almost unchanged (T within 0.5 % of 1, where "amplifies 1.00 times" would say
    nothing): near the crossover at √2 times the natural frequency, or, with the disturbing frequency
    below the natural frequency, because the mount is quasi-static there.

    Parameters
    ----------
    transmissibility : float
        T, the amplitude of the force on the floor over the disturbing force.
    frequency_ratio : float, optional
        r, the disturbing frequency over the (lowest) natural frequency, dimensionless; without it, T
        near 1 is taken as the crossover.
    """
    T = transmissibility
    if abs(T - 1.0) < 5e-3:
        if frequency_ratio is not None and frequency_ratio < 1:
            return (
                f"passes the disturbing force to the floor almost unchanged (transmissibility {T:.4f}): "
                "the disturbing frequency is far below the natural frequency (quasi-static); only a much "
                "softer mount would isolate"
            )
        return (
            f"passes the disturbing force to the floor almost unchanged (transmissibility {T:.4f}): the "
            "disturbing frequency is near √2 times the natural frequency; a softer mount would isolate"
        )
    if T < 1:
        return f"isolates: {100 * (1 - T):.0f} % of the disturbing force is kept from the floor"
    return (
        f"amplifies: the floor gets {T:.2f} times the disturbing force (the disturbing frequency is below "
        "√2 times the natural frequency; a softer mount would isolate)"
    )


def mount_tables(
    result: MountData,
    length_unit: str = "mm",
    pressure_unit: str = "MPa",
    stiffness_unit: str | None = None,
) -> list[Table]:
    """The estimate, frusta, FE convergence, contact pressure, calibration, FRF fit and isolation,
    lengths, pressures and stiffnesses in the given display units (a stiffness, by default, in the unit
    the mount's own stiffness reads best in: kN/mm for most).

    Parameters
    ----------
    result : MountResult
        The mount analysis (or anything with what :class:`MountData` names).
    length_unit, pressure_unit : str
        Display units of lengths (default mm) and pressures (default MPa).
    stiffness_unit : str, optional
        Display unit of stiffnesses (default: the one the mount's stiffness reads best in).

    Returns
    -------
    list of Table
    """
    s = result.data
    stiffness_unit = stiffness_unit or readable_unit(s["stiffness_N_per_m"], "N/m")[0]

    def K(v: float) -> float:
        return float(convert(v, "N/m", stiffness_unit))

    def L(v: float | None) -> float | None:
        return None if v is None else float(convert(v, "m", length_unit))

    def P(v: float) -> float:
        return float(convert(v, "Pa", pressure_unit))

    tables = [
        _table(
            f"{result.name} ({result.kind})",
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
        tables.append(_table("calibration", _rows(s["calibration"])))
    if "frf_fit" in s:
        tables.append(_table("fit to the measured FRF", _rows(s["frf_fit"])))
    if "isolation" in s:
        iso = s["isolation"]
        verdict = "The mount " + isolation_verdict(iso["transmissibility"], iso.get("frequency_ratio")) + "."
        tables.append(
            Table("isolation on the given load", ["quantity", "value", "unit"], _rows(iso), verdict)
        )
    return tables
