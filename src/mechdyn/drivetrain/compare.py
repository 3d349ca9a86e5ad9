"""Rigid-gear against flexible-mesh modes, paired by shape (MAC) rather than by index."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.optimize import linear_sum_assignment

from mechdyn.checks import check_array, check_number
from mechdyn.drivetrain.modal import ModalResult, modal
from mechdyn.drivetrain.model import Drivetrain
from mechdyn.errors import ModelError
from mechdyn.results import Result, Table

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["ModeComparison", "compare_rigid", "mac"]

#: Pairs with a MAC below this are not taken as the same mode.
MAC_THRESHOLD = 0.5


def _unit_columns(x: np.ndarray) -> np.ndarray:
    peak = np.abs(x).max(axis=0, initial=0.0)
    return x / np.where(peak == 0, 1.0, peak)


def mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Modal assurance criterion between the columns of ``a`` and ``b``.

    ``MAC_ij = |a_iᵀ b_j|² / ((a_iᵀ a_i)(b_jᵀ b_j))`` (Allemang & Brown, 1982; Allemang, *Sound and
    Vibration* 37(8), 2003). 1 for identical shapes up to scale, 0 for orthogonal ones.

    Parameters
    ----------
    a, b : ndarray
        Mode shapes as columns, (n, m_a) and (n, m_b), in any one unit (rad for disk angles); finite,
        of any scale (each column is scaled to its largest entry first).

    Returns
    -------
    ndarray
        (m_a, m_b) MAC values, dimensionless, in [0, 1].

    Raises
    ------
    mechdyn.errors.ModelError
        For a NaN or an infinity in the shapes, or shapes whose rows do not match.
    """
    a = check_array("mac", "a", a, bounded=False, what="mode shape entries")
    b = check_array("mac", "b", b, bounded=False, what="mode shape entries")
    if a.ndim != 2 or b.ndim != 2 or a.shape[0] != b.shape[0]:
        raise ModelError(
            f"shapes {a.shape} and {b.shape}: give mode shapes as columns of two (n, m) arrays with the "
            "same n",
            element="mac",
            field="a",
        )
    a, b = _unit_columns(a), _unit_columns(b)  # MAC is scale-free; this keeps the squares finite
    num = np.abs(a.T @ b) ** 2
    den = np.outer(np.sum(a * a, axis=0), np.sum(b * b, axis=0))
    return num / np.where(den == 0, 1.0, den)


@dataclass(frozen=True, repr=False)  # the short repr of Result
class ModeComparison(Result):
    """Flexible-mesh modes next to the rigid-gear modes of the same shape.

    Attributes
    ----------
    flexible, rigid : ModalResult
    mac : ndarray
        (n_flexible, n_rigid) MAC between the full-disk shapes.
    pairs : tuple of (int, int or None)
        For each flexible mode, the rigid mode of the same shape (0-based), or None when no rigid
        mode matches (mesh modes, which a rigid-gear model cannot show).
    """

    flexible: ModalResult
    rigid: ModalResult
    mac: np.ndarray
    pairs: tuple[tuple[int, int | None], ...]

    @property
    def rows(self) -> list[dict[str, Any]]:
        """Table rows: flexible mode, its frequency, the paired rigid mode and frequency, MAC, change."""
        out = []
        f_flex, f_rig = self.flexible.frequencies_hz, self.rigid.frequencies_hz
        for i, j in self.pairs:
            row: dict[str, Any] = {"flexible_mode": i + 1, "flexible_hz": float(f_flex[i])}
            if j is None:
                row.update(
                    rigid_mode=None,
                    rigid_hz=None,
                    mac=float(self.mac[i].max(initial=0.0)),
                    change_percent=None,
                )
            else:
                row.update(
                    rigid_mode=j + 1,
                    rigid_hz=float(f_rig[j]),
                    mac=float(self.mac[i, j]),
                    change_percent=float(100 * (f_flex[i] / f_rig[j] - 1)),
                )
            row["dominant_element"] = self.flexible.dominant_element(i)[0]
            out.append(row)
        return out

    def summary(self) -> dict[str, Any]:
        """The flexible model's modal summary, the pairing rows and the rigid-gear frequencies (Hz)."""
        return self.flexible.summary() | {
            "comparison": self.rows,
            "rigid_frequencies_hz": self.rigid.frequencies_hz.tolist(),
        }

    def tables(self, **display_units: str) -> list[Table]:
        """The flexible model's tables, then the pairing."""
        pairing = Table(
            "flexible meshes against rigid gears (modes paired by shape, MAC)",
            [
                "flexible mode",
                "flexible [Hz]",
                "rigid mode",
                "rigid [Hz]",
                "MAC",
                "change [%]",
                "most strain energy in",
            ],
            [
                [
                    c["flexible_mode"],
                    c["flexible_hz"],
                    c["rigid_mode"],
                    c["rigid_hz"],
                    c["mac"],
                    c["change_percent"],
                    c["dominant_element"],
                ]
                for c in self.rows
            ],
        )
        return [*self.flexible.tables(**display_units), pairing]

    def plots(self, **display_units: str) -> dict[str, Any]:
        """The flexible and the rigid-gear mode shapes."""
        return {
            "mode_shapes.png": lambda: self.flexible.plot(),
            "mode_shapes_rigid.png": lambda: self.rigid.plot(),
        }

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        return self.flexible.arrays() | {"mac": (self.mac, "")}

    def to_frame(self) -> pd.DataFrame:
        """One row per flexible mode with its rigid-gear partner (frequencies in Hz, MAC as a ratio)."""
        import pandas as pd

        frame = pd.DataFrame(self.rows).rename(columns={"mac": "mac_ratio"})
        frame["rigid_mode"] = frame["rigid_mode"].astype("Int64")  # None where no rigid mode matches
        return frame


def compare_rigid(drivetrain: Drivetrain, *, threshold: float = MAC_THRESHOLD) -> ModeComparison:
    """Compare the flexible-mesh model with its rigid-gear version, pairing modes by MAC.

    Parameters
    ----------
    drivetrain : Drivetrain
        The model as given (its flexible meshes stay flexible).
    threshold : float
        Lowest MAC accepted as "the same mode", dimensionless, between 0 and 1.

    Returns
    -------
    ModeComparison

    Notes
    -----
    The pairing maximises the total MAC over one-to-one assignments (Hungarian algorithm,
    :func:`scipy.optimize.linear_sum_assignment`); assigned pairs below ``threshold`` are left
    unpaired.
    """
    threshold = check_number("compare_rigid", "threshold", threshold, low=0.0, high=1.0, what="MAC threshold")
    flexible = modal(drivetrain)
    rigid = modal(drivetrain, rigid_gears=True)
    m = mac(flexible.shapes, rigid.shapes)
    pairs: dict[int, int | None] = dict.fromkeys(range(m.shape[0]))
    if m.size:
        rows, cols = linear_sum_assignment(-m)
        for i, j in zip(rows, cols, strict=True):
            if m[i, j] >= threshold:
                pairs[int(i)] = int(j)
    return ModeComparison(flexible, rigid, m, tuple(pairs.items()))
