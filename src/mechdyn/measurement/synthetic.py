"""Synthetic measurements: the FRFs of a known model at measurement points, spoiled by test noise.

For checks of the identification and the updating against a model whose parameters are known, and
for making example data: H(ω) = B_out (K − ω²M + iωC)⁻¹ B_refᵀ (the direct receptance of the
model's matrices, Ewins, *Modal Testing*, 2nd ed., 2000, §2.5), turned into mobility or accelerance,
with multiplicative complex Gaussian noise and an additive floor relative to each channel's peak
(the leakage and averaging errors of a hammer test, Ewins §3.9).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from mechdyn.measurement.compare import Target, observation_matrix
from mechdyn.measurement.data import MeasuredFRF

__all__ = ["model_matrices", "simulate_frf"]


def model_matrices(model: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[str, ...]]:
    """The mass, stiffness and damping matrices of a model, dense, with its coordinates' names.

    Parameters
    ----------
    model : MountedMachine or Drivetrain
        A machine on mounts (:class:`mechdyn.support.MountedMachine`: kg, N/m, N·s/m over x … rz) or a
        drivetrain (:class:`mechdyn.drivetrain.Drivetrain`: kg·m², N·m/rad, N·m·s/rad over its disks).

    Returns
    -------
    M, K, C : ndarray
        (n, n) in SI.
    names : tuple of str
        The coordinates.

    Raises
    ------
    TypeError
        For another kind of model, naming the two it takes.
    """
    if hasattr(model, "stiffness_matrix") and hasattr(model, "dofs"):
        M, K, C = (
            np.asarray(m, dtype=float)
            for m in (model.mass_matrix, model.stiffness_matrix, model.damping_matrix)
        )
        return M, K, C, tuple(model.dofs)
    if hasattr(model, "dof_names"):
        from mechdyn.drivetrain.assembly import assemble

        asm = assemble(model)
        M, K, C = (
            np.asarray(a.toarray() if hasattr(a, "toarray") else a, dtype=float)
            for a in (asm.M, asm.K, asm.C)
        )
        return M, K, C, tuple(model.dof_names)
    raise TypeError(
        f"simulate_frf takes a MountedMachine or a Drivetrain, not a {type(model).__name__}; give the "
        "matrices of another model through a model object with mass_matrix, stiffness_matrix, "
        "damping_matrix and dofs"
    )


def simulate_frf(
    model: Any,
    outputs: Sequence[tuple[str, str]],
    references: Sequence[tuple[str, str]],
    frequencies_hz: Sequence[float],
    mapping: Mapping[str, Target] | None = None,
    *,
    kind: str = "accelerance",
    relative_noise: float = 0.01,
    noise_floor: float = 1e-3,
    seed: int | np.random.Generator | None = 0,
) -> MeasuredFRF:
    """The FRFs of a model at measurement points, with hammer-test noise.

    Parameters
    ----------
    model : MountedMachine or Drivetrain
        The known model (see :func:`model_matrices`).
    outputs, references : sequence of (point, direction)
        The responses and the excitations, as a file names them.
    frequencies_hz : sequence of float
        Frequency lines, Hz (equally spaced for :func:`mechdyn.measurement.identify_modes`).
    mapping : mapping, optional
        Measurement point → model coordinate or location (x, y, z) in m
        (:func:`mechdyn.measurement.observation_matrix`).
    kind : {"accelerance", "mobility", "receptance"}
        What the outputs measure: accelerance m/(s²·N), mobility m/(s·N) or receptance m/N.
    relative_noise : float
        Standard deviation of the multiplicative complex noise, 1 (0.01: 1 % of each value).
    noise_floor : float
        Standard deviation of the additive complex noise, as a fraction of each channel's peak
        magnitude, 1.
    seed : int or numpy Generator, optional
        The noise's seed (reproducible data).

    Returns
    -------
    MeasuredFRF
        Source ``"synthetic"``.
    """
    if kind not in ("accelerance", "mobility", "receptance"):
        raise ValueError(f"kind {kind!r} must be accelerance, mobility or receptance")
    if relative_noise < 0 or noise_floor < 0:
        raise ValueError(
            f"relative_noise {relative_noise!r} and noise_floor {noise_floor!r} must be ≥ 0 (0: no noise)"
        )
    M, K, C, names = model_matrices(model)
    B_out = observation_matrix(names, tuple(outputs), mapping or {})
    B_ref = observation_matrix(names, tuple(references), mapping or {})
    w = 2.0 * np.pi * np.asarray(frequencies_hz, dtype=float)
    H = np.linalg.inv(K[None] - w[:, None, None] ** 2 * M[None] + 1j * w[:, None, None] * C[None])
    H = np.einsum("oi,fij,rj->for", B_out, H, B_ref)
    H = H * ((1j * w) ** {"receptance": 0, "mobility": 1, "accelerance": 2}[kind])[:, None, None]
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)

    def complex_normal() -> np.ndarray:
        return (rng.standard_normal(H.shape) + 1j * rng.standard_normal(H.shape)) / np.sqrt(2.0)

    peak = np.abs(H).max(axis=0, keepdims=True)
    noisy = H * (1.0 + relative_noise * complex_normal()) + noise_floor * peak * complex_normal()
    return MeasuredFRF(w, noisy, tuple(outputs), tuple(references), kind, "synthetic")
