"""Model against measurement: measured points mapped to model coordinates, modes paired by MAC,
frequency and damping errors.

Pairing maximises the summed modal assurance criterion over one-to-one pairs (the assignment problem,
Hungarian method: :func:`scipy.optimize.linear_sum_assignment`); a pair below ``min_mac`` is left
unpaired (Friswell & Mottershead, *Finite Element Model Updating in Structural Dynamics*, 1995, §3.3).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.measurement.data import DIRECTIONS
from mechdyn.measurement.identify import IdentifiedModes, mac

__all__ = ["ModeComparison", "compare_modes", "observation_matrix"]

Target = str | Sequence[float]


def observation_matrix(
    coordinate_names: Sequence[str], outputs: Sequence[tuple[str, str]], mapping: Mapping[str, Target]
) -> np.ndarray:
    """Rows that turn the model's coordinates into the measured outputs.

    Parameters
    ----------
    coordinate_names : sequence of str
        The model's coordinates (``Modes.coordinate_names``): disks of a drivetrain, or the rigid
        body's ``"x" … "rz"`` of a machine on mounts.
    outputs : sequence of (point, direction)
        The measured outputs.
    mapping : mapping of point name to target
        A model coordinate's name (the output is that coordinate, whatever its measured direction;
        e.g. ``{"p3": "d3"}`` for a torsional pickup on disk d3), or a point (x, y, z) in m in the
        machine's coordinates for a rigid-body model: the output is the point's motion along its
        direction, u = t + θ × r (rotations: θ). A point missing from the mapping is taken as a
        coordinate of the same name.

    Returns
    -------
    ndarray
        (n_out, n_coordinates).

    Raises
    ------
    KeyError
        A point that maps to no coordinate, or a location on a model that is not a rigid body.
    """
    names = list(coordinate_names)
    rows = np.zeros((len(outputs), len(names)))
    for i, (point, direction) in enumerate(outputs):
        target = mapping.get(point, point)
        if isinstance(target, str):
            if target not in names:
                raise KeyError(
                    f"measurement point {point!r} maps to {target!r}, which is not a model coordinate; "
                    f"expected one of {names} or a location (x, y, z) in m"
                )
            rows[i, names.index(target)] = 1.0
            continue
        if not set(names) <= set(DIRECTIONS):
            raise KeyError(
                f"measurement point {point!r} is mapped to a location, but the model's coordinates {names} "
                "are not rigid-body coordinates; map it to a coordinate name"
            )
        x, y, z = (float(v) for v in target)
        full = {  # u = t + θ × r, per measured direction, over (x, y, z, rx, ry, rz)
            "x": (1, 0, 0, 0, z, -y),
            "y": (0, 1, 0, -z, 0, x),
            "z": (0, 0, 1, y, -x, 0),
            "rx": (0, 0, 0, 1, 0, 0),
            "ry": (0, 0, 0, 0, 1, 0),
            "rz": (0, 0, 0, 0, 0, 1),
        }[direction]
        rows[i] = [full[DIRECTIONS.index(c)] for c in names]
    return rows


def _model_damping(model: Any) -> np.ndarray | None:
    """Modal damping ratios ζ_k = φ_kᵀ C φ_k / (2 ω_k) of mass-normalised shapes, where C is known."""
    C: Any = None
    phi: Any = None
    if hasattr(model, "machine"):
        C, phi = np.asarray(model.machine.damping_matrix), model.shapes
    elif hasattr(model, "assembly"):
        C, phi = model.assembly.C, model.reduced_shapes
    if C is None or not np.any(C.toarray() if hasattr(C, "toarray") else C):
        return None
    w = np.where(model.omega == 0, 1.0, model.omega)
    return np.asarray(np.einsum("ik,ik->k", phi, C @ phi) / (2.0 * w))


@dataclass(frozen=True, repr=False)
class ModeComparison:
    """Measured modes paired with a model's, with the MAC matrix and the errors.

    Attributes
    ----------
    mac : ndarray
        (n_measured, n_model) MAC between the measured shapes and the model's shapes at the outputs.
    pairs : ndarray
        (n_pairs, 2) index pairs: the indices (measured, model) of the paired modes, by measured frequency.
    measured_hz, model_hz : ndarray
        (n_pairs,) frequencies of the paired modes, Hz.
    measured_damping, model_damping : ndarray
        (n_pairs,) damping ratios, 1 (model: NaN where the model has no damping matrix).
    measured_scatter_hz : ndarray
        (n_pairs,) scatter of the measured frequency over the stable poles, Hz.
    """

    mac: np.ndarray
    pairs: np.ndarray
    measured_hz: np.ndarray
    model_hz: np.ndarray
    measured_damping: np.ndarray
    model_damping: np.ndarray
    measured_scatter_hz: np.ndarray

    @property
    def paired_mac(self) -> np.ndarray:
        """(n_pairs,) MAC of each pair."""
        return self.mac[self.pairs[:, 0], self.pairs[:, 1]] if self.pairs.size else np.zeros(0)

    @property
    def frequency_error(self) -> np.ndarray:
        """(n_pairs,) relative error of the model, (f_model − f_measured) / f_measured, 1."""
        return (self.model_hz - self.measured_hz) / self.measured_hz

    @property
    def damping_error(self) -> np.ndarray:
        """(n_pairs,) relative error of the model's damping ratio, 1 (NaN without model damping)."""
        return (self.model_damping - self.measured_damping) / self.measured_damping

    def residuals(self, *, shape_weight: float = 1.0) -> np.ndarray:
        """The residual vector of model updating: relative frequency errors, then weighted 1 − MAC.

        Parameters
        ----------
        shape_weight : float
            Weight factor of the shape residuals against the frequency residuals, dimensionless.
        """
        return np.concatenate([self.frequency_error, shape_weight * (1.0 - self.paired_mac)])

    def summary(self) -> dict[str, Any]:
        """Paired frequencies (Hz), errors (%) and MAC, one list entry per pair."""
        return {
            "paired_modes": len(self.pairs),
            "measured_frequencies_hz": [float(v) for v in self.measured_hz],
            "model_frequencies_hz": [float(v) for v in self.model_hz],
            "frequency_error_percent": [float(100 * v) for v in self.frequency_error],
            "damping_error_percent": [float(100 * v) for v in self.damping_error],
            "mac": [float(v) for v in self.paired_mac],
        }

    def to_frame(self) -> Any:
        """One row per pair."""
        import pandas as pd

        return pd.DataFrame(
            {
                "measured_mode": self.pairs[:, 0],
                "model_mode": self.pairs[:, 1],
                "measured_hz": self.measured_hz,
                "measured_scatter_hz": self.measured_scatter_hz,
                "model_hz": self.model_hz,
                "frequency_error_percent": 100 * self.frequency_error,
                "measured_damping": self.measured_damping,
                "model_damping": self.model_damping,
                "damping_error_percent": 100 * self.damping_error,
                "mac": self.paired_mac,
            }
        )

    def plot(self, ax: Any = None) -> Any:
        """The MAC matrix as an image (measured modes down, model modes across).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw (a new figure when None).

        Returns
        -------
        matplotlib Axes
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(5, 4.5))
        im = ax.imshow(self.mac, vmin=0, vmax=1, cmap="viridis", origin="upper")
        ax.set_xlabel("model mode")
        ax.set_ylabel("measured mode")
        ax.figure.colorbar(im, ax=ax, label="MAC")
        return ax


def compare_modes(
    measured: IdentifiedModes,
    model: Any,
    mapping: Mapping[str, Target] | None = None,
    *,
    model_damping: Sequence[float] | None = None,
    min_mac: float = 0.5,
    pairs: np.ndarray | None = None,
) -> ModeComparison:
    """Pair measured modes with a model's by MAC and report frequency and damping errors.

    Parameters
    ----------
    measured : IdentifiedModes
        From :func:`identify_modes`.
    model : Modes
        A modal result with ``omega`` (rad/s), mass-normalised ``shapes`` and ``coordinate_names``:
        :func:`mechdyn.support.modes` or :func:`mechdyn.drivetrain.modal`.
    mapping : mapping, optional
        Measurement point → model coordinate or location, see :func:`observation_matrix`.
    model_damping : sequence of float, optional
        The model's modal damping ratios; by default ζ_k = φ_kᵀ C φ_k / (2 ω_k) from the model's
        damping matrix (the machine's mounts, the drivetrain's dampers), the proportional-damping
        approximation.
    min_mac : float
        Pairs with a smaller MAC are left unpaired, dimensionless.
    pairs : ndarray, optional
        (n_pairs, 2) index pairs (measured, model) to keep instead of pairing anew, e.g. those of a
        first comparison while a model is updated, so that the residuals keep their order.

    Returns
    -------
    ModeComparison
    """
    from scipy.optimize import linear_sum_assignment

    B = observation_matrix(model.coordinate_names, measured.outputs, mapping or {})
    at_outputs = B @ np.asarray(model.shapes)
    m = mac(measured.shapes, at_outputs)
    if pairs is None:
        rows, cols = linear_sum_assignment(-m) if m.size else (np.zeros(0, int), np.zeros(0, int))
        keep = m[rows, cols] >= min_mac
        pairs = np.column_stack([rows[keep], cols[keep]]).astype(int).reshape(-1, 2)
        pairs = pairs[np.argsort(pairs[:, 0])]
    else:
        pairs = np.asarray(pairs, dtype=int).reshape(-1, 2)
    zeta = np.asarray(model_damping, float) if model_damping is not None else _model_damping(model)
    i, j = pairs[:, 0], pairs[:, 1]
    return ModeComparison(
        mac=m,
        pairs=pairs,
        measured_hz=measured.frequencies_hz[i],
        model_hz=np.asarray(model.omega)[j] / (2.0 * np.pi),
        measured_damping=measured.damping[i],
        model_damping=zeta[j] if zeta is not None else np.full(len(j), np.nan),
        measured_scatter_hz=measured.frequency_scatter_hz[i],
    )
