"""What a linkage designer reads off the motion: transmission angles, the output's swing, the motion of
every body and traced point, the coupler curves — against closed forms, against finite differences,
on the batched path as on the single one, and through the result protocol to CSV, JSON and the table.

Closed forms: Norton, *Design of Machinery*, §4.10 (transmission angle, toggle positions of a
crank-rocker), Uicker, Pennock & Shigley, *Theory of Machines and Mechanisms*, §1.14.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import replace

import numpy as np
import pytest

from conftest import EXAMPLES
from mechdyn.io import load_model
from mechdyn.mechanism import Body, Driver, Mechanism, Prismatic, Revolute, cycle, inverse_dynamics, variants
from mechdyn.mechanism.batch import cycle_columns
from mechdyn.units import key_unit

# crank-rockers (Grashof, crank shortest): crank a, coupler b, rocker c, ground d, in m
CRANK_ROCKERS = [(0.05, 0.2, 0.15, 0.18), (0.03, 0.11, 0.08, 0.1), (0.1, 0.35, 0.3, 0.25)]
SWING_KEYS = (
    "output_swing_deg",
    "output_angle_min_deg",
    "output_angle_max_deg",
    "crank_angle_at_output_angle_min_deg",
    "crank_angle_at_output_angle_max_deg",
)
TRANSMISSION_KEYS = ("transmission_angle_min_deg", "crank_angle_at_transmission_angle_min_deg")


def _tolerance(key: str) -> float:
    """How closely two solvers agree on a figure, deg: an extreme's value to round-off, the crank
    angle where it lies to about the square root of that (the curve is flat there)."""
    return 1e-6 if key.startswith("crank_angle_at") else 1e-8


def _circle_cross(p: complex, r: float, q: complex, s: float, sign: float) -> complex:
    """The point at r from p and s from q, on the left of p→q for sign = +1."""
    d = abs(q - p)
    x = (d**2 + r**2 - s**2) / (2 * d)
    return p + (q - p) / d * (x + 1j * sign * math.sqrt(r**2 - x**2))


THETA0 = math.radians(60)


def fourbar(a, b, c, d, theta0=THETA0, point=None, w=12.0):
    """Crank a about O2 = (0, 0), coupler b (with a coupler point P at ``point`` = (distance from A,
    angle from A→B, rad)), rocker c about O4 = (d, 0); B above the frame line in the drawing."""
    A = a * complex(math.cos(theta0), math.sin(theta0))
    B = _circle_cross(A, b, complex(d, 0.0), c, 1.0)
    pts = {"O2": (0.0, 0.0), "A": (A.real, A.imag), "B": (B.real, B.imag), "O4": (d, 0.0)}
    coupler = ("A", "B")
    if point is not None:
        P = A + point[0] * (B - A) / abs(B - A) * complex(math.cos(point[1]), math.sin(point[1]))
        pts["P"] = (P.real, P.imag)
        coupler = ("A", "B", "P")
    return Mechanism(
        points=pts,
        bodies=(
            Body("crank", ("O2", "A"), 0.3, 6e-5),
            Body("coupler", coupler, 1.2, 4e-3),
            Body("rocker", ("B", "O4"), 0.9, 1.7e-3),
        ),
        joints=(
            Revolute("O2", ("ground", "crank"), "O2"),
            Revolute("A", ("crank", "coupler"), "A"),
            Revolute("B", ("coupler", "rocker"), "B"),
            Revolute("O4", ("rocker", "ground"), "O4"),
        ),
        driver=Driver("crank", "O2", "A", w),
        name="crank-rocker",
    )


def slider_crank(r=0.1, rod=0.4, w=100.0):
    """An in-line slider-crank: crank r about the origin, connecting rod ``rod``, slider on the x axis."""
    return Mechanism(
        points={"O": (0.0, 0.0), "A": (r, 0.0), "B": (r + rod, 0.0)},
        bodies=(
            Body("crank", ("O", "A"), 2.0, 0.002),
            Body("rod", ("A", "B"), 3.0, 0.04),
            Body("slider", ("B",), 5.0),
        ),
        joints=(
            Revolute("O", ("ground", "crank"), "O"),
            Revolute("A", ("crank", "rod"), "A"),
            Revolute("B", ("rod", "slider"), "B"),
            Prismatic("guide", ("slider", "ground"), "B", 0.0),
        ),
        driver=Driver("crank", "O", "A", w),
    )


def _cos_gamma(a, b, c, d, theta):
    """cos of the coupler–rocker angle: (b² + c² − a² − d² + 2ad cos θ₂) / (2bc)."""
    return (b**2 + c**2 - a**2 - d**2 + 2 * a * d * np.cos(theta)) / (2 * b * c)


def _wrapped(deg):
    """An angle difference in degrees within (−180, 180]."""
    return (np.asarray(deg) + 180.0) % 360.0 - 180.0


@pytest.mark.parametrize(("a", "b", "c", "d"), CRANK_ROCKERS)
@pytest.mark.parametrize("method", ["dyads", "newton"])
def test_the_transmission_angle_of_a_crank_rocker_is_its_closed_form(a, b, c, d, method):
    r = inverse_dynamics(fourbar(a, b, c, d), 360, method)
    gamma = np.degrees(np.arccos(_cos_gamma(a, b, c, d, r.angle)))
    mu = np.minimum(gamma, 180.0 - gamma)  # the acute angle of the pair
    np.testing.assert_allclose(np.degrees(r.kinematics.transmission_angles["B"]), mu, atol=1e-9)
    np.testing.assert_allclose(r.to_frame()["transmission_angle_B_deg"], mu, atol=1e-9)
    # the smallest at θ₂ = 0 or π, whichever gives the angle farther from 90°
    ends = {0.0: _cos_gamma(a, b, c, d, 0.0), 180.0: _cos_gamma(a, b, c, d, math.pi)}
    at = max(ends, key=lambda k: abs(ends[k]))
    want = 90.0 - math.degrees(math.asin(abs(ends[at])))
    s = r.summary()
    assert s["transmission_angle_min_deg"] == pytest.approx(want, abs=1e-9)
    assert _wrapped(s["crank_angle_at_transmission_angle_min_deg"] - at) == pytest.approx(0.0, abs=1e-6)
    dyad = s["dyads"]["B"]
    assert (dyad["kind"], dyad["links"]) == ("RRR", "coupler, rocker")
    assert dyad["transmission_angle_min_deg"] == s["transmission_angle_min_deg"]
    assert dyad["transmission_angle_max_deg"] == pytest.approx(mu.max(), abs=1e-12)


@pytest.mark.parametrize(("a", "b", "c", "d"), CRANK_ROCKERS)
def test_the_rocker_swing_is_the_closed_form_from_the_two_toggle_positions(a, b, c, d):
    s = inverse_dynamics(fourbar(a, b, c, d), 360).summary()

    def toggle(L):  # crank and coupler in line, O2–B = L: the rocker at a limit (B above the frame)
        psi = math.acos((c**2 + d**2 - L**2) / (2 * c * d))  # at O4, from O4→O2
        B = complex(d, 0.0) + c * complex(-math.cos(psi), math.sin(psi))
        return math.degrees(math.pi - psi), B

    extended, B_ext = toggle(a + b)  # the rocker's smallest angle from +x, crank along O2→B
    folded, B_fold = toggle(b - a)  # its largest, crank pointing away from B
    assert s["output_swing_deg"] == pytest.approx(folded - extended, abs=1e-8)
    assert s["output_angle_min_deg"] == pytest.approx(extended, abs=1e-8)
    assert s["output_angle_max_deg"] == pytest.approx(folded, abs=1e-8)
    crank_ext = math.degrees(np.angle(B_ext))
    crank_fold = math.degrees(np.angle(-B_fold))
    assert _wrapped(s["crank_angle_at_output_angle_min_deg"] - crank_ext) == pytest.approx(0.0, abs=1e-5)
    assert _wrapped(s["crank_angle_at_output_angle_max_deg"] - crank_fold) == pytest.approx(0.0, abs=1e-5)


def test_the_example_four_bar_and_its_rocker_output():
    r = inverse_dynamics(load_model(EXAMPLES / "fourbar.toml").model, 360)
    s = r.summary()
    assert s["transmission_angle_min_deg"] == pytest.approx(math.degrees(math.acos(0.76)), abs=1e-7)
    assert s["output_swing_deg"] == pytest.approx(
        math.degrees(math.acos(-7600 / 54000) - math.acos(0.6)), abs=1e-7
    )
    angle = r.to_frame()["output_angle_deg"]  # sampled every degree; the limits lie between samples
    assert 0 <= angle.min() - s["output_angle_min_deg"] < 1e-2
    assert 0 <= s["output_angle_max_deg"] - angle.max() < 1e-2
    assert "stroke_m" not in s and "output_motion.png" in r.plots()


@pytest.mark.parametrize("method", ["dyads", "newton"])
def test_a_slider_crank_strokes_twice_its_crank_and_transmits_best_at_the_dead_centres(method):
    r, rod = 0.1, 0.4
    s = inverse_dynamics(slider_crank(r, rod), 360, method).summary()
    assert s["stroke_m"] == pytest.approx(2 * r, abs=1e-12)
    assert not any(k in s for k in SWING_KEYS)  # a slide's travel is its stroke
    # μ between the rod and the normal to the slider's travel: smallest, acos(r/l), with the crank
    # square to the guide; 90° minus the rod's largest obliquity
    assert s["transmission_angle_min_deg"] == pytest.approx(math.degrees(math.acos(r / rod)), abs=1e-9)
    # equal at 90° and 270°: the first crank angle is reported, whichever solver gave the motion
    assert s["crank_angle_at_transmission_angle_min_deg"] == pytest.approx(90.0, abs=1e-9)
    assert s["transmission_angle_min_deg"] == pytest.approx(
        90.0 - s["output_link_obliquity_max_deg"], abs=1e-9
    )
    assert s["dyads"]["B"]["kind"] == "RRP" and s["dyads"]["B"][
        "transmission_angle_max_deg"
    ] == pytest.approx(90.0)


def test_the_press_reports_both_dyads_and_its_stroke_once():
    r = inverse_dynamics(load_model(EXAMPLES / "press_link_drive.toml").model, 360)
    s = r.summary()
    assert set(s["dyads"]) == {"C", "F"}
    assert s["dyads"]["F"]["links"] == "connecting rod, slide"
    # the slide's dyad: 90° minus the connecting rod's largest obliquity, at the same crank angle
    assert s["dyads"]["F"]["transmission_angle_min_deg"] == pytest.approx(
        90.0 - s["output_link_obliquity_max_deg"], abs=1e-9
    )
    assert s["transmission_angle_min_deg"] == min(
        d["transmission_angle_min_deg"] for d in s["dyads"].values()
    )
    assert not any(k in s for k in SWING_KEYS)
    assert {"transmission_angle.png", "coupler_curves.png", "output_motion.png"} <= set(r.plots())


@pytest.mark.parametrize("method", ["dyads", "newton"])
def test_a_coupler_point_follows_its_direct_geometric_construction(method):
    a, b, c, d = CRANK_ROCKERS[0]
    p, beta = 0.12, math.radians(35)
    mech = fourbar(a, b, c, d, point=(p, beta))
    r = replace(inverse_dynamics(mech, 180, method), trace=("P",))
    frame = r.to_frame()
    A = a * np.exp(1j * r.kinematics.crank_angle)
    B = np.array([_circle_cross(z, b, complex(d, 0.0), c, 1.0) for z in A])
    P = A + p * (B - A) / np.abs(B - A) * np.exp(1j * beta)
    np.testing.assert_allclose(frame["point_P_x_m"], P.real, atol=1e-12)
    np.testing.assert_allclose(frame["point_P_y_m"], P.imag, atol=1e-12)
    from mechdyn.mechanism.plots import coupler_points

    np.testing.assert_allclose(coupler_points(r)["P"], np.stack([P.real, P.imag], -1), atol=1e-12)


def _central(y, h):
    """The derivative of a periodic sampled signal by fourth-order central differences."""
    return (8 * (np.roll(y, -1) - np.roll(y, 1)) - (np.roll(y, -2) - np.roll(y, 2))) / (12 * h)


@pytest.mark.parametrize(
    "case",
    ["fourbar", "press", "slider_crank"],
    ids=["four-bar with a coupler point", "press", "slider-crank"],
)
def test_velocities_and_accelerations_are_the_rates_of_the_positions(case):
    """Finite differences of the tabulated positions give the tabulated velocities, and of those the
    accelerations (the columns come from the differentiated constraints, never from differences)."""
    if case == "press":
        mech = load_model(EXAMPLES / "press_link_drive.toml").model
        traced = ("E",)
    elif case == "fourbar":
        mech = fourbar(*CRANK_ROCKERS[0], point=(0.12, math.radians(35)))
        traced = ("P",)
    else:
        mech = slider_crank()
        traced = ("A",)
    n = 720
    r = replace(inverse_dynamics(mech, n), trace=traced)
    frame = r.to_frame()
    h = 2 * math.pi / n / abs(mech.driver.speed)  # time between samples, s (constant speed)
    t = frame["time_s"].to_numpy()
    order = np.argsort(t)  # the samples in time order (the table is in crank-angle order)
    prefixes = [f"body_{b.name}" for b in mech.bodies] + [f"point_{p}" for p in traced]
    for name in prefixes:
        for axis in ("x", "y"):
            x = frame[f"{name}_{axis}_m"].to_numpy()[order]
            v = frame[f"{name}_velocity_{axis}_m_per_s"].to_numpy()[order]
            acc = frame[f"{name}_acceleration_{axis}_m_per_s2"].to_numpy()[order]
            scale_v, scale_a = max(np.abs(v).max(), 1e-9), max(np.abs(acc).max(), 1e-9)
            assert np.abs(_central(x, h) - v).max() < 1e-6 * scale_v + 1e-12, (name, axis)
            assert np.abs(_central(v, h) - acc).max() < 1e-6 * scale_a + 1e-12, (name, axis)
    for b in mech.bodies:
        phi = np.unwrap(np.radians(frame[f"body_{b.name}_angle_deg"].to_numpy()[order]))
        w = frame[f"body_{b.name}_angular_velocity_rad_s"].to_numpy()[order]
        closing = 2 * math.pi * round((phi[-1] - phi[0] + (phi[1] - phi[0])) / (2 * math.pi))
        phi = phi - closing * np.arange(n) / n  # a crank's angle grows by a turn: take it out
        assert np.abs(_central(phi, h) + closing / (n * h) - w).max() < 1e-6 * max(np.abs(w).max(), 1e-9), (
            b.name
        )
        alpha = r.kinematics.qdd[:, 3 * mech.body_index[b.name] + 2][order]
        assert np.abs(_central(w, h) - alpha).max() < 1e-6 * max(np.abs(alpha).max(), 1e-9), b.name


def test_the_body_columns_are_the_body_coordinates():
    r = inverse_dynamics(fourbar(*CRANK_ROCKERS[0]), 36)
    frame = r.to_frame()
    i = r.mechanism.body_index["coupler"]
    q, qd = r.kinematics.q, r.kinematics.qd
    np.testing.assert_array_equal(frame["body_coupler_x_m"], q[:, 3 * i])
    np.testing.assert_array_equal(frame["body_coupler_velocity_y_m_per_s"], qd[:, 3 * i + 1])
    np.testing.assert_allclose(
        np.radians(frame["body_coupler_angle_deg"]), np.angle(np.exp(1j * q[:, 3 * i + 2]))
    )
    assert (frame["body_crank_angle_deg"].abs() <= 180.0).all()


# -- the batched path ----------------------------------------------------------------------------
@pytest.mark.parametrize("example", ["fourbar.toml", "press_link_drive.toml", "slider_crank.toml"])
@pytest.mark.parametrize("store_points", [True, False])
def test_the_batched_and_single_paths_give_the_same_figures(example, store_points):
    mech = load_model(EXAMPLES / example).model
    single = inverse_dynamics(mech, 180, "newton").summary()
    batch = cycle(mech, 180, store_points=store_points).summary()
    keys = [k for k in (*TRANSMISSION_KEYS, *SWING_KEYS) if k in single]
    assert keys and {k for k in (*TRANSMISSION_KEYS, *SWING_KEYS) if k in batch} == set(keys)
    for k in keys:
        assert batch[k].shape == (1,)
        assert float(batch[k][0]) == pytest.approx(single[k], abs=_tolerance(k)), k


def test_variants_each_get_their_own_transmission_angle_and_swing():
    models = [fourbar(*dims) for dims in CRANK_ROCKERS]
    batch = variants(models, 180, store_points=False).summary()
    for v, m in enumerate(models):
        single = inverse_dynamics(m, 180).summary()
        for k in (*TRANSMISSION_KEYS, *SWING_KEYS):
            assert float(batch[k][v]) == pytest.approx(single[k], abs=_tolerance(k)), (v, k)


def test_a_study_reads_the_new_figures_from_the_batch_columns():
    """The study path (mechdyn.mechanism.batch): varying the rocker's pivot, each variant's smallest
    transmission angle and swing are those of its own model; one that cannot assemble is NaN."""
    base = load_model(EXAMPLES / "fourbar.toml").model
    xs = np.array([0.17, 0.18, 0.19, 0.5])  # the last: the rocker cannot reach round the turn
    batch = cycle_columns(base, {("points", "O4", 0): xs}, 90)
    summary = batch.summary()
    assert set(batch.failures) == {3}
    for v, x in enumerate(xs[:3]):
        model = replace(base, points={**base.points, "O4": (float(x), 0.0)})
        single = inverse_dynamics(model, 90).summary()
        for k in (*TRANSMISSION_KEYS, *SWING_KEYS):
            assert float(summary[k][v]) == pytest.approx(single[k], abs=_tolerance(k)), (v, k)
    assert all(np.isnan(summary[k][3]) for k in (*TRANSMISSION_KEYS, *SWING_KEYS))
    from mechdyn.mechanism.batch import summary_columns

    got = summary_columns(summary, ["transmission_angle_min_deg", "output_swing_deg"], 4)
    assert got["transmission_angle_min_deg"].shape == (4,)


def test_a_link_that_turns_right_round_has_no_swing():
    """A drag link (double crank): the output link pinned to the frame turns a whole turn."""
    a, b, c, d = 0.2, 0.25, 0.22, 0.05  # the frame shortest: both frame links turn fully
    mech = fourbar(a, b, c, d, theta0=math.radians(90))
    s = inverse_dynamics(mech, 180).summary()
    assert not any(k in s for k in SWING_KEYS) and "transmission_angle_min_deg" in s
    batch = cycle(mech, 180, store_points=False).summary()
    assert np.isnan(batch["output_swing_deg"]).all()


# -- through the result protocol: table, CSV, JSON, the stored arrays, the terminal -------------------
COUPLER_FILE = """
[model]
type = "mechanism"
name = "four-bar with a coupler point"

[points]
O2 = ["0 mm", "0 mm"]
A = ["25.000000 mm", "43.301270 mm"]
B = ["194.608480 mm", "149.286946 mm"]
O4 = ["180 mm", "0 mm"]
P = ["150 mm", "160 mm"]

[[bodies]]
name = "crank"
points = ["O2", "A"]
mass = "0.3 kg"
inertia = "6.25e-5 kg*m^2"

[[bodies]]
name = "coupler"
points = ["A", "B", "P"]
mass = "1.2 kg"
inertia = "4.0e-3 kg*m^2"

[[bodies]]
name = "rocker"
points = ["B", "O4"]
mass = "0.9 kg"
inertia = "1.6875e-3 kg*m^2"

[[joints]]
name = "O2"
type = "revolute"
bodies = ["ground", "crank"]
point = "O2"

[[joints]]
name = "A"
type = "revolute"
bodies = ["crank", "coupler"]
point = "A"

[[joints]]
name = "B"
type = "revolute"
bodies = ["coupler", "rocker"]
point = "B"

[[joints]]
name = "O4"
type = "revolute"
bodies = ["rocker", "ground"]
point = "O4"

[driver]
body = "crank"
pivot = "O2"
tip = "A"
speed = "12 rad/s"

[settings]
trace = ["P"]
"""

NEW_COLUMNS = {
    "body_coupler_x_m",
    "body_coupler_y_m",
    "body_coupler_angle_deg",
    "body_coupler_velocity_x_m_per_s",
    "body_coupler_angular_velocity_rad_s",
    "body_coupler_acceleration_y_m_per_s2",
    "point_P_x_m",
    "point_P_y_m",
    "point_P_velocity_x_m_per_s",
    "point_P_acceleration_y_m_per_s2",
    "transmission_angle_B_deg",
    "output_angle_deg",
    "output_angular_velocity_rad_s",
}


def test_the_new_columns_and_figures_reach_csv_json_the_store_and_the_terminal(tmp_path, monkeypatch, capsys):
    from mechdyn.cli.main import main
    from mechdyn.registry import get

    model = tmp_path / "coupler.toml"
    model.write_text(COUPLER_FILE)
    monkeypatch.setenv("MECHDYN_DB", str(tmp_path / "runs.db"))
    monkeypatch.chdir(tmp_path)
    csv, plots = tmp_path / "table.csv", tmp_path / "plots"
    assert (
        main(["mechanism", str(model), "--csv", str(csv), "--plots", str(plots), "--angles", "72", "--json"])
        == 0
    )
    doc = json.loads(capsys.readouterr().out)
    assert {*TRANSMISSION_KEYS, *SWING_KEYS, "dyads"} <= set(doc)
    assert doc["dyads"]["B"]["links"] == "coupler, rocker"
    # the table as the command line writes it, and as the result gives it
    header = csv.read_text().splitlines()[0].split(",")
    assert NEW_COLUMNS <= set(header)
    result = get("mechanism").run(load_model(model), angles=72)
    frame = result.to_frame()
    assert NEW_COLUMNS <= set(frame.columns)
    assert all(key_unit(c) for c in frame.columns)
    rows = np.loadtxt(csv, delimiter=",", skiprows=1)
    for c in ("point_P_x_m", "transmission_angle_B_deg", "output_angle_deg"):
        np.testing.assert_allclose(rows[:, header.index(c)], frame[c], rtol=1e-9)
    # every summary key is a registered output with its unit; the stored arrays carry the columns
    assert set(result.summary()) <= set(get("mechanism").output_units)
    arrays = result.arrays()
    assert arrays["transmission_angle_B_deg"][1] == "deg" and arrays["point_P_y_m"][1] == "m"
    assert {"transmission_angle.png", "coupler_curves.png", "output_motion.png"} <= {
        p.name for p in plots.iterdir()
    }
    # the stored run keeps the figures
    assert main(["results", "show", str(doc["run_id"]), "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown["scalars"]["transmission_angle_min_deg"] == pytest.approx(doc["transmission_angle_min_deg"])
    # the terminal: words, not keys, and the unit; at least three significant digits
    assert main(["mechanism", str(model), "--angles", "72"]) == 0
    text = capsys.readouterr().out
    for label in ("transmission angle min", "crank angle at transmission angle min", "output swing"):
        line = next(x for x in text.splitlines() if x.strip().startswith(label + " "))
        value = re.search(r"\s(-?\d[\d.]*)\s+deg\s*$", line)
        assert value is not None, line
        digits = value.group(1).replace(".", "").lstrip("-0")
        assert len(digits) >= 3 or float(value.group(1)) == 0.0, line
    assert "transmission angles of the dyads" in text


def test_the_summary_table_labels_the_new_figures_in_words():
    from mechdyn.results import summary_table

    summary = inverse_dynamics(fourbar(*CRANK_ROCKERS[0]), 72).summary()
    rows = {r[0]: r for r in summary_table(summary).rows}
    for label in (
        "transmission angle min",
        "crank angle at transmission angle min",
        "output swing",
        "output angle min",
        "output angle max",
        "crank angle at output angle min",
        "crank angle at output angle max",
    ):
        assert rows[label][2] == "deg" and isinstance(rows[label][1], float), label
    assert not any("_" in label for label in rows)


def test_the_new_plots_draw_the_curves_and_the_smallest_angle():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    r = replace(inverse_dynamics(fourbar(*CRANK_ROCKERS[0], point=(0.12, 0.6)), 72), trace=("P",))
    ax = r.plots()["transmission_angle.png"]()
    assert ax.get_ylabel() == "transmission angle (deg)" and ax.get_xlabel() == "crank angle (deg)"
    texts = [t.get_text() for t in ax.texts]
    assert any(t.startswith(f"{r.summary()['transmission_angle_min_deg']:.1f}°") for t in texts)
    ax = r.plots()["coupler_curves.png"]()
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "P" in labels and ax.get_xlabel() == "x (mm)"
    line = next(ln for ln in ax.get_lines() if ln.get_label() == "P")
    assert np.ptp(line.get_xdata()) > 10.0  # mm
    plt.close("all")


def test_angular_accelerations_are_columns_in_rad_per_s2():
    """Every column names its unit (the result protocol), the angular accelerations in rad/s²."""
    r = inverse_dynamics(fourbar(*CRANK_ROCKERS[0]), 36)
    assert all(key_unit(c) for c in r.to_frame().columns)
    frame = r.to_frame()
    i = r.mechanism.body_index["rocker"]
    np.testing.assert_array_equal(
        frame["body_rocker_angular_acceleration_rad_s2"], r.kinematics.qdd[:, 3 * i + 2]
    )
    np.testing.assert_array_equal(frame["output_angular_acceleration_rad_s2"], r.kinematics.qdd[:, 3 * i + 2])
    assert key_unit("body_rocker_angular_acceleration_rad_s2") == "rad/s^2"
