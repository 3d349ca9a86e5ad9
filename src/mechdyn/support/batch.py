"""Design studies' batch evaluation of a machine on a one-degree-of-freedom support, shaken by a
mechanism: every variant's mechanism in one compiled cycle, every variant's steady state at once.

The steady state is the one of :func:`mechdyn.support.periodic_response`, written out for one
coordinate: X_h = c_h / (k − (hΩ)² m + i hΩ c) for the Fourier coefficients c_h of the vertical
exciting force over the cycle's samples (Rao, *Mechanical Vibrations*, §4.2), c = 2ζ√(km) as
:meth:`mechdyn.support.MountedMachine.single_dof` builds it; the transmitted force is k z + c ż.
Anything else (several mounts, a load given as samples, mounts estimated from their drawings)
raises :class:`~mechdyn.registry.NotBatchable`, and a study evaluates it one variant at a time.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from mechdyn.registry import NotBatchable

__all__ = ["support_batch"]

_OWN = {("machine", "mass"), ("support", "stiffness"), ("support", "damping_ratio")}


def support_batch(
    loaded: Any,
    columns: Mapping[tuple[tuple[str, ...], tuple[Any, ...]], np.ndarray],
    keys: Sequence[str],
    cycles: int | None = None,
    store: Any = None,
) -> tuple[dict[str, np.ndarray], list[str | None]]:
    """The steady-state figures of many variants (see :attr:`mechdyn.registry.Analysis.batch`).

    ``cycles`` and ``store`` are the support analysis' options; the steady state needs neither.
    """
    from mechdyn.mechanism.batch import cycle_columns, summary_columns
    from mechdyn.support.excitation import series_on_grid
    from mechdyn.support.response import extremes
    from mechdyn.support.schema import MechanismExcitation

    spec = loaded.settings
    e = getattr(spec, "excitation", None)
    if spec is None or not isinstance(e, MechanismExcitation) or spec.estimates:
        raise NotBatchable("the batch takes a support whose load comes from a mechanism file")
    machine = loaded.model
    if machine.dofs != ("z",) or len(machine.mounts) != 1 or e.mechanism.process_forces:
        raise NotBatchable("the batch takes the one-degree-of-freedom support")
    own: dict[tuple[Any, ...], np.ndarray] = {}
    mech: dict[tuple[Any, ...], np.ndarray] = {}
    for (files, where), values in columns.items():
        if files == (e.path,):
            mech[where] = values
        elif not files and where in _OWN:
            own[where] = np.asarray(values, dtype=float)
        else:
            raise NotBatchable(f"the batch does not vary {'.'.join(map(str, where))}")
    V = max(np.asarray(v).size for v in columns.values()) if columns else 1
    batch = cycle_columns(e.mechanism, mech, e.angles, V)
    N = batch.angle.shape[1]
    f2 = batch.shaking_force  # (V, N, 2) in the mechanism's plane
    F = f2[..., 0] * e.placement.x_axis[2] + f2[..., 1] * e.placement.y_axis[2]
    mount = machine.mounts[0]
    m = own.get(("machine", "mass"), np.full(V, machine.body.mass))
    k = own.get(("support", "stiffness"), np.full(V, mount.stiffness[2]))
    # the file gives the damping ratio: a stiffer or heavier variant keeps it (c = 2ζ√(km))
    zeta0 = mount.damping[2] / (2.0 * np.sqrt(mount.stiffness[2] * machine.body.mass))
    zeta = own.get(("support", "damping_ratio"), np.full(V, zeta0))
    c = 2.0 * zeta * np.sqrt(k * m)
    if np.any(~(k > 0)) or np.any(~(m > 0)) or np.any(c < 0):
        raise NotBatchable("a variant has a mass or stiffness that is not positive")
    coeff = np.fft.rfft(np.nan_to_num(F), axis=-1) / N  # (V, H + 1)
    if N % 2 == 0:
        coeff[:, -1] *= 0.5
    period = abs(2 * math.pi / e.mechanism.driver.speed)
    w = 2 * math.pi / period * np.arange(coeff.shape[1])
    X = coeff / (k[:, None] - w**2 * m[:, None] + 1j * w * c[:, None])
    z = series_on_grid(X.T, N).T  # (V, N)
    zd = series_on_grid((1j * w * X).T, N).T
    FT = k[:, None] * z + c[:, None] * zd
    ok = np.isfinite(F).all(axis=1)
    (f_lo, f_hi), (t_lo, t_hi), (z_lo, z_hi) = (extremes(y) for y in (F, FT, z))  # as the single path
    rng_F, rng_T = f_hi - f_lo, t_hi - t_lo
    figures: dict[str, Any] = {
        "inertia_force_max_N": f_hi,
        "inertia_force_min_N": f_lo,
        "inertia_force_range_N": rng_F,
        "transmitted_force_max_N": t_hi,
        "transmitted_force_min_N": t_lo,
        "transmitted_force_range_N": rng_T,
        "transmitted_to_inertia_force_range": np.divide(
            rng_T, rng_F, out=np.full(V, np.nan), where=rng_F > 0
        ),
        "displacement_max_m": z_hi,
        "displacement_min_m": z_lo,
        "machine_mass_kg": m,
        "period_s": np.full(V, period),
        "excitation": batch.summary(),
    }
    for key, arr in list(figures.items()):
        if key != "excitation":
            figures[key] = np.where(ok, arr, np.nan)
    return summary_columns(figures, keys, V), [batch.failures.get(v) for v in range(V)]
