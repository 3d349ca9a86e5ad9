"""Make the tap test of examples/measured: tap_test.uff, the FRFs of the machine as built.

    python examples/measured/make_data.py          # (re)write examples/measured/tap_test.uff

The "machine as built" is machine.toml with its mounts' stiffness changed (TRUE_STIFFNESS below:
20 % stiffer across x, 12.5 % softer across y, 15 % stiffer vertically, every mount alike) and
stiffness-proportional damping (c = 1e-3 s · k, ζ = 0.5 … 6.5 %). Its accelerances are taken at
the four mount tops (points 1 … 4, x, y and z: 12 accelerometers) for hammer blows at point 1
along z and point 4 along x, from 2 to 30 Hz every 0.05 Hz, with 1 % multiplicative complex noise
and an additive floor of 0.1 % of each channel's peak (mechdyn.measurement.simulate_frf, seed 2026),
and written as Universal File dataset 58 by pyuff's writer: binary, single precision, in m/s²/N
against Hz, one dataset per response and reference (about 130 KB).
"""

from __future__ import annotations

import dataclasses
import gc
import warnings
from pathlib import Path

import numpy as np

import mechdyn
from mechdyn.measurement import simulate_frf

HERE = Path(__file__).resolve().parent
TRUE_STIFFNESS = (0.6e6, 0.7e6, 2.3e6)  # N/m along x, y, z: each mount of the machine as built
BETA = 1.0e-3  # s, stiffness-proportional damping of the mounts as built
SEED = 2026
FREQUENCIES_HZ = np.arange(2.0, 30.0 + 1e-9, 0.1)  # a 10 s record
REFERENCES = (("1", "z"), ("4", "x"))


def machine_as_built():
    """machine.toml's machine with the mounts' true stiffness and damping."""
    designed = mechdyn.load(HERE / "machine.toml").model
    k = np.array(TRUE_STIFFNESS)
    mounts = [dataclasses.replace(m, stiffness=k, damping=BETA * k) for m in designed.mounts]
    return dataclasses.replace(designed, mounts=mounts), {m.name: tuple(m.position) for m in designed.mounts}


def measure():
    """The noisy accelerances of the machine as built (a MeasuredFRF)."""
    machine, points = machine_as_built()
    outputs = tuple((p, d) for p in points for d in "xyz")
    return simulate_frf(machine, outputs, REFERENCES, FREQUENCIES_HZ, points, kind="accelerance", seed=SEED)


def write_uff(path: Path) -> Path:
    """Write the tap test as UFF 58 (pyuff's writer)."""
    import pyuff

    m = measure()
    code = {d: i + 1 for i, d in enumerate(("x", "y", "z", "rx", "ry", "rz"))}
    sets = []
    for j, (rp, rd) in enumerate(m.references):
        for i, (op, od) in enumerate(m.outputs):
            sets.append(
                pyuff.prepare_58(
                    binary=1,
                    id1=f"tap test: {op}{od} / {rp}{rd}",
                    id2="examples/measured/make_data.py",
                    func_type=4,
                    rsp_node=int(op),
                    rsp_dir=code[od],
                    ref_node=int(rp),
                    ref_dir=code[rd],
                    ord_data_type=6,  # complex, double precision
                    abscissa_spacing=1,  # even: the first frequency and the step, not every line
                    data=m.H[:, i, j],
                    x=m.frequencies_hz,
                    abscissa_spec_data_type=18,
                    abscissa_axis_units_lab="Hz",
                    ordinate_spec_data_type=12,
                    ordinate_axis_units_lab="m/s^2",
                    orddenom_spec_data_type=13,
                    orddenom_axis_units_lab="N",
                )
            )
    if path.exists():
        path.unlink()
    with warnings.catch_warnings():
        # pyuff 2.5's binary writer reopens the file inside each dataset and leaves that handle to
        # the garbage collector: collect it here, where its ResourceWarning is known and harmless
        warnings.simplefilter("ignore", ResourceWarning)
        pyuff.UFF(str(path)).write_sets(sets, mode="add")
        gc.collect()
    return path


if __name__ == "__main__":
    out = write_uff(HERE / "tap_test.uff")
    print(f"wrote {out.name}: {out.stat().st_size / 1024:.0f} KB")
