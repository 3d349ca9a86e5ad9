"""Periodic steady state of press A on its supports: frequency domain against time integration.

    python benchmarks/periodic_response.py            # both models, best of three
    python benchmarks/periodic_response.py --quick    # both models, one run each (within a minute)
    python benchmarks/periodic_response.py --json     # one JSON object with the times and ratios

Baseline, measured in the same run: what a script does without the frequency-domain method —
``scipy.integrate.solve_ivp`` (DOP853, rtol 1e-10) from rest, period after period, until one period
differs from the one before by less than 1e-8 of the response; its last period is the steady state.
Both see the same continuous load (the Fourier series of the mechanism's 360 samples), so they must
agree to 1e-6 of the response; the agreement is printed.

mechdyn: :func:`mechdyn.support.periodic_response` — one complex solve per harmonic and the series
back to 360 time steps, for the one-degree-of-freedom model and for the machine on four mounts.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
from _timing import best_time
from scipy.integrate import solve_ivp

import mechdyn
from mechdyn.support import periodic_response

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
CASES = {"1 DOF": "press_on_support.toml", "4 mounts, 6 DOF": "press_on_mounts.toml"}


def integrate_to_steady_state(machine, load, n: int, tol: float = 1e-8, max_periods: int = 200):
    """Periods of solve_ivp from rest until the response repeats; returns (last period, periods)."""
    M, K, C = machine.mass_matrix, machine.stiffness_matrix, machine.damping_matrix
    B = machine.load_matrix()
    Minv = np.linalg.inv(M)
    dof = M.shape[0]
    T = load.period
    grid = T * np.arange(n + 1) / n

    def rhs(t, y):
        q, v = y[:dof], y[dof:]
        return np.concatenate([v, Minv @ (B @ load.value(t) - C @ v - K @ q)])

    y = np.zeros(2 * dof)
    previous = None
    for k in range(max_periods):
        sol = solve_ivp(
            rhs, (k * T, (k + 1) * T), y, method="DOP853", t_eval=k * T + grid, rtol=1e-10, atol=1e-16
        )
        y = sol.y[:, -1]
        q = sol.y[:dof, :-1].T
        if previous is not None and np.abs(q - previous).max() < tol * np.abs(q).max():
            return q, k + 1
        previous = q
    raise RuntimeError("no steady state within the periods allowed")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="one run of each (within a minute)")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)
    n = 360
    repeats = 1 if args.quick else 3
    result: dict[str, object] = {
        "benchmark": "periodic_response",
        "quick": args.quick,
        "samples": n,
        "cases": {},
    }
    rows = []
    for label, file in CASES.items():
        spec = mechdyn.load(EXAMPLES / file).settings
        machine, load = spec.machine, spec.load
        t_fd, fd = best_time(lambda m=machine, ld=load: periodic_response(m, ld, n), max_repeats=50)
        t_ivp, (q, periods) = best_time(
            lambda m=machine, ld=load: integrate_to_steady_state(m, ld, n), max_repeats=repeats, budget=60.0
        )
        agreement = float(np.abs(q - fd.displacement).max() / np.abs(fd.displacement).max())
        result["cases"][label] = {  # type: ignore[index]
            "dofs": len(machine.dofs),
            "frequency_domain_s": t_fd,
            "solve_ivp_to_steady_state_s": t_ivp,
            "solve_ivp_periods": periods,
            "ratio": t_ivp / t_fd,
            "max_rel_diff": agreement,
        }
        rows.append((label, t_fd, t_ivp, periods, agreement))
    result["ratio_min"] = min(c["ratio"] for c in result["cases"].values())  # type: ignore[union-attr]
    if args.json:
        print(json.dumps(result, indent=2))
        return 0
    head = ("frequency domain", "solve_ivp", "periods", "ratio", "agreement")
    print(f"{'model':18s}" + "".join(f"{h:>{w}s}" for h, w in zip(head, (18, 14, 9, 9, 11), strict=True)))
    for label, t_fd, t_ivp, periods, agreement in rows:
        ratio = t_ivp / t_fd
        print(f"{label:18s}{t_fd * 1e3:15.2f} ms{t_ivp:12.2f} s{periods:9d}{ratio:8.0f}×{agreement:11.1e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
