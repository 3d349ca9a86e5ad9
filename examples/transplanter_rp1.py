"""Reference machine D: the gear-type rotary planting mechanism "RP-1" (SPEC §6), and its sensitivity.

    python examples/transplanter_rp1.py            # sensitivity of forces, torque and shaking force
    python examples/transplanter_rp1.py --quick    # fewer angles (the tests run this)
    python examples/transplanter_rp1.py --json     # the table as JSON
    python examples/transplanter_rp1.py --write    # (re)write examples/transplanter_rp1.toml

A carrier arm turns at 200 rpm about the fixed sun gear G1; on each side an idler at R/2 and a
planet at R mesh in a chain, and a planting fork is fixed to each planet. The sun and the planets
are eccentric circles of pitch radius ρ, sized so that the mates close at the centre distance
R/2; the planets are installed at the phase α (the line from pivot to centre at α to the
horizontal in the drawing), and the sun at the angle that makes each idler the exact pure-rolling
mate of both its neighbours (an idler is one gear: solved, −50.9° for the published data). Side 2
is installed as side 1 stands half a turn later, so that the two sides run point-symmetric about
the sun. Published data: ε 0.13, α −35°, β −76° (the arm in the drawing), R 76.8 mm, L 138 mm,
γ 14° (the fork's direction in the drawing), masses and the inertias about the pivots. Not
published, chosen here: d = 20 mm from the planet's pivot to the centre of mass of planet + fork,
along the fork (the inertia about the pivot, 1.092e-3 kg·m² for 1.0654 kg, allows at most
√(I/m) = 32 mm, where the inertia about the centre of mass would vanish); the arm's inertia
2.1e-3 kg·m² (a bar of 2R; at constant speed it changes nothing).

Each variable is moved by ±10 % with the others fixed (ε also over 0–0.2), and the script reports the
peak tooth force, the peak force between a gear and the carrier, the range of the driving torque
and the ranges of the shaking force, to compare with the published trends.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np
from scipy.optimize import minimize_scalar

from mechdyn.mechanism import Body, Driver, GearJoint, Mechanism, Revolute, inverse_dynamics, kinematics
from mechdyn.mechanism.pitch import closing_centre_distance, eccentric_circle, pitch_law

HERE = Path(__file__).resolve().parent
NOMINAL = {"eps": 0.13, "R": 0.0768, "alpha": -35.0, "L": 0.138, "gamma": 14.0, "d": 0.020}
BETA = -76.0  # deg, the arm in the drawing
MASSES = {"arm": 1.0716, "idler": 0.0069, "planet": 1.0654}  # kg (planet with its fork)
I_PIVOT = {"idler": 1.26e-5, "planet": 1.092e-3}  # kg·m² about the pivots
I_ARM = 2.1e-3  # kg·m², not published
FIELD_VELOCITY = -0.8  # m/s along x: the machine's speed over the field (not published; typical)


def _side(curve, pts, com, mass, sun, planet, k):
    """Bodies and joints of one side (k = 1 or 2); ``sun`` and ``planet``: the installation angles
    of the eccentrics (rad)."""
    mp, ip = mass
    bodies = (
        Body(f"idler {k}", (f"I{k}",), MASSES["idler"], I_PIVOT["idler"], f"I{k}"),
        Body(f"planet {k}", (f"P{k}", f"F{k}"), mp, ip, com),
    )
    g_sun, g_pl = ("G1-G2", "G3-G2") if k == 1 else ("G1-G4", "G5-G4")
    joints = (
        Revolute(f"I{k}", ("arm", f"idler {k}"), f"I{k}"),
        Revolute(f"P{k}", ("arm", f"planet {k}"), f"P{k}"),
        GearJoint(g_sun, ("ground", f"idler {k}"), ("O", f"I{k}"), curve, "arm", sun),
        GearJoint(g_pl, (f"planet {k}", f"idler {k}"), (f"P{k}", f"I{k}"), curve, "arm", planet),
    )
    return bodies, joints


def idler_mismatch(curve, a: float, beta: float, sun: float, planet: float, n: int = 2048) -> float:
    """Largest difference between the idler pitch curve that the sun mesh implies and the one the
    planet mesh implies (m): an idler is one gear, so the two must agree."""
    psi = 2 * np.pi * np.arange(n) / n
    curves = []
    for law, side in (
        (pitch_law(curve, a, beta - sun), math.pi),
        (pitch_law(curve, a, beta + math.pi - planet), 0.0),
    ):
        turned, _, _ = law(psi)
        theta = np.mod(beta + side - turned, 2 * np.pi)
        radius = a - law.contact_radius(psi)[0]
        o = np.argsort(theta)
        curves.append(
            np.interp(np.linspace(0, 2 * np.pi, 1000, endpoint=False), theta[o], radius[o], period=2 * np.pi)
        )
    return float(np.abs(curves[0] - curves[1]).max())


def sun_orientation(curve, a: float, beta: float, planet: float) -> float:
    """The sun's installation angle (rad) at which each idler is the exact mate of both the sun and
    its planet."""
    scan = np.radians(np.arange(-180.0, 180.0, 10.0))
    start = scan[int(np.argmin([idler_mismatch(curve, a, beta, x, planet) for x in scan]))]
    res = minimize_scalar(
        lambda x: idler_mismatch(curve, a, beta, x, planet),
        bounds=(start - math.radians(10), start + math.radians(10)),
        method="bounded",
        options={"xatol": 1e-10},
    )
    return float(res.x)


def geometry(eps, R, alpha, L, gamma, d):
    """Drawing points (m), the pitch radius ρ (m), the planets' centres of mass, and the
    installation angles of the sun's and planet 2's eccentrics (rad; planet 1's is α).

    Side 2 is installed as side 1 stands half a turn later (the carrier's half turn brings side 1
    where side 2 is), so that the two sides run alike half a turn apart, point-symmetric about the
    sun: its planet, fork and eccentric are turned by the angle planet 1 turns in half a turn.
    """
    a = R / 2
    rho = a / closing_centre_distance(eccentric_circle(1.0, eps)) if eps > 0 else a / 2
    b = math.radians(BETA)
    u = np.array([math.cos(b), math.sin(b)])
    f = np.array([math.cos(math.radians(gamma)), math.sin(math.radians(gamma))])
    pts = {"O": (0.0, 0.0), "I1": tuple(u * a), "P1": tuple(u * R), "F1": tuple(u * R + L * f)}
    com1 = tuple(u * R + d * f)
    curve = eccentric_circle(rho, eps * rho)
    mass = (MASSES["planet"], I_PIVOT["planet"] - MASSES["planet"] * d**2)  # about the centre of mass
    planet = math.radians(alpha)
    sun = sun_orientation(curve, a, b, planet) if eps > 0 else planet
    # side 1 alone, half a turn on: how far has planet 1 turned?
    bodies, joints = _side(curve, pts, com1, mass, sun, planet, 1)
    arm = Body("arm", ("O", "I1", "P1"), MASSES["arm"], I_ARM, "O")
    half = Mechanism(
        pts, (arm, *bodies), (Revolute("O", ("ground", "arm"), "O"), *joints), Driver("arm", "O", "I1", 1.0)
    )
    k = kinematics(half, 4)
    i = int(np.argmin(np.abs(np.angle(np.exp(1j * (k.crank_angle - b - math.pi))))))
    turn = float(k.q[i, 3 * half.body_index["planet 1"] + 2])
    rot = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    f2 = rot @ f
    pts |= {"I2": tuple(-u * a), "P2": tuple(-u * R), "F2": tuple(-u * R + L * f2)}
    com2 = tuple(-u * R + d * f2)
    return pts, rho, (com1, com2), sun, planet + turn


def build(eps=0.13, R=0.0768, alpha=-35.0, L=0.138, gamma=14.0, d=0.020, rpm=200.0) -> Mechanism:
    """The mechanism in Python (angles in degrees, lengths in m)."""
    pts, rho, com, sun, planet2 = geometry(eps, R, alpha, L, gamma, d)
    curve = eccentric_circle(rho, eps * rho)
    mass = (MASSES["planet"], I_PIVOT["planet"] - MASSES["planet"] * d**2)
    b1, j1 = _side(curve, pts, com[0], mass, sun, math.radians(alpha), 1)
    b2, j2 = _side(curve, pts, com[1], mass, sun, planet2, 2)
    arm = Body("arm", ("O", "I1", "P1", "I2", "P2"), MASSES["arm"], I_ARM, "O")
    joints = (Revolute("O", ("ground", "arm"), "O"), *j1[:2], *j2[:2], *j1[2:], *j2[2:])
    return Mechanism(
        pts,
        (arm, b1[0], b1[1], b2[0], b2[1]),
        joints,
        Driver("arm", "O", "I1", f"{rpm} rpm"),
        gravity=(0.0, -9.81),
        name="planting mechanism RP-1",
    )


def metrics(m: Mechanism, n: int) -> dict[str, float]:
    d = inverse_dynamics(m, n)
    gears = [j for j in m.joints if isinstance(j, GearJoint)]
    tooth = max(np.linalg.norm(d.joint_load(j.name, j.bodies[1])[:, :2], axis=1).max() for j in gears)
    bearings = [j for j in m.joints if isinstance(j, Revolute) and j.bodies[0] == "arm"]
    carrier = max(np.linalg.norm(d.joint_load(j.name, j.bodies[1])[:, :2], axis=1).max() for j in bearings)
    T, F = d.driving_torque, d.shaking_force
    return {
        "tooth_force_max_N": float(tooth),
        "carrier_force_max_N": float(carrier),
        "driving_torque_range_Nm": float(np.ptp(T)),
        "shaking_force_x_range_N": float(np.ptp(F[:, 0])),
        "shaking_force_y_range_N": float(np.ptp(F[:, 1])),
    }


def study(n: int, progress: bool = False) -> list[dict[str, object]]:
    """Each variable ±10 % (ε also 0–0.2), the others nominal; ``progress`` reports each variant
    on stderr as it is done (a full run takes about a minute)."""
    cases: list[tuple[str, float | None]] = [("nominal", None)]
    for var, nominal in NOMINAL.items():
        values = [0.9 * nominal, 1.1 * nominal] + ([0.0, 0.05, 0.10, 0.15, 0.20] if var == "eps" else [])
        cases += [(var, v) for v in sorted(values)]
    rows = []
    for k, (var, v) in enumerate(cases):
        params = NOMINAL if v is None else NOMINAL | {var: v}
        rows.append({"variable": var, "value": v, **metrics(build(**params), n)})
        if progress:
            print(f"[{k + 1}/{len(cases)}] {var} = {v if v is not None else 'nominal'}", file=sys.stderr)
    return rows


def toml_text() -> str:
    """The example file, from the nominal design."""
    pts, rho, com, sun, planet2 = geometry(**NOMINAL)
    mm = lambda xy: f'["{xy[0] * 1e3:.6f} mm", "{xy[1] * 1e3:.6f} mm"]'  # noqa: E731
    ip = I_PIVOT["planet"] - MASSES["planet"] * NOMINAL["d"] ** 2
    lines = [
        "# Reference machine D: the gear-type rotary planting mechanism RP-1 (SPEC §6), written by",
        "# examples/transplanter_rp1.py --write from its published design data (see that script):",
        f"# ε = {NOMINAL['eps']}, α = {NOMINAL['alpha']}°, β = {BETA}°, R = {NOMINAL['R'] * 1e3} mm, "
        f"L = {NOMINAL['L'] * 1e3} mm, γ = {NOMINAL['gamma']}°,",
        f"# d = {NOMINAL['d'] * 1e3} mm (not published: pivot to centre of mass of planet + fork, along",
        "# the fork). The sun and planets are eccentric circles",
        f"# (ρ = {rho * 1e3:.4f} mm, sized so that the mates close at",
        "# R/2); each idler is their exact pure-rolling mate. Carrier at 200 rpm, gravity on.",
        "",
        "[model]",
        'type = "mechanism"',
        'name = "planting mechanism RP-1"',
        'source = "SPEC §6 (published design RP-1); d and the arm inertia chosen: see transplanter_rp1.py"',
        "",
        "[points]",
        *[f"{k} = {mm(v)}" for k, v in pts.items()],
        "",
    ]
    bodies = [
        ("arm", '["O", "I1", "P1", "I2", "P2"]', MASSES["arm"], I_ARM, '"O"'),
        ("idler 1", '["I1"]', MASSES["idler"], I_PIVOT["idler"], '"I1"'),
        ("planet 1", '["P1", "F1"]', MASSES["planet"], ip, mm(com[0])),
        ("idler 2", '["I2"]', MASSES["idler"], I_PIVOT["idler"], '"I2"'),
        ("planet 2", '["P2", "F2"]', MASSES["planet"], ip, mm(com[1])),
    ]
    for name, points, mass, inertia, c in bodies:
        lines += [
            "[[bodies]]",
            f'name = "{name}"',
            f"points = {points}",
            f'mass = "{mass} kg"',
            f'inertia = "{inertia:.6g} kg*m^2"',
            f"center_of_mass = {c}",
            "",
        ]
    for name, a, b in (
        ("O", "ground", "arm"),
        ("I1", "arm", "idler 1"),
        ("P1", "arm", "planet 1"),
        ("I2", "arm", "idler 2"),
        ("P2", "arm", "planet 2"),
    ):
        lines += [
            "[[joints]]",
            f'name = "{name}"',
            'type = "revolute"',
            f'bodies = ["{a}", "{b}"]',
            f'point = "{name}"',
            "",
        ]
    pitch = f'{{ kind = "eccentric", radius = "closing", eccentricity_ratio = {NOMINAL["eps"]} }}'
    for name, g1, g2, p1, p2, orient in (
        ("G1-G2", "ground", "idler 1", "O", "I1", math.degrees(sun)),
        ("G3-G2", "planet 1", "idler 1", "P1", "I1", NOMINAL["alpha"]),
        ("G1-G4", "ground", "idler 2", "O", "I2", math.degrees(sun)),
        ("G5-G4", "planet 2", "idler 2", "P2", "I2", math.degrees(planet2)),
    ):
        lines += [
            "[[joints]]",
            f'name = "{name}"',
            'type = "gear"',
            f'bodies = ["{g1}", "{g2}"]',
            f'points = ["{p1}", "{p2}"]',
            'carrier = "arm"',
            f"pitch = {pitch}",
            f'orientation = "{orient:.9f} deg"',
            'pressure_angle = "20 deg"',
            "",
        ]
    lines += [
        "[driver]",
        'body = "arm"',
        'pivot = "O"',
        'tip = "I1"',
        'speed = "200 rpm"',
        "",
        "[settings]",
        'gravity = ["0 m/s^2", "-9.81 m/s^2"]',
        "n_angles = 360",
        'trace = ["F1", "F2"]  # the fork tips',
        f'field_velocity = ["{FIELD_VELOCITY} m/s", "0 m/s"]  # the machine over the field',
        "",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="72 angles per turn")
    ap.add_argument("--json", action="store_true", help="print the table as JSON")
    ap.add_argument("--write", action="store_true", help="write examples/transplanter_rp1.toml")
    args = ap.parse_args(argv)
    if args.write:
        (HERE / "transplanter_rp1.toml").write_text(toml_text(), encoding="utf-8")
        print(f"wrote {HERE / 'transplanter_rp1.toml'}")
        return 0
    rows = study(72 if args.quick else 360, progress=not args.json)
    if args.json:
        print(json.dumps(rows, indent=2))
        return 0
    head = [
        "variable",
        "value",
        "tooth max [N]",
        "carrier max [N]",
        "torque range [N·m]",
        "shake x [N]",
        "shake y [N]",
    ]
    print("  ".join(f"{h:>18s}" for h in head))
    for r in rows:
        v = "" if r["value"] is None else f"{r['value']:.4g}"
        vals = [r[k] for k in list(r)[2:]]
        print(f"{r['variable']:>18s}  {v:>18s}  " + "  ".join(f"{x:18.3f}" for x in vals))
    return 0


if __name__ == "__main__":
    sys.exit(main())
