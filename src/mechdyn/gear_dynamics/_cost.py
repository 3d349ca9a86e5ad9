"""What a speed sweep or a time simulation will cost, estimated before the work, and the limits.

Counted from the model and the options, not measured: the operations of the dominant step at a
throughput this two-core class of machine reaches (:data:`FLOPS`), and the memory of the largest
array. A run whose memory would exceed :data:`MEMORY_LIMIT` or whose time would exceed
:data:`TIME_LIMIT` is refused, naming the option that makes it so and what to give instead; one
that would take more than :data:`TIME_WARN` goes on with a warning that gives the estimate.

- **Harmonic balance**: at each speed a dense complex system of J (2H + 1) unknowns (the mesh
  deflections' harmonics, :func:`mechdyn.gear_dynamics.harmonic_balance._hb_solve`): (8/3) N³ real
  operations of LU, 16 N² bytes.
- **Floquet stability** (harmonic balance's check, and shooting): S Magnus segments per period, each
  a matrix exponential of the 2m + 1 state (the Padé [13/13] with scaling, about 30 products of
  d³ each) and the product.
- **Shooting with backlash**: Newton's iterations of the event-located flow; about
  :data:`BACKLASH_SECONDS` of CPU a speed (measured 0.10 s a speed on a single pair and 0.71 s on
  turret C, the continuation through a fold 0.08–1.2 s a point).
- **simulate**: at least ``cycle_steps`` steps a mesh cycle at the fastest mesh's frequency at the
  highest speed the inputs can reach (the motor's no-load speed, or the initial speed), about
  :data:`SECONDS_PER_CYCLE` × (n/10)² of CPU a cycle (1.2–8 ms measured for 10 disks); every sample
  of n angles, n speeds and J mesh forces kept.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

from mechdyn.errors import LongRunWarning, ModelError

__all__ = ["Cost", "check", "simulation_cost", "sweep_cost"]

#: Real floating-point operations a second assumed for dense linear algebra (a 2-core machine).
FLOPS = 1e10
#: The most memory one array of a run may take, bytes.
MEMORY_LIMIT = 4 * 2**30
#: Runs estimated to take longer than this are refused, s (ten hours).
TIME_LIMIT = 36_000.0
#: Runs estimated to take longer than this go on with a warning, s.
TIME_WARN = 600.0
#: CPU of one speed of the Newton shooting through contact loss, continuation included, s (the
#: figure the docs state and the sweeps meet: at most 1 s a speed).
BACKLASH_SECONDS = 1.0
#: CPU of one mesh cycle of ``simulate`` for a 10-disk train, s.
SECONDS_PER_CYCLE = 5e-3


def _duration(seconds: float) -> str:
    """A duration in seconds, minutes or hours, whichever reads best."""
    from mechdyn.units import convert

    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{float(convert(seconds, 's', 'min')):.0f} min"
    return f"{float(convert(seconds, 's', 'h')):.1f} h"


@dataclass(frozen=True)
class Cost:
    """An estimate of a run.

    Attributes
    ----------
    seconds : float
        CPU time, s.
    bytes : float
        Memory of the largest array, bytes.
    what : str
        What was counted, in words.
    """

    seconds: float
    bytes: float
    what: str

    def words(self) -> str:
        """The estimate in words (minutes or hours, MB or GB)."""
        time = _duration(self.seconds)
        size = self.bytes
        memory = f"{size / 2**20:.0f} MB" if size < 2**30 else f"{size / 2**30:.1f} GB"
        return f"about {time} of CPU and {memory} for its largest array ({self.what})"


def sweep_cost(
    n_speeds: int,
    meshes: int,
    harmonics: int,
    top_order: int,
    states: int,
    segments: int,
    stability: bool,
    backlash: bool,
) -> Cost:
    """The estimated cost of a speed sweep.

    Parameters
    ----------
    n_speeds : int
        Speeds to solve (those given; refinement adds a few), count.
    meshes : int
        Meshes whose stiffness varies, J, count.
    harmonics : int
        Harmonics of each mesh frequency, count.
    top_order : int
        The highest mesh frequency's order over the common fundamental, count.
    states : int
        The state's size 2m, count.
    segments : int
        Magnus segments per period at the lowest speed, count.
    stability : bool
        Whether each speed's Floquet multipliers are computed.
    backlash : bool
        Whether the sweep shoots through contact loss.
    """
    floquet = segments * 30.0 * (states + 1) ** 3 / FLOPS if (stability or backlash) else 0.0
    if backlash:
        return Cost(
            n_speeds * (BACKLASH_SECONDS + floquet),
            8.0 * segments * (states + 1) ** 2,
            f"{n_speeds} speeds by Newton shooting",
        )
    N = meshes * (2 * harmonics * max(top_order, 1) + 1)
    solve = (8.0 / 3.0) * N**3 / FLOPS
    return Cost(
        n_speeds * (solve + floquet),
        max(16.0 * N**2, 8.0 * segments * (states + 1) ** 2 if stability else 0.0),
        f"{n_speeds} speeds, a dense system of {N} unknowns each"
        + (f", {segments} Magnus segments a period for the stability" if stability else ""),
    )


def simulation_cost(
    duration: float, fastest_mesh_hz: float, cycle_steps: int, n: int, meshes: int, samples: float | None
) -> Cost:
    """The estimated cost of a time simulation.

    Parameters
    ----------
    duration : float
        Simulated time, s.
    fastest_mesh_hz : float
        The highest mesh frequency the run can reach, Hz.
    cycle_steps : int
        Fewest steps a mesh cycle, count.
    n : int
        Coordinates, count.
    meshes : int
        Flexible meshes, count.
    samples : float or None
        Samples kept (``duration / output_step``); None: every step (about ``cycle_steps`` a cycle).
    """
    cycles = duration * fastest_mesh_hz
    kept = samples if samples is not None else max(cycles * cycle_steps, 1.0)
    return Cost(
        cycles * SECONDS_PER_CYCLE * max(n / 10.0, 1.0) ** 2,
        kept * (2 * n + 2 * meshes) * 8.0,
        f"{cycles:.3g} mesh cycles, {kept:.3g} samples kept",
    )


def check(cost: Cost, element: str, field: str, fix: str) -> None:
    """Refuse a run beyond :data:`MEMORY_LIMIT` or :data:`TIME_LIMIT`, warn beyond :data:`TIME_WARN`.

    Parameters
    ----------
    cost : Cost
    element, field : str
        Where the error points (the option or the file's field that makes the run so large).
    fix : str
        What to give instead, in words.

    Raises
    ------
    mechdyn.errors.ModelError
        Beyond a limit.
    """
    if cost.bytes > MEMORY_LIMIT or cost.seconds > TIME_LIMIT:
        limit = "memory" if cost.bytes > MEMORY_LIMIT else "time"
        raise ModelError(
            f"this run would take {cost.words()}, beyond the {limit} this machine gives a run "
            f"({MEMORY_LIMIT / 2**30:.0f} GB, {_duration(TIME_LIMIT)}); {fix}",
            element=element,
            field=field,
        )
    if cost.seconds > TIME_WARN:
        warnings.warn(
            f"{element}: this run will take {cost.words()}; {fix} for a quicker one",
            LongRunWarning,
            stacklevel=3,
        )
