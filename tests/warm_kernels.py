"""Compile numba's kernels once before the test workers start (run by ``tests/conftest.py``).

On a clean clone numba's on-disk cache is empty: without this, each pytest-xdist worker, and every
command-line subprocess a test starts before the cache is written, compiles the same kernels at the
same time. Two processes compile here together, one per family of kernels: ``python
tests/warm_kernels.py mechanism`` and ``python tests/warm_kernels.py gears``. Each runs the smallest
cases that reach every signature the suite uses; a kernel missed here is still compiled where a test
first needs it, so this only saves time and never decides a result.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def _quietly(job) -> None:
    """Run one warm-up case; whatever it raises or warns is the tests' business, not this one's."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            job()
        except Exception:  # a case that fails here still compiled what it reached
            pass


def mechanism() -> None:
    """The dyad path (one design, a batch in threads, the summary-only batch with and without a
    failed variant, process forces) and the Newton path of a geared mechanism."""
    import mechdyn
    from mechdyn.mechanism import cycle
    from mechdyn.mechanism.batch import cycle_columns
    from mechdyn.registry import get

    for name in ("press_link_drive.toml", "press_tonnage.toml"):
        m = mechdyn.load(EXAMPLES / name).model
        _quietly(lambda m=m: cycle(m, 36))
        D = m.points["D"][0] + np.linspace(-0.01, 0.01, 16)
        failing = D.copy()
        failing[3] = 1e3  # a variant that does not assemble
        for summary_only in (False, True):
            for column in (D, D[:1], failing):
                _quietly(
                    lambda c=column, s=summary_only, m=m: cycle_columns(
                        m, {("points", "D", 0): c}, 36, summary_only=s
                    )
                )
    for name in ("transplanter_rp1.toml", "fourbar.toml"):
        _quietly(lambda name=name: get("mechanism").run(mechdyn.load(EXAMPLES / name)))


def gears() -> None:
    """The contact law, the right-hand side, its Jacobian and the events: a pair with backlash in time
    and in its periodic steady state."""
    from mechdyn.drivetrain import Disk, Drivetrain, GearMesh
    from mechdyn.gear_dynamics import ConstantTorque, GearSystem, simulate, steady_state

    pair = Drivetrain(
        [Disk("pinion", 0.05), Disk("gear", 0.03)],
        [
            GearMesh(
                "m",
                ("pinion", "gear"),
                teeth=(20, 50),
                base_radii=(0.0188, 0.047),
                stiffness=3e8,
                damping=3e3,
            )
        ],
        name="pair",
    )
    for backlash in (None, {"m": 2e-5}):
        system = GearSystem.from_drivetrain(
            pair, errors={"m": {"amplitude": 1e-6, "samples": 24}}, backlash=backlash
        )
        simulate(
            system,
            0.002,
            inputs=[ConstantTorque("gear", 10.0), ConstantTorque("pinion", 4.0)],
            initial_speed=300.0,
        )
        steady_state(system, 300.0, reference="pinion", drive="speed", load={"gear": 10.0})


def _cached(family: str) -> bool:
    """Whether the family's main kernels are in numba's cache already (then there is nothing to do)."""
    from mechdyn._compiled import is_cached

    if family == "mechanism":
        from mechdyn.mechanism.dyads import _kernel, _reduce

        kernels = (_kernel.run_serial, _kernel.run_parallel, _reduce.run_lanes)
    else:
        from mechdyn.gear_dynamics import _contact
        from mechdyn.gear_dynamics import _kernel as gear_kernel

        kernels = (gear_kernel.rhs, _contact.mesh_forces)
    return all(is_cached(k) for k in kernels)


if __name__ == "__main__":
    family = sys.argv[1]
    if not _cached(family):
        {"mechanism": mechanism, "gears": gears}[family]()
