"""Singular and non-assembly positions are never missed: not between two samples, not on either path.

Three linkages an engineer meets: a four-bar with s + l = p + q (a parallelogram, which reaches a
change point where all four links lie in line), and two four-bars whose coupler and rocker fall just
short of reaching across, so that they jam over a window narrower than the sample spacing (0.3°
between samples 1° apart; 2.6° between samples 5° apart). The change point and the edges of the
window follow in closed form from the link lengths; both engines must name them to 0.01°.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mechdyn.mechanism import Body, Driver, Mechanism, Revolute, cycle, inverse_dynamics
from mechdyn.mechanism.kinematics import AssemblyError, SingularPositionError


def fourbar(a, b, c, d, frame_deg=0.0, theta_deg=60.0):
    """Crank O2–A (a), coupler A–B (b), rocker B–O4 (c); the frame O2–O4 (d) at ``frame_deg``."""
    O4 = d * np.array([math.cos(math.radians(frame_deg)), math.sin(math.radians(frame_deg))])
    A = a * np.array([math.cos(math.radians(theta_deg)), math.sin(math.radians(theta_deg))])
    e = O4 - A
    L = float(np.linalg.norm(e))
    x = (L**2 + b**2 - c**2) / (2 * L)
    u = e / L
    B = A + x * u + math.sqrt(b**2 - x**2) * np.array([-u[1], u[0]])
    return Mechanism(
        points={"O2": (0.0, 0.0), "A": A, "B": B, "O4": O4},
        bodies=(
            Body("crank", ("O2", "A"), 0.3, 6e-5),
            Body("coupler", ("A", "B"), 1.2, 4e-3),
            Body("rocker", ("B", "O4"), 0.9, 1.7e-3),
        ),
        joints=(
            Revolute("O2", ("ground", "crank"), "O2"),
            Revolute("A", ("crank", "coupler"), "A"),
            Revolute("B", ("coupler", "rocker"), "B"),
            Revolute("O4", ("rocker", "ground"), "O4"),
        ),
        driver=Driver("crank", "O2", "A", 12.0),
    )


def jam(window_deg, frame_deg):
    """A crank 50 mm, frame 180 mm: coupler + rocker fall ε short of a + d, so the loop cannot close
    while the crank points away from O4, over 2δ with ε = δ² a d / (2 (a + d)) (to second order)."""
    a, d, b = 0.05, 0.18, 0.12
    delta = math.radians(window_deg / 2)
    eps = delta**2 * a * d / (2 * (a + d))
    return fourbar(a, b, a + d - eps - b, d, frame_deg=frame_deg)


def _angle(message):
    return float(message.split("crank angle ")[1].split("°")[0])


def _jam_edges(m):
    """The exact crank angles (θ, degrees) where |A − O4| = b + c: the edges of the jam."""
    a, d = 0.05, 0.18
    O4 = np.asarray(m.points["O4"])
    reach = float(
        np.linalg.norm(np.subtract(m.points["B"], m.points["A"])) + np.linalg.norm(O4 - m.points["B"])
    )
    # |A − O4|² = a² + d² − 2 a d cos(θ − frame) = reach²
    half = math.degrees(math.acos((a**2 + d**2 - reach**2) / (2 * a * d)))
    frame = math.degrees(math.atan2(O4[1], O4[0]))
    return frame + half, frame + 360 - half


@pytest.mark.parametrize("method", ["dyads", "newton"])
def test_a_change_point_between_samples_is_named_to_a_hundredth_of_a_degree(method):
    # the parallelogram 40/100/40/100 with its frame at 0.37°: the links lie in line at θ = 180.37°
    m = fourbar(0.04, 0.10, 0.04, 0.10, frame_deg=0.37)
    with pytest.raises(SingularPositionError, match="singular") as info:
        inverse_dynamics(m, 360, method=method)
    assert _angle(str(info.value)) == pytest.approx(180.37, abs=0.01)
    assert "'B'" in str(info.value)  # the joint of the loop that locks


@pytest.mark.parametrize("method", ["dyads", "newton"])
@pytest.mark.parametrize(("window", "frame", "n"), [(0.3, 0.5, 360), (2.6, 2.5, 72), (0.3, 2.5, 72)])
def test_a_jam_between_two_samples_is_found_with_its_joint(method, window, frame, n):
    m = jam(window, frame)
    start, end = _jam_edges(m)
    assert end - start == pytest.approx(window, rel=0.02)  # the construction
    with pytest.raises(AssemblyError, match=r"cannot assemble at crank angle .*joint 'B'") as info:
        inverse_dynamics(m, n, method=method)
    assert _angle(str(info.value)) == pytest.approx(start, abs=0.01)


def test_a_batch_keeps_the_variants_that_pass_and_marks_the_one_that_jams():
    base = jam(0.3, 0.5)
    # variant 1 moves B up 2 mm: a longer coupler and rocker that reach across all the way round
    points = {"B": np.array([base.points["B"], np.asarray(base.points["B"]) + np.array([0.0, 0.002])])}
    with pytest.raises(AssemblyError, match=r"variant 0: cannot assemble at crank angle"):
        cycle(base, 360, points=points)
    batch = cycle(base, 360, points=points, errors="nan")
    assert batch.assembled.tolist() == [False, True]
    assert "cannot assemble at crank angle 180.35°" in batch.failures[0] and 1 not in batch.failures


def test_the_command_line_exits_2_and_names_the_angle(tmp_path, capsys, monkeypatch):
    from mechdyn.cli.main import main

    m = jam(0.3, 0.5)
    # the same linkage as a model file, written from the model (every joint a pin)
    lines = ['[model]\ntype = "mechanism"\nname = "jamming four-bar"\n[points]']
    lines += [f'{k} = ["{x * 1e3:.9f} mm", "{y * 1e3:.9f} mm"]' for k, (x, y) in m.points.items()]
    for b in m.bodies:
        lines.append(
            f'[[bodies]]\nname = "{b.name}"\npoints = {list(b.points)!r}\nmass = "{b.mass} kg"'.replace(
                "'", '"'
            )
        )
    for jt in m.joints:
        bodies = '["' + '", "'.join(jt.bodies) + '"]'
        lines.append(
            f'[[joints]]\nname = "{jt.name}"\ntype = "revolute"\nbodies = {bodies}\npoint = "{jt.point}"'
        )
    lines.append('[driver]\nbody = "crank"\npivot = "O2"\ntip = "A"\nspeed = "12 rad/s"\n')
    text = "\n".join(lines)
    path = tmp_path / "jam.toml"
    path.write_text(text)
    monkeypatch.setenv("MECHDYN_DB", str(tmp_path / "db.sqlite"))
    assert main(["mechanism", str(path)]) == 2
    err = capsys.readouterr().err
    assert "cannot assemble at crank angle 180.35°" in err and "joint 'B'" in err
    assert "Traceback" not in err
