"""The summary-only batch: many design variants reduced to their scalar figures, in chunks.

A study that keeps only scalars (the stroke, the torque peak, each joint's largest force) need not
keep every variant's curves: :func:`cycle_summary` runs the compiled kernel into work rows that the
variants reuse (one per thread, or chunks of variants where a speed profile, process forces or a
rocker output need Python between the passes), reduces each variant's curves to its figures in the
same compiled pass (:mod:`mechdyn.mechanism.dyads._reduce`: the formulas of
:mod:`mechdyn.mechanism.extrema`, per variant), and keeps those alone. Memory grows with the number
of variants by their inputs and figures (about 1.1 KB each), not by V × N; the figures equal
:meth:`CycleBatch.summary` of the full batch to round-off.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mechdyn.mechanism.dyads.angles import crank_angles
from mechdyn.mechanism.dyads.run import Outputs, _setup, checked_variants, dyad_plan, run_block, screen_block
from mechdyn.mechanism.model import Mechanism
from mechdyn.mechanism.revolution import check_angles
from mechdyn.results import Result

__all__ = ["CHUNK", "CycleSummary", "cycle_summary"]

CHUNK = 32
"""Variants per chunk where the summary-only batch runs chunk by chunk (its work buffers hold this
many cycles)."""


@dataclass(frozen=True, repr=False)  # the short repr of Result
class CycleSummary(Result):
    """The scalar figures of many design variants over one revolution, without their curves.

    Attributes
    ----------
    mechanism : Mechanism
        The base design the variants were made from.
    figures : dict of str to ndarray
        Summary key → (V,) values in the unit its name ends with (the keys of
        :meth:`CycleBatch.summary`, less the joint-force peaks).
    joint_peaks : ndarray
        (V, joints) each joint's largest force over the cycle on its second body, N.
    failures : dict of int to str
        Variant index → why it could not be computed (its figures are NaN).
    """

    mechanism: Mechanism
    figures: dict[str, np.ndarray]
    joint_peaks: np.ndarray
    failures: dict[int, str] = field(default_factory=dict)

    @property
    def n_variants(self) -> int:
        """V, the number of variants."""
        return int(self.joint_peaks.shape[0])

    @property
    def status(self) -> tuple[str, ...]:
        """Per variant: ``"ok"``, or why it was not computed (the angle, the loop and the joint)."""
        return tuple(self.failures.get(v, "ok") for v in range(self.n_variants))

    @property
    def assembled(self) -> np.ndarray:
        """(V,) True for the variants that assemble over the whole cycle."""
        ok = np.ones(self.n_variants, dtype=bool)
        ok[list(self.failures)] = False
        return ok

    @property
    def joint_force_peaks(self) -> dict[str, np.ndarray]:
        """Joint → (V,) largest force magnitude over the cycle on its second body, N."""
        return {j.name: self.joint_peaks[:, k] for k, j in enumerate(self.mechanism.joints)}

    def summary(self) -> dict[str, Any]:
        """Per variant (arrays over V): the figures of :meth:`CycleBatch.summary`, with
        ``joint_force_peak_N`` (joint → (V,) N)."""
        return {**self.figures, "joint_force_peak_N": self.joint_force_peaks}

    def to_frame(self) -> Any:
        """One row per variant: whether it assembles and its :meth:`summary` figures (units in the names)."""
        import pandas as pd

        cols: dict[str, Any] = {"variant": np.arange(self.n_variants), "assembled": self.assembled}
        cols |= self.figures
        cols |= {f"joint_{name}_force_peak_N": v for name, v in self.joint_force_peaks.items()}
        return pd.DataFrame(cols)


def cycle_summary(
    mechanism: Mechanism,
    n_angles: int = 360,
    points: Mapping[str, Any] | None = None,
    masses: Mapping[str, Any] | None = None,
    *,
    inertias: Mapping[str, Any] | None = None,
    chunk: int = CHUNK,
) -> CycleSummary:
    """The summary figures of a mechanism's variants, without keeping their curves.

    The same variants, checks and numbers as :func:`~mechdyn.mechanism.dyads.cycle` with
    ``errors="nan"`` followed by :meth:`CycleBatch.summary`, but each variant's curves go to a work
    row that the next variant reuses and are reduced to its figures in compiled code as soon as
    they are computed: one parallel pass with a row per thread at constant speed without process
    forces or a rocker output, else ``chunk`` variants at a time (memory: about 1.1 KB per
    variant, its encoded drawing and its figures). A variant whose dyads come near a singular
    position is screened afterwards (:mod:`mechdyn.mechanism.screening`).

    Parameters
    ----------
    mechanism : Mechanism
        The nominal design.
    n_angles : int
        Crank angles per revolution, a whole number from 4 to 100 000.
    points, masses, inertias : mapping, optional
        What differs between the variants, as for :func:`~mechdyn.mechanism.dyads.cycle` (m, kg,
        kg·m²).
    chunk : int
        Variants per chunk, from 1 to 100 000 (the work buffers hold chunk × n_angles samples of
        each curve).

    Returns
    -------
    CycleSummary
        A variant that cannot be assembled has NaN figures and its reason in ``failures``.

    Raises
    ------
    NotDecomposable
        When the mechanism is not a crank with RRR/RRP dyads.
    ModelError
        For an input outside its range (naming it).
    """
    from mechdyn.checks import check_count
    from mechdyn.mechanism.dyads._reduce import (
        COLUMNS,
        LAYOUT,
        LOAD,
        OUTPUT,
        bdc_degrees,
        run_and_summarise,
        summarise,
    )

    m = mechanism
    n_angles = check_angles(n_angles)
    chunk = check_count("cycle_summary", "chunk", chunk, low=1, high=100_000, what="variants")
    steps = dyad_plan(m)
    given, masses, inertias = checked_variants(m, points, masses, inertias)
    rocker = m.output_rocker()
    bdc = m.angle_datum == "bdc"
    has_output = m.output_joint() is not None
    # one parallel pass over lanes where each variant's curves are its own (constant speed, no
    # process forces) and every figure is compiled (no rocker's swing); else chunk by chunk
    lanes = m.driver.profile is None and not m.process_forces and rocker is None and (has_output or not bdc)
    s = _setup(m, steps, n_angles, given, masses, inertias, False, encode_all=lanes)
    V, N = s.V, s.N

    def buffers(W: int) -> Outputs:
        return Outputs(
            pos=np.empty((W, N, s.keep.size), dtype=complex),
            vel=np.empty((0, 0, 0), dtype=complex),  # positions alone: layout figures, process forces
            acc=np.empty((0, 0, 0), dtype=complex),
            rates=np.empty((0, 0, 0, 0)),
            force=np.empty((W, N), dtype=complex),
            inertia_force=np.empty((W, N), dtype=complex),
            moment=np.empty((W, N)),
            torque=np.empty((W, N)),
            stroke=np.empty((W, N)) if has_output else np.empty((0, 0)),
            dyad_measure=np.empty((W, N, s.n_dyads)),
            multipliers=np.empty((0, 0, 0)),
            peaks=np.empty((0, 0)),
        )

    peaks = np.empty((V, len(m.joints)))
    rows = np.empty((V, len(COLUMNS)))
    j = m.output_joint()
    link = m.output_link()
    where = {n: i for i, n in enumerate(s.wanted)}
    ends = np.array(
        [where[link[0]], where[link[1]], where[m.driver.pivot]]
        if link is not None and j is not None and all(p in where for p in (*link, m.driver.pivot))
        else [-1, -1, -1],
        dtype=np.int64,
    )
    axis = complex(math.cos(j.axis), math.sin(j.axis)) if j is not None else 0j
    swing: dict[str, np.ndarray] = {}
    failures: dict[int, str] = {}
    if lanes:
        suspect = _lanes(s, bdc, axis, ends, rows, peaks)
        blocks = [(int(v), int(v) + 1) for v in np.flatnonzero(suspect)]  # screened one by one
        W = 1
    else:
        W = min(chunk, V)
        blocks = [(lo, min(lo + W, V)) for lo in range(0, V, W)]
    buf = buffers(W)
    deg_buf = np.empty((W, N))
    for lo, hi in blocks:
        out = Outputs._make([*(a[: hi - lo] if a.shape[0] else a for a in buf[:-1]), peaks[lo:hi]])
        deg = deg_buf[: hi - lo]
        if not (bdc and has_output):  # a fixed datum: the angles are known before the motion
            deg[:] = np.degrees(crank_angles(m, s.theta_draw[lo:hi], s.step, None, N))
        chunk_rows = rows[lo:hi]

        def kernel(args: Any, deg: np.ndarray = deg, chunk_rows: np.ndarray = chunk_rows) -> None:
            run_and_summarise(args, s.step, deg, bdc and has_output, axis, ends, chunk_rows)

        read_at = run_block(s, lo, hi, out, kernel)
        known = len(failures)
        screen_block(s, lo, out, read_at, "nan", failures)
        stroke = out.stroke if has_output else None
        if len(failures) > known:  # a variant failed: its curves are NaN now, its figures follow
            failed = np.zeros(hi - lo, dtype=bool)
            failed[[v - lo for v in failures if v >= lo]] = True
            if bdc and has_output:
                bdc_degrees(out.stroke, s.step, deg)
            summarise(
                deg,
                out.torque,
                out.force,
                out.moment,
                out.stroke,
                out.inertia_force,
                axis,
                out.pos,
                ends,
                out.dyad_measure,
                failed,
                bdc,
                chunk_rows,
            )
        if rocker is not None and all(p in where for p in rocker[1:]):
            from mechdyn.mechanism.extrema import bdc_origin, swing_figures

            origin = bdc_origin(deg, stroke) if stroke is not None and bdc else None
            tip, pivot = where[rocker[2]], where[rocker[1]]
            for key, value in swing_figures(deg, out.pos[..., tip] - out.pos[..., pivot], origin).items():
                swing.setdefault(key, np.empty(V))[lo:hi] = value
    keys = list(LOAD)
    if j is not None and has_output:
        keys += OUTPUT
        if ends[0] >= 0:
            keys += LAYOUT
    figures = {k: rows[:, COLUMNS.index(k)] for k in keys}
    if s.n_dyads:
        figures["transmission_angle_min_deg"] = rows[:, COLUMNS.index("transmission_angle_min_deg")]
        key = "crank_angle_at_transmission_angle_min_deg"
        figures[key] = rows[:, COLUMNS.index(key)]
    figures |= swing
    return CycleSummary(m, figures, peaks, failures)


def _lanes(
    s: Any, bdc: bool, axis: complex, ends: np.ndarray, rows: np.ndarray, peaks: np.ndarray
) -> np.ndarray:
    """Every variant of ``s`` through :func:`~mechdyn.mechanism.dyads._reduce.run_lanes`: one work
    row per thread, the figures into ``rows``, the joint-force peaks into ``peaks``; returns (V,)
    the variants to screen."""
    import numba

    from mechdyn.mechanism.dyads._reduce import run_lanes
    from mechdyn.mechanism.dyads.arguments import kernel_args
    from mechdyn.mechanism.screening import SCREEN

    m, V, N = s.m, s.V, s.N
    L = min(V, numba.get_num_threads())
    w, a = m.driver.rates(np.zeros(1))  # a constant speed: the same at every angle and variant
    # one row for every variant (a row each would be V × N floats): the kernel reads row 0
    omega, alpha = np.full((1, N), float(w[0])), np.full((1, N), float(a[0]))
    out = Outputs(
        pos=np.empty((L, N, s.keep.size), dtype=complex),
        vel=np.empty((0, 0, 0), dtype=complex),
        acc=np.empty((0, 0, 0), dtype=complex),
        rates=np.empty((0, 0, 0, 0)),
        force=np.empty((L, N), dtype=complex),
        inertia_force=np.empty((L, N), dtype=complex),
        moment=np.empty((L, N)),
        torque=np.empty((L, N)),
        stroke=np.empty((L, N)) if s.output_slot >= 0 else np.empty((0, 0)),
        dyad_measure=np.empty((L, N, s.n_dyads)),
        multipliers=np.empty((0, 0, 0)),
        peaks=peaks,
    )
    args = kernel_args(
        drawing=s.dz,
        ops=s.ops,
        op_data=s.fdata,
        grounded=s.grounded,
        turn=s.turn,
        omega=omega,
        alpha=alpha,
        mass=s.mass,
        inertia=s.inertia,
        gravity=complex(*m.gravity),
        keep=s.keep,
        output_slot=s.output_slot,
        output_axis=s.output_axis,
        load_ops=s.load_ops,
        load_data=s.load_data,
        frame_ops=s.frame_ops,
        frame_data=s.frame_data,
        joint_kind=s.joint_kind,
        n_multipliers=m.n_constraints,
        applied=np.zeros((0, 0, 0, 0)),
        **out._asdict(),
    )
    offsets = np.zeros(V) if bdc else s.theta_draw - float(m.angle_datum)
    suspect = np.zeros(V, dtype=bool)
    run_lanes(args, s.step, bdc, offsets, axis, ends, SCREEN, np.empty((L, N)), rows, suspect)
    return suspect
