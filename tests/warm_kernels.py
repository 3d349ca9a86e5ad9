"""Compile numba's kernels once before the test workers start (run by ``tests/conftest.py``).

On a clean clone numba's on-disk cache is empty: without this, each pytest-xdist worker, and every
command-line subprocess a test starts before the cache is written, compiles the same kernels at the
same time. Two processes compile here together, one per family of kernels (``python
tests/warm_kernels.py dyads``, ``gears``). The dyad family is the largest share: its curves' kernels
first and then its summary's, in one process, because the summary's kernels call the curves' kernel
and find it compiled (two processes would compile it twice); the gear family, with the Newton path
of a geared mechanism, takes the other core. Each runs the smallest cases that reach every signature
the suite uses (checked against the kernels a whole run compiles); a kernel missed here is still
compiled where a test first needs it, so this only saves time and never decides a result.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path
from typing import Any

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


def _press(name: str) -> Any:
    import mechdyn

    return mechdyn.load(EXAMPLES / name).model


def _columns(m: Any, n: int = 16) -> dict[tuple[str, str, int], np.ndarray]:
    return {("points", "D", 0): m.points["D"][0] + np.linspace(-0.01, 0.01, n)}


def cycle() -> None:
    """The dyad kernel on one design (serially) and on a batch (in threads), curves kept."""
    from mechdyn.mechanism import cycle as one_cycle
    from mechdyn.mechanism.batch import cycle_columns

    press = _press("press_link_drive.toml")
    _quietly(lambda: one_cycle(press, 36))
    _quietly(lambda: cycle_columns(press, _columns(press), 36))


def summary() -> None:
    """The summary-only batch: in lanes, chunk by chunk with process forces, a variant that fails."""
    from mechdyn.mechanism.batch import cycle_columns

    for name in ("press_link_drive.toml", "press_tonnage.toml"):
        m = _press(name)
        columns = _columns(m)
        failing = {k: v.copy() for k, v in columns.items()}
        failing[("points", "D", 0)][3] = 1e3  # a variant that does not assemble
        for c in (columns, failing):
            _quietly(lambda m=m, c=c: cycle_columns(m, c, 36, summary_only=True))
    # variants that assemble where drawn but not over the whole turn: summarised again after screening
    # (the press's with its bottom dead centre located again)
    for name, point in (("fourbar.toml", "B"), ("press_link_drive.toml", "B")):
        m = _press(name)
        stuck = {("points", point, 0): m.points[point][0] + np.array([0.0, 0.01, 0.3, 3.0])}
        _quietly(lambda m=m, stuck=stuck: cycle_columns(m, stuck, 36, summary_only=True))


def dyads() -> None:
    """The dyad kernel's curves, then its summary (which calls the curves' kernel, compiled by then)."""
    cycle()
    summary()


def gears() -> None:
    """The contact law, the right-hand side, its Jacobian and the events: a pair with backlash in time
    and in its periodic steady state; and the Newton path of a geared mechanism."""
    import mechdyn
    from mechdyn.drivetrain import Disk, Drivetrain, GearMesh
    from mechdyn.gear_dynamics import ConstantTorque, GearSystem, simulate, steady_state
    from mechdyn.registry import get

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
    # an implicit integrator asks for the Jacobian
    simulate(
        GearSystem.from_drivetrain(pair),
        0.002,
        inputs=[ConstantTorque("gear", 10.0), ConstantTorque("pinion", 4.0)],
        initial_speed=300.0,
        method="BDF",
    )
    _quietly(lambda: get("mechanism").run(mechdyn.load(EXAMPLES / "transplanter_rp1.toml")))


FAMILIES = {"dyads": dyads, "gears": gears}
"""The families of kernels, one process each."""


def _cached(family: str) -> bool:
    """Whether the family's main kernels are in numba's cache already (then there is nothing to do)."""
    from mechdyn._compiled import is_cached

    if family == "dyads":
        from mechdyn.mechanism.dyads import _kernel, _reduce

        kernels = (_kernel.run_serial, _kernel.run_parallel, _reduce.run_lanes, _reduce.run_and_summarise)
    else:
        from mechdyn.gear_dynamics import _contact
        from mechdyn.gear_dynamics import _kernel as gear_kernel

        kernels = (gear_kernel.rhs, _contact.mesh_forces)
    return all(is_cached(k) for k in kernels)


if __name__ == "__main__":
    family = sys.argv[1]
    if not _cached(family):
        FAMILIES[family]()
