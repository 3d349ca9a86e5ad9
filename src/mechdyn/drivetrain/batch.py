"""Design studies' batch evaluation of the ``modal`` analysis: many variants of one drivetrain, assembled
as a stack and solved by one batched LAPACK call.

A variant changes disks' inertias and elements' stiffnesses given as numbers in the file. Each of these
enters the model linearly: M = Tᵀ diag(J) T on the independent coordinates, K = Σ_e k_e Tᵀ B_e T with
B_e the element's stiffness block for unit stiffness (:meth:`~mechdyn.drivetrain.elements.Element.blocks`
at k_e, divided by k_e). So the stack is the base model's matrices plus each varied value's change
times its unit block, assembled from the model, not from formulas typed here; its eigenvalues are those
of M^-½ K M^-½, one ``numpy.linalg.eigh`` over the stack. A variant whose lowest flexible frequency the
batched solve cannot promise to :data:`mechdyn.vibration.eigen.ACCURACY` (the inertias or stiffnesses
spread over many decades) is solved by :func:`~mechdyn.drivetrain.modal` on its own, as the single path
would. Anything else (a value computed from geometry, a gear's data) raises
:class:`~mechdyn.registry.NotBatchable`, and the study evaluates it one variant at a time; so does a
model whose mass matrix is not diagonal (a shaft with consistent inertia: the stack is built on
M^-½, which needs a diagonal M). Shafts with lumped inertia, or divided into elements, batch as
any other model (their nodes are coordinates of the stack).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from mechdyn.registry import NotBatchable, summary_columns

__all__ = ["modal_batch"]

_ELEMENT_TABLES = ("shafts", "meshes", "ground_springs")


def modal_batch(
    loaded: Any,
    columns: Mapping[tuple[tuple[str, ...], tuple[Any, ...]], np.ndarray],
    keys: Sequence[str],
    rigid_gears: bool = False,
    compare_rigid: bool = False,
    modes: int | None = None,
    solver: str = "auto",
) -> tuple[dict[str, np.ndarray], list[str | None]]:
    """The modal figures of many variants (see :attr:`mechdyn.registry.Analysis.batch`).

    Parameters
    ----------
    loaded : LoadedModel
        The base drivetrain file as loaded.
    columns : mapping
        ``((), ("disks", i, "inertia"))`` → V inertias (kg·m²); ``((), (table, i, "stiffness"))`` →
        V stiffnesses (N·m/rad for shafts and ground springs, N/m for meshes), for ``table`` one of
        shafts, meshes, ground_springs.
    keys : sequence of str
        Summary keys: ``frequencies_hz.N``, ``modes.N.frequency_hz`` (Hz), ``modes.N.mode``,
        ``rigid_body_modes``.
    rigid_gears, compare_rigid, modes, solver
        The ``modal`` analysis' options; ``compare_rigid`` is not batched, ``solver`` changes only
        round-off.

    Returns
    -------
    outputs : dict of str → ndarray
        (V,) per key.
    errors : list
        None for every variant (a variant the batch cannot take raises NotBatchable instead).
    """
    from mechdyn.drivetrain.assembly import assemble
    from mechdyn.drivetrain.modal import modal
    from mechdyn.vibration.eigen import doubt_below

    if compare_rigid:
        raise NotBatchable("the batch does not pair modes with the rigid-gear ones")
    if loaded.source is None:
        raise NotBatchable("the batch takes a drivetrain read from a file")
    data = loaded.source.data
    model = loaded.model.with_rigid_gears() if rigid_gears else loaded.model
    asm = assemble(model)
    if not asm.diagonal_mass:
        raise NotBatchable(
            "the mass matrix is not diagonal (a shaft with consistent inertia); each variant is solved on "
            "its own"
        )
    n, n_rb = asm.n, asm.n_rigid_body
    V = max((np.asarray(v).size for v in columns.values()), default=1)
    T = asm.T.toarray()
    disk_index = model.dof_index
    blocks = {e.name: b for e, b in model.element_blocks}
    mass = np.tile(asm.mass, (V, 1))
    K = np.tile(asm.K.toarray(), (V, 1, 1))
    stiffness = {e.name: getattr(e, "stiffness", None) for e, _ in model.element_blocks}
    inertia: dict[str, np.ndarray] = {}
    changed: dict[str, np.ndarray] = {}
    for (files, where), values in columns.items():
        v = np.broadcast_to(np.asarray(values, dtype=float), (V,))
        if not np.all(v > 0):
            raise NotBatchable("a variant has an inertia or a stiffness that is not positive")
        match (files, where):
            case ((), ("disks", int(i), "inertia")) if _given(data, "disks", i, "inertia"):
                name = data["disks"][i]["name"]
                d = disk_index[name]
                inertia[name] = v
                mass += np.outer(v - model.disks[d].inertia, T[d] ** 2)  # Tᵀ diag(ΔJ) T is diagonal
            case ((), (str(table), int(i), "stiffness")) if table in _ELEMENT_TABLES and _given(
                data, table, i, "stiffness"
            ):
                name = data[table][i]["name"]
                changed[name] = v
                b = blocks.get(name)
                if b is None or b.stiffness is None:  # a mesh made a rigid constraint: no spring left
                    continue
                k0 = stiffness[name]
                n_dofs = len(model.dof_names)
                unit = np.zeros((n_dofs, n_dofs))
                at = [disk_index[x] for x in b.disks]
                unit[np.ix_(at, at)] = b.stiffness / k0
                K += (v - k0)[:, None, None] * (T.T @ unit @ T)[None]
            case _:
                raise NotBatchable(f"the batch does not vary {'.'.join(map(str, where))}")
    want = set(keys)
    top = {k.split(".")[0] for k in want}
    if not top <= {"frequencies_hz", "modes", "rigid_body_modes"} or any(
        k.startswith("modes.") and k.split(".")[-1] not in ("frequency_hz", "mode") for k in want
    ):
        raise NotBatchable("the batch gives the natural frequencies only")
    d = 1.0 / np.sqrt(mass)
    lam = np.linalg.eigvalsh(d[:, :, None] * K * d[:, None, :])  # (V, n), ascending
    flexible = lam[:, n_rb:]
    # the batched solve is backward stable, each λ within about ε‖A‖: the single path's estimate
    norm = np.abs(lam).max(axis=1)
    doubt = np.flatnonzero(flexible.min(axis=1, initial=np.inf) < doubt_below(norm)).tolist()
    count = n - n_rb if modes is None else min(modes, n - n_rb)
    omega = np.sqrt(np.clip(flexible[:, :count], 0.0, None))
    for row in doubt:  # widely spread values: the single path's accurate solvers, for these variants
        one = replace(
            loaded.model,
            disks=tuple(
                replace(x, inertia=float(inertia[x.name][row])) if x.name in inertia else x
                for x in loaded.model.disks
            ),
            elements=tuple(
                replace(e, stiffness=float(changed[e.name][row])) if e.name in changed else e
                for e in loaded.model.elements
            ),
        )
        omega[row] = modal(one, rigid_gears=rigid_gears, n_modes=modes, solver="auto").omega[:count]
    hz = omega / (2 * np.pi)
    summary: dict[str, Any] = {
        "frequencies_hz": {str(m + 1): hz[:, m] for m in range(count)},
        "modes": {str(m + 1): {"mode": np.full(V, m + 1.0), "frequency_hz": hz[:, m]} for m in range(count)},
        "rigid_body_modes": np.full(V, float(n_rb)),
    }
    return summary_columns(summary, keys, V), [None] * V


def _given(data: Mapping[str, Any], table: str, i: int, field: str) -> bool:
    """Whether row ``i`` of ``[[table]]`` gives ``field`` as a value of its own (not from geometry)."""
    rows = data.get(table, [])
    return 0 <= i < len(rows) and isinstance(rows[i], Mapping) and field in rows[i] and "name" in rows[i]
