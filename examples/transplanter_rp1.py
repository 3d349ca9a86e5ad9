"""Reference machine D: the gear-type rotary planting mechanism "RP-1" (SPEC §6), written out.

    python examples/transplanter_rp1.py --write    # (re)write examples/transplanter_rp1.toml

``examples/transplanter_rp1_design.toml`` is RP-1 by its design variables (ε, α, β, R, L, γ, d, masses
and inertias about the pivots); mechdyn builds the mechanism from them (``mechdyn.mechanism.planter``).
This script writes the same mechanism body by body, joint by joint, as a plain mechanism file
(``examples/transplanter_rp1.toml``), which the tests compare with what it writes. The sensitivity of
RP-1 to its design variables is a design study: ``mechdyn study examples/studies/rp1_sensitivity.toml``.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from mechdyn.mechanism.planter import PlanterDesign, geometry

HERE = Path(__file__).resolve().parent
FIELD_VELOCITY = -0.8  # m/s along x: the machine's speed over the field (not published; typical)


def deg(x: float) -> float:
    return round(math.degrees(x), 9)


def toml_text() -> str:
    """The example file, from the nominal design."""
    D = PlanterDesign()
    pts, rho, com, sun, planet2 = geometry(D)
    mm = lambda xy: f'["{xy[0] * 1e3:.6f} mm", "{xy[1] * 1e3:.6f} mm"]'  # noqa: E731
    ip = D.planet_inertia - D.planet_mass * D.com_offset**2
    lines = [
        "# Reference machine D: the gear-type rotary planting mechanism RP-1 (SPEC §6), written by",
        "# examples/transplanter_rp1.py --write from its published design data (see that script):",
        f"# ε = {D.eccentricity_ratio}, α = {deg(D.alpha)}°, β = {deg(D.beta)}°, "
        f"R = {D.arm_radius * 1e3} mm, "
        f"L = {D.fork_length * 1e3} mm, γ = {deg(D.fork_angle)}°,",
        f"# d = {D.com_offset * 1e3} mm (not published: pivot to centre of mass of planet + fork, along",
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
        ("arm", '["O", "I1", "P1", "I2", "P2"]', D.arm_mass, D.arm_inertia, '"O"'),
        ("idler 1", '["I1"]', D.idler_mass, D.idler_inertia, '"I1"'),
        ("planet 1", '["P1", "F1"]', D.planet_mass, ip, mm(com[0])),
        ("idler 2", '["I2"]', D.idler_mass, D.idler_inertia, '"I2"'),
        ("planet 2", '["P2", "F2"]', D.planet_mass, ip, mm(com[1])),
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
    pitch = f'{{ kind = "eccentric", radius = "closing", eccentricity_ratio = {D.eccentricity_ratio} }}'
    for name, g1, g2, p1, p2, orient in (
        ("G1-G2", "ground", "idler 1", "O", "I1", math.degrees(sun)),
        ("G3-G2", "planet 1", "idler 1", "P1", "I1", math.degrees(D.alpha)),
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
    ap.add_argument("--write", action="store_true", help="write examples/transplanter_rp1.toml")
    args = ap.parse_args(argv)
    text = toml_text()
    if args.write:
        (HERE / "transplanter_rp1.toml").write_text(text, encoding="utf-8")
        print(f"wrote {HERE / 'transplanter_rp1.toml'}")
    else:
        print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
