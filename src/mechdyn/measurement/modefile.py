"""Mode shapes from a Universal File (dataset 55, data at nodes) in the identified-mode form.

A modal test's software exports its identified modes as UFF 55 records: one per mode, with the mode's
frequency and damping (normal modes, analysis type 2) or complex eigenvalue (analysis types 3 and 7),
and the shape's components at each node (SDRC I-DEAS, *Universal File Datasets Summary*, dataset 55;
read with pyuff, Slavič et al., https://github.com/ladisk/pyuff). They become an
:class:`mechdyn.measurement.IdentifiedModes` that :func:`mechdyn.measurement.compare_modes` and
:func:`mechdyn.measurement.update_model` take like modes identified here, with no scatter (the file
holds none) and no stabilisation chart.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from mechdyn.errors import ModelFileError
from mechdyn.measurement.data import DIRECTIONS, uff_sets
from mechdyn.measurement.identify import IdentifiedModes, StabilisationChart

__all__ = ["read_uff_modes"]

_NORMAL, _COMPLEX = (2,), (3, 7)


def _mode(name: str, i: int, s: dict[str, Any]) -> tuple[float, float, dict[tuple[str, str], complex]]:
    """(ω rad/s, ζ, {(node, direction): component}) of one dataset 55."""
    where = f"dataset #{i + 1} (type 55, mode {s.get('mode_n', '?')})"
    kind = int(s.get("analysis_type", 0))
    if kind in _NORMAL:
        f = float(s.get("freq", np.nan))
        if not f > 0:
            raise ModelFileError(name, f"{where} → freq", "must be a frequency > 0 Hz", value=s.get("freq"))
        omega, zeta = 2.0 * np.pi * f, float(s.get("modal_damp_vis", 0.0) or 0.0)
    elif kind in _COMPLEX:
        lam = complex(s.get("eig", np.nan))  # s_k = −ζω + iω√(1 − ζ²), rad/s
        omega = abs(lam)
        if not omega > 0:
            raise ModelFileError(name, f"{where} → eig", "must be a complex eigenvalue ≠ 0 rad/s", value=lam)
        zeta = -lam.real / omega
    else:
        raise ModelFileError(
            name,
            f"{where} → analysis_type",
            "is not a mode: give normal modes (2) or complex modes (3, 7)",
            value=kind,
        )
    nodes = [str(int(n)) for n in np.atleast_1d(s.get("node_nums", []))]
    comp: dict[tuple[str, str], complex] = {}
    for k, d in enumerate(DIRECTIONS):
        r = s.get(f"r{k + 1}")
        if r is None:
            continue
        r = np.atleast_1d(np.asarray(r))
        if r.size != len(nodes):
            raise ModelFileError(
                name, f"{where} → r{k + 1}", f"has {r.size} values for {len(nodes)} nodes", value=r.size
            )
        comp.update({(n, d): complex(v) for n, v in zip(nodes, r, strict=True)})
    if not comp:
        raise ModelFileError(name, f"{where} → r1 … r6", "holds no shape components", value=None)
    return omega, zeta, comp


def read_uff_modes(path: str | Path, *, directions: tuple[str, ...] | None = None) -> IdentifiedModes:
    """Read the mode shapes of a Universal File (dataset 55) as identified modes.

    Parameters
    ----------
    path : str or Path
        The ``.uff``/``.unv`` file. Every dataset 55 of a mode (analysis type 2, 3 or 7) is read; other
        datasets are skipped.
    directions : tuple of str, optional
        Keep only these directions of each node (``("z",)``: the vertical accelerometers); by default
        every direction that is non-zero in some mode (a component zero in every mode was not measured).

    Returns
    -------
    IdentifiedModes
        Frequencies (Hz → rad/s) and viscous damping ratios (normal modes: ``modal_damp_vis``; complex
        modes: ζ = −Re s / abs(s)), sorted by frequency; shapes (n_out, n_modes) at the outputs
        ``(node, direction)``, node by node, each scaled so that its largest entry is real and 1 (mode
        shapes have no unit); zero scatter and an empty stabilisation chart (the file holds neither).

    Raises
    ------
    ModelFileError
        For a missing or unreadable file, no mode in it, a dataset that is not a mode or whose shape
        does not fit its nodes, naming the file, the dataset and the field.
    """

    name = str(path)
    sets = uff_sets(name)
    modes = [_mode(name, i, s) for i, s in enumerate(sets) if s.get("type") == 55]
    if not modes:
        raise ModelFileError(name, "file", "holds no dataset 55 (data at nodes); write the mode shapes as 55")
    if directions is not None:
        bad = [d for d in directions if d not in DIRECTIONS]
        if bad:
            raise ValueError(f"directions {bad} are not among {DIRECTIONS}")
    modes.sort(key=lambda m: m[0])
    keys = list(dict.fromkeys(k for _, _, comp in modes for k in comp))
    nodes = list(dict.fromkeys(node for node, _ in keys))
    keys.sort(key=lambda k: (nodes.index(k[0]), DIRECTIONS.index(k[1])))
    shapes = np.array([[comp.get(k, 0.0) for _, _, comp in modes] for k in keys], dtype=complex)
    keep = np.array([d in directions if directions is not None else True for _, d in keys])
    keep &= np.abs(shapes).max(axis=1) > 0
    shapes, outputs = shapes[keep], tuple(k for k, q in zip(keys, keep, strict=True) if q)
    for j in range(shapes.shape[1]):
        big = shapes[np.argmax(np.abs(shapes[:, j])), j]
        shapes[:, j] = shapes[:, j] / big if big != 0 else shapes[:, j]
    if np.allclose(shapes.imag, 0.0):
        shapes = shapes.real.astype(complex)
    n = len(modes)
    empty = np.zeros(0)
    return IdentifiedModes(
        omega=np.array([m[0] for m in modes]),
        damping=np.array([m[1] for m in modes]),
        shapes=shapes,
        residues=np.zeros((len(outputs), 0, n), dtype=complex),
        omega_scatter=np.zeros(n),
        damping_scatter=np.zeros(n),
        shape_scatter=np.zeros(n),
        stable_orders=np.zeros(n, dtype=int),
        outputs=outputs,
        references=(),
        chart=StabilisationChart(empty, empty, empty, np.zeros(0, dtype=int), None),  # type: ignore[arg-type]
        method=f"read from Universal File dataset 55 ({Path(name).name})",
    )
