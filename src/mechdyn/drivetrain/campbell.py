"""Campbell (interference) diagram: excitation orders against natural frequencies over a speed range."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.checks import check_array
from mechdyn.drivetrain.modal import ModalResult, modal
from mechdyn.drivetrain.model import Drivetrain
from mechdyn.errors import ModelError
from mechdyn.results import Result, Table
from mechdyn.units import convert, si_field

if TYPE_CHECKING:
    import pandas as pd

MAX_ORDER = 1e4
"""The highest excitation order a Campbell diagram draws (of a shaft's speed or a mesh's tooth-passing)."""

__all__ = ["CampbellResult", "ExcitationLine", "campbell"]


@dataclass(frozen=True)
class ExcitationLine:
    """An excitation whose frequency is proportional to the reference speed.

    Attributes
    ----------
    label : str
        E.g. ``"1× shaft line 3–4"``, ``"1× mesh frequency of G1 (24/96 teeth)"``, or for coinciding
        lines ``"1× shaft lines 1–2, 3–5"``.
    kind : {"shaft", "mesh"}
    per_rev : float
        Excitation cycles per revolution of the reference disk.
    """

    label: str
    kind: str
    per_rev: float

    def frequency_hz(self, speed_rad_s: np.ndarray | float) -> np.ndarray:
        """Excitation frequency, Hz, at reference speeds in rad/s."""
        return self.per_rev * np.asarray(speed_rad_s) / (2.0 * np.pi)


@dataclass(frozen=True, repr=False)  # the short repr of Result
class CampbellResult(Result):
    """Excitation lines and natural frequencies over a reference speed range.

    Attributes
    ----------
    modal : ModalResult
    reference : str
        The disk whose speed is the abscissa.
    speed_range : (float, float)
        Reference speeds, rad/s.
    lines : tuple of ExcitationLine
    """

    modal: ModalResult
    reference: str
    speed_range: tuple[float, float]
    lines: tuple[ExcitationLine, ...]

    @property
    def crossings(self) -> list[dict[str, Any]]:
        """Every intersection of an excitation line with a natural frequency inside the range.

        Each item has ``line``, ``kind``, ``mode`` (1-based), ``frequency_hz`` and ``speed_rpm``
        (reference speed at the crossing), sorted by speed.
        """
        lo, hi = self.speed_range
        out = []
        for line in self.lines:
            for m, f in enumerate(self.modal.frequencies_hz):
                speed = 2.0 * np.pi * f / line.per_rev
                if lo <= speed <= hi:
                    out.append(
                        {
                            "line": line.label,
                            "kind": line.kind,
                            "mode": m + 1,
                            "frequency_hz": float(f),
                            "speed_rpm": float(convert(speed, "rad/s", "rpm")),
                        }
                    )
        return sorted(out, key=lambda c: c["speed_rpm"])

    def to_frame(self) -> pd.DataFrame:
        """The crossings as a table."""
        import pandas as pd

        return pd.DataFrame(self.crossings, columns=["line", "kind", "mode", "frequency_hz", "speed_rpm"])

    @property
    def speed_range_rpm(self) -> tuple[float, float]:
        """The reference speed range, rpm."""
        lo, hi = convert(np.asarray(self.speed_range), "rad/s", "rpm")
        return float(lo), float(hi)

    def summary(self) -> dict[str, Any]:
        """Reference disk, speed range (rpm), natural frequencies (Hz), excitation lines, crossings."""
        return {
            "reference_disk": self.reference,
            "speed_range_rpm": list(self.speed_range_rpm),
            "frequencies_hz": self.modal.frequencies_hz.tolist(),
            "rigid_body_modes": self.modal.rigid_body_modes,
            "lines": [{"label": ln.label, "kind": ln.kind, "per_rev": ln.per_rev} for ln in self.lines],
            "crossings": self.crossings,
        }

    def tables(self, **display_units: str) -> list[Table]:
        """The excitation lines and their crossings with the natural frequencies; the model as assembled."""
        from mechdyn.drivetrain.summary import model_table

        lo, hi = self.speed_range_rpm
        return [
            Table(
                f"excitation lines (reference disk {self.reference})",
                ["line", "kind", "cycles per rev", f"at {hi:.0f} rpm [Hz]"],
                [
                    [ln.label, ln.kind, ln.per_rev, float(ln.frequency_hz(self.speed_range[1]))]
                    for ln in self.lines
                ],
            ),
            Table(
                f"crossings with natural frequencies between {lo:.0f} and {hi:.0f} rpm"
                + ("" if self.crossings else f": none ({self._why_no_crossing()})"),
                ["line", "mode", "frequency [Hz]", "speed [rpm]"],
                [[x["line"], x["mode"], x["frequency_hz"], x["speed_rpm"]] for x in self.crossings],
            ),
            model_table(self.modal.drivetrain),
        ]

    def _why_no_crossing(self) -> str:
        """Why no excitation line meets a natural frequency in the speed range, in words."""
        freqs = self.modal.frequencies_hz
        if not freqs.size:
            return "the model has no flexible mode"
        top = max((float(ln.frequency_hz(self.speed_range[1])) for ln in self.lines), default=0.0)
        reason = (
            f"the highest line reaches {top:.4g} Hz, below the lowest natural frequency, {freqs[0]:.4g} Hz"
        )
        meshes = [e for e in self.modal.drivetrain.elements if hasattr(e, "teeth")]
        untoothed = [e.name for e in meshes if e.teeth is None]
        if untoothed and not any(ln.kind == "mesh" for ln in self.lines):
            reason += f"; no gear-mesh orders: {', '.join(untoothed)} give no teeth"
        return reason

    def plots(self, **display_units: str) -> dict[str, Any]:
        """``campbell.png``."""
        from mechdyn.drivetrain.plots import plot_campbell

        return {"campbell.png": lambda: plot_campbell(self)}

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        return {"frequencies_hz": (self.modal.frequencies_hz, "Hz")}

    def plot(self, ax: Any = None, max_frequency_hz: float | None = None, **display_units: str) -> Any:
        """Draw the Campbell diagram; returns the matplotlib Figure.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw on (default: a new figure).
        max_frequency_hz : float, optional
            Upper limit of the frequency axis, Hz (default: a little above the highest line).
        **display_units : str
            Display units (the speed axis is in rpm).
        """
        from mechdyn.drivetrain.plots import plot_campbell

        return plot_campbell(self, ax=ax, max_frequency_hz=max_frequency_hz)


def _span(names: Sequence[str]) -> str:
    return names[0] if len(names) == 1 else f"{names[0]}–{names[-1]}"


def campbell(
    drivetrain: Drivetrain,
    speed_range: tuple[Any, Any],
    *,
    reference: str | None = None,
    shaft_orders: Sequence[float] = (1.0,),
    mesh_orders: Sequence[float] = (1.0,),
    modes: ModalResult | None = None,
    rigid_gears: bool = False,
) -> CampbellResult:
    """Campbell diagram of a geared drivetrain.

    Parameters
    ----------
    drivetrain : Drivetrain
    speed_range : (speed, speed)
        Lowest and highest speed of the reference disk (quantities such as ``"3000 rpm"``, or rad/s),
        from 0 to 1e8 rad/s.
    reference : str, optional
        The disk whose speed is given; default the first disk.
    shaft_orders : sequence of float
        Orders of each shaft line's own speed (1 = once per revolution of that line), positive, at
        most :data:`MAX_ORDER` (1e4).
    mesh_orders : sequence of float
        Harmonics of each mesh's tooth-passing frequency (teeth × shaft speed), positive, at most
        :data:`MAX_ORDER`; meshes without teeth have no mesh line.
    modes : ModalResult, optional
        Reuse modes already computed.
    rigid_gears : bool
        Natural frequencies of the rigid-gear model.

    Returns
    -------
    CampbellResult

    Notes
    -----
    Each shaft line (disks joined by shafts) turns at its mean speed ratio to the reference, from
    the mesh ratios (teeth first). The gear-mesh frequency is N_a ω_a/2π = N_b ω_b/2π. Natural
    frequencies of a torsional model without gyroscopic terms do not depend on speed, so the
    crossings are where order × speed equals a natural frequency (the interference diagram of
    torsional analysis, e.g. Friswell et al., *Dynamics of Rotating Machines*, 2010, ch. 9).
    """
    ref = reference or drivetrain.disk_names[0]
    if isinstance(speed_range, str) or len(speed_range) != 2:
        raise ModelError(
            f"speed range {speed_range!r} must be two speeds (low, high)",
            element="campbell",
            field="speed_range",
        )
    lo, hi = (
        si_field("campbell", "speed_range", s, "rad/s", nonnegative=True, what="speed") for s in speed_range
    )
    shaft_orders, mesh_orders = (
        tuple(np.atleast_1d(check_array("campbell", f, v, positive=True, high=MAX_ORDER, what="orders")))
        for f, v in (("shaft_orders", shaft_orders), ("mesh_orders", mesh_orders))
    )
    if not 0 <= lo < hi:
        raise ModelError(
            f"speed range {lo:g}..{hi:g} rad/s must satisfy 0 ≤ low < high",
            element="campbell",
            field="speed_range",
        )
    ratios = drivetrain.speed_ratios(ref)
    idx = drivetrain.disk_index
    lines: list[ExcitationLine] = []
    for names in drivetrain.shaft_lines():
        ratio = ratios[idx[names[0]]]
        if not np.isfinite(ratio):
            continue
        for k in shaft_orders:
            lines.append(ExcitationLine(f"{k:g}× shaft line {_span(names)}", "shaft", k * ratio))
    for mesh in drivetrain.meshes:
        if mesh.teeth is None:
            continue
        ratio = ratios[idx[mesh.disks[0]]]
        if not np.isfinite(ratio):
            continue
        for h in mesh_orders:
            lines.append(
                ExcitationLine(
                    f"{h:g}× mesh frequency of {mesh.name} ({mesh.teeth[0]}/{mesh.teeth[1]} teeth)",
                    "mesh",
                    h * mesh.teeth[0] * ratio,
                )
            )
    result = modes if modes is not None else modal(drivetrain, rigid_gears=rigid_gears)
    return CampbellResult(result, ref, (lo, hi), _merge(lines))


_MESH = "mesh frequency of "


def _merge(lines: list[ExcitationLine]) -> tuple[ExcitationLine, ...]:
    """One line per (kind, cycles per revolution): shaft lines turning at one speed share a line."""
    groups: dict[tuple[str, float], list[ExcitationLine]] = {}
    for line in lines:
        key = (line.kind, round(line.per_rev, 9))
        groups.setdefault(key, []).append(line)
    merged = []
    for (kind, _), same in groups.items():
        if len(same) == 1:
            merged.append(same[0])
            continue
        order = same[0].label.partition(" ")[0]
        noun, prefix = ("shaft lines", "shaft line ") if kind == "shaft" else ("mesh frequency of", _MESH)
        rest = [ln.label.partition(" ")[2].removeprefix(prefix) for ln in same]
        merged.append(ExcitationLine(f"{order} {noun} {', '.join(rest)}", kind, same[0].per_rev))
    return tuple(merged)
