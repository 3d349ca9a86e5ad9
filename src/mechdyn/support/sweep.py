"""A rotating unbalance over a speed range: the force on the floor, the transmissibility and the
isolation at the running speed.

The unbalance force grows as the speed squared, U Ω²; the machine on its mounts passes a share of
it to the floor that depends on the speed. At each speed of the range the rotors' load (their
speeds kept in ratio, :class:`~mechdyn.support.Rotor`) is solved harmonic by harmonic,
(K − ω² M + i ω C) X = B c, and the floor force is Σ_m (K_m + i ω C_m) T_m X (as in
:func:`~mechdyn.support.periodic_response`). The transmissibility is the largest magnitude of the
floor force over a period over the largest magnitude of the unbalance force (the kept translations):
for one vertical spring and damper it is the classical T = √((1 + (2ζr)²)/((1 − r²)² + (2ζr)²)),
r = Ω/ω_n (Rao, *Mechanical Vibrations*, 6th ed., §3.7 and §9.10; Harris & Piersol, *Shock and
Vibration Handbook*, ch. 30), and the isolation efficiency is 1 − T. A slow run-up passes through
these steady states.

Beside the machine's own figure, each mount is rated on its own at the running speed, as a vendor's
calculator and ``mechdyn mount`` do (:func:`mechdyn.mounts.isolation`): its vertical stiffness and
damping under its share of the machine's weight, one degree of freedom.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.checks import check_array, check_count
from mechdyn.errors import ModelError
from mechdyn.results import Result, Table
from mechdyn.support.excitation import PeriodicLoad
from mechdyn.support.model import MountedMachine
from mechdyn.support.unbalance import Rotor, rotor_tuple, unbalance_coefficients

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["DEFAULT_SPEED_STEPS", "UnbalanceSweep", "unbalance_sweep"]

DEFAULT_SPEED_STEPS = 241
"""Speeds of a sweep when none are given: 0 to 1.2 times the running speed, 0.5 % apart."""
TABLE_ROWS = 13
"""Evenly spaced speeds the table of a sweep shows (besides the running speed and the peak)."""
MAX_SPEEDS = 100_000
"""The most speeds one sweep evaluates."""
_CHUNK = 2_000_000  # complex samples evaluated at once when locating the peak of a force


def _peak_magnitude(F: np.ndarray, orders: np.ndarray) -> np.ndarray:
    """The largest norm over a period of f(θ) = 2 Re Σ_a F[..., a, :] e^{i h_a θ}, for (S, A, c) amplitudes.

    One harmonic: exactly, max ‖Re(A e^{iθ})‖² = (‖A‖² + abs(A·A))/2 with A = 2F (the semi-major axis of
    the ellipse the vector draws). Several: on 16 steps a period of the highest order, the largest
    sample refined between the samples (:func:`mechdyn.support.response.extremes` on ‖f‖²).
    """
    from mechdyn.support.response import extremes

    if F.shape[1] == 1:
        A = 2 * F[:, 0, :]
        norm2 = np.sum(np.abs(A) ** 2, axis=-1)
        return np.sqrt(np.maximum(0.5 * (norm2 + np.abs(np.sum(A * A, axis=-1))), 0.0))
    n = max(64, 16 * int(orders.max()))
    theta = 2 * math.pi * np.arange(n) / n
    E = np.exp(1j * np.multiply.outer(orders, theta))  # (A, n)
    out = np.empty(F.shape[0])
    step = max(1, _CHUNK // (n * F.shape[2]))
    for lo in range(0, F.shape[0], step):
        f = 2 * np.einsum("sac,an->snc", F[lo : lo + step], E).real  # (s, n, c)
        out[lo : lo + step] = extremes(np.sum(f * f, axis=-1))[1]
    return np.sqrt(np.maximum(out, 0.0))


def _rpm(w: Any) -> Any:
    from mechdyn.units import convert

    return (
        convert(np.asarray(w, dtype=float), "rad/s", "rpm")
        if np.ndim(w)
        else convert(float(w), "rad/s", "rpm")
    )


@dataclass(frozen=True, repr=False)  # the short repr of Result
class UnbalanceSweep(Result):
    """The force a rotating unbalance puts on the floor through the mounts, over a speed range.

    Attributes
    ----------
    machine : MountedMachine
        The machine on its mounts.
    rotors : tuple of Rotor
        The rotors at their running speeds; the sweep turns all of them faster or slower together.
    speed : ndarray
        (S,) the first rotor's speed, rad/s, ascending, the running speed among them.
    unbalance_force, floor_force : ndarray
        (S,) the largest magnitude over a period of the unbalance force (its kept translations) and of
        the total force on the floor, N.
    unbalance_force_z, floor_force_z : ndarray
        (S,) the largest vertical unbalance force and vertical floor force, N.
    transmissibility : ndarray
        (S,) floor force over unbalance force, a ratio (at speed 0 its limit, the static ratio).
    natural_frequencies : ndarray
        (n,) of the machine on its mounts, Hz.
    mode_coordinates : tuple of str
        The coordinate that dominates each mode.
    resonance_speeds : ndarray
        (R, 3) rows (first rotor's speed rad/s, natural frequency Hz, harmonic order) at which a
        rotor's force meets a natural frequency, ascending.
    mounts : dict
        Each mount rated on its own at the running speed (:func:`mechdyn.mounts.isolation`), or a
        reason why it cannot be.
    """

    machine: MountedMachine
    rotors: tuple[Rotor, ...]
    speed: np.ndarray
    unbalance_force: np.ndarray
    floor_force: np.ndarray
    unbalance_force_z: np.ndarray
    floor_force_z: np.ndarray
    transmissibility: np.ndarray
    natural_frequencies: np.ndarray
    mode_coordinates: tuple[str, ...]
    resonance_speeds: np.ndarray
    mounts: dict[str, dict[str, Any]] = field(default_factory=dict)

    # -- at the running speed ------------------------------------------------------------------
    @property
    def running_speed(self) -> float:
        """The first rotor's running speed, rad/s."""
        return abs(float(self.rotors[0].speed))

    @property
    def running_index(self) -> int:
        """The index of the running speed in :attr:`speed`."""
        return int(np.argmin(np.abs(self.speed - self.running_speed)))

    @property
    def isolation_efficiency(self) -> np.ndarray:
        """(S,) 1 − T, a ratio (negative: the mounts amplify)."""
        return 1.0 - self.transmissibility

    @property
    def frequency_ratio(self) -> float:
        """The fastest rotor's turning frequency at the running speed over the lowest natural frequency."""
        f = max(abs(r.speed) for r in self.rotors) / (2 * math.pi)
        return float(f / self.natural_frequencies.min())

    @property
    def verdict(self) -> str:
        """What the machine on its mounts does to the unbalance force at the running speed, in words."""
        from mechdyn.mounts.tables import isolation_verdict

        return isolation_verdict(float(self.transmissibility[self.running_index]), self.frequency_ratio)

    # -- the result protocol -------------------------------------------------------------------
    def summary(self) -> dict[str, Any]:
        """The running speed's figures, the speed range and its largest floor force, each mount's own."""
        i = self.running_index
        peak = int(np.argmax(self.floor_force))
        T = float(self.transmissibility[i])
        out: dict[str, Any] = {
            "running_speed_rpm": _rpm(self.running_speed),
            "unbalance_force_N": float(self.unbalance_force[i]),
            "unbalance_floor_force_N": float(self.floor_force[i]),
            "unbalance_transmissibility_ratio": T,
            "unbalance_isolation_efficiency_percent": 100 * (1 - T),
            "unbalance_verdict": self.verdict,
            "speed_range_rpm": [_rpm(float(self.speed[0])), _rpm(float(self.speed[-1]))],
            "unbalance_floor_force_peak_N": float(self.floor_force[peak]),
            "unbalance_floor_force_peak_speed_rpm": _rpm(float(self.speed[peak])),
            "resonance_speeds_rpm": [_rpm(float(s)) for s in self.resonance_speeds[:, 0]],
        }
        if self.mounts:
            out["mount_isolation"] = self.mounts
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row per speed: speed, unbalance and floor forces, transmissibility, isolation."""
        import pandas as pd

        return pd.DataFrame(
            {
                "speed_rpm": _rpm(self.speed),
                "unbalance_force_N": self.unbalance_force,
                "floor_force_N": self.floor_force,
                "unbalance_force_z_N": self.unbalance_force_z,
                "floor_force_z_N": self.floor_force_z,
                "transmissibility_ratio": self.transmissibility,
                "isolation_efficiency_percent": 100 * self.isolation_efficiency,
            }
        )

    def _rows(self) -> list[int]:
        """The speeds a table shows: evenly spaced, the running speed and the largest floor force."""
        s = self.speed
        picks = {int(np.argmin(np.abs(s - v))) for v in np.linspace(s[0], s[-1], TABLE_ROWS)}
        picks |= {self.running_index, int(np.argmax(self.floor_force))}
        return sorted(picks)

    def tables(self, **display_units: str) -> list[Table]:
        """The running speed's figures (with the verdict), each mount rated on its own, and the forces
        and transmissibility over the speed range. Forces in ``force_unit`` where given, else in the
        unit their size reads best in (N, kN or MN)."""
        from mechdyn.units import convert, readable_unit

        fu = display_units.get("force_unit")
        i = self.running_index
        rpm = _rpm(self.running_speed)
        largest = float(max(self.unbalance_force.max(), self.floor_force.max()))
        unit, shown = (fu, fu) if fu else readable_unit(largest, "N")

        def F(v: float) -> float:
            return float(convert(float(v), "N", unit))

        T = float(self.transmissibility[i])
        rows: list[list[Any]] = [
            [
                "running speed" + (" (first rotor)" if len({abs(r.speed) for r in self.rotors}) > 1 else ""),
                rpm,
                "rpm",
            ],
            ["unbalance force (largest in a period)", F(self.unbalance_force[i]), shown],
            ["floor force (largest in a period)", F(self.floor_force[i]), shown],
        ]
        if self.unbalance_force_z[i] > 0:
            rows += [
                ["vertical unbalance force (largest)", F(self.unbalance_force_z[i]), shown],
                ["vertical floor force (largest)", F(self.floor_force_z[i]), shown],
            ]
        rows += [["transmissibility", T, ""], ["isolation efficiency", 100 * (1 - T), "%"]]
        out = [
            Table(
                f"rotating unbalance at the running speed ({rpm:.6g} rpm)",
                ["quantity", "value", "unit"],
                rows,
                f"On its mounts the machine {self.verdict}.",
            )
        ]
        rated = {n: m for n, m in self.mounts.items() if "transmissibility_ratio" in m}
        if rated:
            weights = [m["static_load_N"] for m in rated.values()]
            wu, wshown = (fu, fu) if fu else readable_unit(max(weights), "N")
            verdicts = {m["verdict"] for m in rated.values()}
            if len(verdicts) == 1 and len(rated) == len(self.mounts):
                note = f"Each mount on its own {verdicts.pop()}."
            else:
                note = " ".join(
                    f"{n}: {m.get('verdict', m.get('not_rated'))}." for n, m in self.mounts.items()
                )
            out.append(
                Table(
                    f"each mount on its own at {rpm:.6g} rpm (vertical, its share of the weight, "
                    "as mechdyn mount rates it)",
                    [
                        "mount",
                        f"static load [{wshown}]",
                        "natural frequency [Hz]",
                        "frequency ratio",
                        "transmissibility",
                        "isolation [%]",
                    ],
                    [
                        [
                            n,
                            float(convert(m["static_load_N"], "N", wu)),
                            m["natural_frequency_hz"],
                            m["frequency_ratio"],
                            m["transmissibility_ratio"],
                            m["isolation_efficiency_percent"],
                        ]
                        for n, m in rated.items()
                    ],
                    note,
                )
            )
        peak = int(np.argmax(self.floor_force))
        remark = {i: "running", peak: "largest floor force"} if peak != i else {i: "running, largest"}
        passed = [
            f"{f:.3g} Hz ({self.mode_coordinates[self._mode(f)]}) at {_rpm(s):.4g} rpm"
            + (f", order {int(h)}" if len({int(x) for x in self.resonance_speeds[:, 2]}) > 1 else "")
            for s, f, h in self.resonance_speeds
            if s <= self.speed[-1]
        ]
        above = [(s, f) for s, f, _ in self.resonance_speeds if s > self.speed[-1]]
        note = (
            "The unbalance force grows as the speed squared; a slow run-up passes through these steady "
            "states."
            + (f" Natural frequencies met in the range: {'; '.join(passed)}." if passed else "")
            + (
                f" The {'next' if passed else 'lowest'} natural frequency, {above[0][1]:.3g} Hz "
                f"({self.mode_coordinates[self._mode(above[0][1])]}), is met at {_rpm(above[0][0]):.4g} rpm, "
                "above the range."
                if above
                else ""
            )
        )
        out.append(
            Table(
                "rotating unbalance over the speed range",
                [
                    "speed [rpm]",
                    f"unbalance force [{shown}]",
                    f"floor force [{shown}]",
                    f"vertical floor force [{shown}]",
                    "transmissibility",
                    "isolation efficiency [%]",
                    "",
                ],
                [
                    [
                        _rpm(float(self.speed[k])),
                        F(self.unbalance_force[k]),
                        F(self.floor_force[k]),
                        F(self.floor_force_z[k]),
                        float(self.transmissibility[k]),
                        float(100 * self.isolation_efficiency[k]),
                        remark.get(k, ""),
                    ]
                    for k in self._rows()
                ],
                note,
            )
        )
        return out

    def _mode(self, frequency: float) -> int:
        return int(np.argmin(np.abs(self.natural_frequencies - frequency)))

    def plots(self, **display_units: str) -> dict[str, Any]:
        """The unbalance and floor forces and the transmissibility against speed."""
        from mechdyn.support import plots as sp

        return {
            "unbalance_speed_sweep.png": lambda: sp.plot_unbalance_sweep(
                self, force_unit=display_units.get("force_unit")
            )
        }


def _speeds(speeds: Any, running: float) -> np.ndarray:
    """The sweep's speeds, rad/s: given (quantities or SI numbers), or 0 to 1.2 times the running
    speed; the running speed added, sorted, each once."""
    if speeds is None:
        s = np.linspace(0.0, 1.2 * running, DEFAULT_SPEED_STEPS)
    elif hasattr(speeds, "m_as"):  # a pint array
        s = check_array(
            "speed sweep", "speeds", speeds.m_as("rad/s"), "rad/s", nonnegative=True, what="speeds"
        )
    elif isinstance(speeds, str) or (np.ndim(speeds) == 1 and any(isinstance(v, str) for v in speeds)):
        from mechdyn.units import si_field

        values = [speeds] if isinstance(speeds, str) else list(speeds)
        s = np.array([si_field("speed sweep", "speeds", v, "rad/s", nonnegative=True) for v in values])
    else:
        s = check_array("speed sweep", "speeds", speeds, "rad/s", nonnegative=True, what="speeds")
    s = np.atleast_1d(s).ravel()
    check_count("speed sweep", "speeds", s.size, low=1, high=MAX_SPEEDS, what="speeds")
    return np.union1d(s, [running])


def _mount_ratings(machine: MountedMachine, frequency: float) -> dict[str, dict[str, Any]]:
    """Each mount on its own at ``frequency`` (Hz): vertical stiffness and damping under its share of
    the weight, rated by :func:`mechdyn.mounts.isolation` (ζ = c / (2 √(k m)), η = 2ζ)."""
    from mechdyn.mounts.tables import isolation_verdict
    from mechdyn.mounts.types import G0, isolation

    out: dict[str, dict[str, Any]] = {}
    if machine.gravity <= 0:
        return out
    loads = -machine.static_mount_forces[:, 2]
    for m, W in zip(machine.mounts, loads, strict=True):
        k, c = float(m.stiffness_matrix[2, 2]), float(m.damping_matrix[2, 2])
        if W <= 0 or k <= 0:
            out[m.name] = {"not_rated": "carries none of the weight"}
            continue
        mass = W / machine.gravity
        zeta = c / (2 * math.sqrt(k * mass))
        if zeta >= 1:
            out[m.name] = {"not_rated": f"damped past critical (ζ = {zeta:.3g})"}
            continue
        iso = isolation(k, mass * G0, frequency, 2 * zeta)
        T = iso["transmissibility"]
        out[m.name] = {
            "static_load_N": float(W),
            "natural_frequency_hz": iso["natural_frequency_hz"],
            "frequency_ratio": iso["frequency_ratio"],
            "damping_ratio": zeta,
            "transmissibility_ratio": T,
            "isolation_efficiency_percent": 100 * iso["isolation_efficiency"],
            "verdict": isolation_verdict(T, iso["frequency_ratio"]),
        }
    return out


def unbalance_sweep(
    machine: MountedMachine, rotors: Rotor | Sequence[Rotor] | PeriodicLoad, speeds: Any = None
) -> UnbalanceSweep:
    """The floor force and transmissibility of a rotating unbalance over a range of speeds.

    All rotors turn faster or slower together, their speeds kept in ratio (one drive); the sweep's
    speed is the first rotor's. The force is U Ω² per rotor; the transmissibility is the largest
    floor force over the largest unbalance force in a period (Rao, *Mechanical Vibrations*, §3.7
    and §9.10). Each mount is also rated on its own at the running speed (:func:`mechdyn.mounts.isolation`).

    Parameters
    ----------
    machine : MountedMachine
        The machine on its mounts.
    rotors : Rotor, sequence of Rotor, or PeriodicLoad
        The rotors at their running speeds (rad/s), or a load made by :meth:`PeriodicLoad.from_unbalance`.
    speeds : array_like or quantity, optional
        The first rotor's speeds to evaluate, rad/s (or quantities such as ``["0 rpm", "3000 rpm"]``,
        or a pint array), each ≥ 0, at most 100 000 of them; by default 241 speeds from 0 to 1.2 times
        the running speed. The running speed is always among them.

    Returns
    -------
    UnbalanceSweep

    Raises
    ------
    mechdyn.errors.ModelError
        For a load without rotors, speeds that are negative or not finite, or rotors whose force lies
        wholly along coordinates the machine's model does not keep (a vertical rotor on the
        one-degree-of-freedom support).

    Examples
    --------
    >>> from mechdyn.support import MountedMachine, Rotor, unbalance_sweep
    >>> machine = MountedMachine.single_dof("400 kg", "1.6e6 N/m", 0.05)  # 10.07 Hz
    >>> sweep = unbalance_sweep(machine, Rotor("0.01 kg*m", "1480 rpm", "y"))
    >>> round(sweep.summary()["unbalance_transmissibility_ratio"], 4)  # r = 2.45, ζ = 0.05
    0.2055
    """
    from mechdyn.support.modes import modes
    from mechdyn.vibration.harmonic import harmonic_solve

    if isinstance(rotors, PeriodicLoad):
        if not rotors.rotors:
            raise ModelError(
                "this load has no rotors; build it with PeriodicLoad.from_unbalance(...) or pass the rotors",
                element="speed sweep",
                field="rotors",
            )
        rotors = rotors.rotors
    rotors = rotor_tuple(rotors)
    period, c = unbalance_coefficients(rotors)
    running = abs(rotors[0].speed)
    s = _speeds(speeds, running)
    base = 2 * math.pi / period
    orders = np.nonzero(np.abs(c).max(axis=1) > 0)[0]
    ch = c[orders]  # (A, 6)
    kept = [k for k, d in enumerate(("x", "y", "z")) if d in machine.dofs]
    exciting = np.zeros((1, orders.size, 3), dtype=complex)  # the force the model sees
    exciting[0][:, kept] = ch[:, kept]
    E = float(_peak_magnitude(exciting, orders)[0])
    Ez = float(_peak_magnitude(exciting[..., 2:], orders)[0])
    if not E > 1e-12 * max(r.force_amplitude for r in rotors):
        raise ModelError(
            f"the rotors' force lies wholly along coordinates the model does not keep (it keeps "
            f'{", ".join(machine.dofs)}); stand the machine on [[mounts]] with dofs = "spatial", or check '
            "the rotors' axes",
            element="speed sweep",
            field="rotors",
        )
    # unit loads at the running speed's force, at each speed's frequencies; forces scale as λ²
    lam = s / running
    omega = np.multiply.outer(lam, orders * base)  # (S, A)
    Q = ch @ machine.load_matrix().T  # (A, n)
    n = Q.shape[1]
    X = harmonic_solve(
        machine.stiffness_matrix,
        machine.damping_matrix,
        machine.mass_matrix,
        np.broadcast_to(Q, (s.size, orders.size, n)).reshape(-1, n),
        omega.ravel(),
    ).reshape(s.size, orders.size, n)
    Kf = sum(m.stiffness_matrix @ machine.mount_transform(m) for m in machine.mounts)
    Cf = sum(m.damping_matrix @ machine.mount_transform(m) for m in machine.mounts)
    floor = X @ np.asarray(Kf).T + 1j * omega[..., None] * (X @ np.asarray(Cf).T)  # (S, A, 3)
    P = _peak_magnitude(floor, orders)
    Pz = _peak_magnitude(floor[..., 2:], orders)
    md = modes(machine)
    fn = np.asarray(md.frequencies_hz, dtype=float)
    # the first rotor's speed at which the force of order h meets a natural frequency
    res = sorted(
        (float(2 * math.pi * f * running / (h * base)), float(f), float(h))
        for f in fn
        for h in orders
        if f > 0
    )
    scale = lam**2
    return UnbalanceSweep(
        machine,
        rotors,
        s,
        scale * E,
        scale * P,
        scale * Ez,
        scale * Pz,
        P / E,
        fn,
        tuple(md.dominant),
        np.array(res, dtype=float).reshape(-1, 3),
        _mount_ratings(machine, running / (2 * math.pi)),
    )
