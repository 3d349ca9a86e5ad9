"""Counterweights (``mechdyn.balance``): the linear maps against the inverse dynamics, complete force
balance of a four-bar against Berkof & Lowen's closed form, the exact solution against a brute-force
minimisation, counterweights in the model file, bad input, and what counterweights buy press A."""

from __future__ import annotations

import dataclasses
import json
import warnings

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.balance import CounterweightSlot, balance, influence
from mechdyn.balance.solve import Evaluator
from mechdyn.errors import ModelError, ModelFileError
from mechdyn.mechanism import Counterweight, inverse_dynamics
from mechdyn.mechanism.summary import model_tables

FOURBAR = EXAMPLES / "fourbar.toml"
PRESS = EXAMPLES / "press_link_drive.toml"
MOUNTS = EXAMPLES / "press_on_mounts.toml"


def _load(path):
    return mechdyn.load(path).model


def _channels(mechanism, n=360):
    d = inverse_dynamics(mechanism, n)
    return np.column_stack([d.shaking_force, d.shaking_moment(), d.driving_torque])


# -- the linear maps are the inverse dynamics ---------------------------------------------------------


@pytest.mark.parametrize(
    ("path", "links", "mass", "reach"),
    [
        (FOURBAR, ("crank", "coupler", "rocker"), 0.3, 0.1),
        (PRESS, ("crank", "ternary", "rocker", "connecting rod"), 300.0, 1.0),
    ],
    ids=["fourbar with gravity", "press A"],
)
def test_the_linear_maps_give_the_inverse_dynamics_of_the_loaded_model(path, links, mass, reach):
    """Counterweights with their own inertia on every link: the force, moment and torque the maps
    predict are those of mechdyn's inverse dynamics of the model with the counterweights folded in."""
    m = _load(path)
    infl = influence(m, links)
    rng = np.random.default_rng(7)
    L = len(links)
    design = np.column_stack([rng.uniform(0.5, 3.0, L) * mass, rng.uniform(-reach, reach, (L, 2))])
    cws = tuple(dataclasses.replace(c, inertia=0.2 * c.mass * reach**2) for c in infl.counterweights(design))
    got = _channels(dataclasses.replace(m, counterweights=cws))
    x = []
    for (mm, u, v), c in zip(design, cws, strict=True):
        x += [mm, mm * u, mm * v, c.inertia + mm * (u * u + v * v)]
    predicted = infl.channels(np.array(x))
    change = np.abs(got - infl.base).max(axis=0)
    assert np.all(change > 0)
    np.testing.assert_array_less(np.abs(predicted - got).max(axis=0), 1e-9 * change)


# -- Berkof & Lowen (1969): complete shaking-force balance of a four-bar --------------------------------


def _closed_form(m):
    """The counterweights' mass moments (complex, drawing axes) about O2 and O4 that balance the
    four-bar completely (Berkof & Lowen 1969, linearly independent vectors): the crank's total
    m1 r1 = m2 L1 (c2/L2 − 1), the rocker's total m3 r3 = −m2 (c2/L2) L3, with L1 = A − O2,
    L2 = B − A, L3 = B − O4 and c2 the coupler's centre of mass from A."""
    z = {k: complex(*v) for k, v in m.points.items()}
    body = {b.name: b for b in m.bodies}
    com = {n: complex(*m.com(b)) for n, b in body.items()}
    L1, L2, L3 = z["A"] - z["O2"], z["B"] - z["A"], z["B"] - z["O4"]
    m2, c2 = body["coupler"].mass, com["coupler"] - z["A"]
    crank = m2 * L1 * (c2 / L2 - 1) - body["crank"].mass * (com["crank"] - z["O2"])
    rocker = -m2 * (c2 / L2) * L3 - body["rocker"].mass * (com["rocker"] - z["O4"])
    return crank, rocker


def test_a_fourbar_is_completely_force_balanced_as_berkof_and_lowen_give_it():
    m = _load(FOURBAR)
    slots = [CounterweightSlot(k, (0, "10 kg"), (0, "100 mm")) for k in ("crank", "rocker")]
    result = balance(m, slots, "shaking_force_rms", front=False)
    assert result.exact and result.method.startswith("exact")
    # the counterweights found carry the closed form's mass moments
    want = _closed_form(m)
    z = {k: complex(*v) for k, v in m.points.items()}
    for cw, pivot, w in zip(result.counterweights, ("O2", "O4"), want, strict=True):
        got = cw.mass * (complex(*cw.position) - z[pivot])
        print(f"{cw.body}: {cw.mass:.6g} kg at {cw.position} m; m·r {got:.6g} kg·m, closed form {w:.6g}")
        assert abs(got - w) < 1e-9 * abs(w)
        assert cw.mass == pytest.approx(abs(w) / 0.1, rel=1e-9)  # carried at the largest radius
    # mechdyn's own inverse dynamics of the balanced model: a constant shaking force (the weight, down)
    before = inverse_dynamics(m, 360).shaking_force
    after = inverse_dynamics(result.mechanism, 360).shaking_force
    swing = np.abs(after - after.mean(axis=0)).max()
    print(f"shaking force swing {np.abs(before - before.mean(axis=0)).max():.4g} N → {swing:.3g} N")
    assert swing < 1e-9 * np.abs(before - before.mean(axis=0)).max()
    total = sum(b.mass for b in result.mechanism.bodies)
    np.testing.assert_allclose(after.mean(axis=0), [0.0, -total * 9.81], atol=1e-9 * total * 9.81)
    assert (
        result.summary()["shaking_force_rms_after_N"] < 1e-9 * result.summary()["shaking_force_rms_before_N"]
    )


# -- the exact solution is the minimum ---------------------------------------------------------------


@pytest.mark.parametrize("statistic", ["rms", "range"])
def test_the_exact_force_solution_equals_a_brute_force_minimisation(statistic):
    """Press A, crank and rocker: the least-squares (RMS) or linear-programme (range) design against
    scipy's Nelder–Mead on the same objective from several starts, with bounds wide enough not to
    bind."""
    from scipy.optimize import minimize

    m = _load(PRESS)
    slots = [CounterweightSlot(k, (0, "500 t"), (0, "2 m")) for k in ("crank", "rocker")]
    result = balance(m, slots, f"shaking_force_{statistic}", front=False)
    assert result.exact
    ev = Evaluator(result.influence)
    name = f"shaking_force_{statistic}"

    def f(z):  # mass moments (m u, m v) per link, t·m, at the largest radius
        mu = np.asarray(z).reshape(2, 2) * 1e3
        design = np.column_stack([np.hypot(*mu.T) / 2.0, np.full(2, 2.0), np.arctan2(mu[:, 1], mu[:, 0])])
        return float(ev.metrics(ev.coefficients(design), [name])[name])

    best = min(
        (
            minimize(f, z0, method="Nelder-Mead", options={"xatol": 1e-6, "fatol": 1e-3, "maxiter": 20000})
            for z0 in ([0, 0, 0, 0], [20, -20, -20, -20], [-10, -60, -80, -100])
        ),
        key=lambda r: r.fun,
    )
    found = result.after[name]
    print(f"{name}: exact {found:.6g} N, Nelder–Mead {best.fun:.6g} N")
    assert found <= best.fun * (1 + 1e-6)
    assert found == pytest.approx(best.fun, rel=1e-3 if statistic == "rms" else 2e-2)


# -- counterweights in the model file -----------------------------------------------------------------


def test_counterweights_fold_into_their_link_and_come_back_from_a_saved_file(tmp_path):
    m = _load(PRESS)
    cws = (
        Counterweight("crank", "20 t", ["-300 mm", "0 mm"], "5 kg*m^2"),
        Counterweight("rocker", "1 t", "D", name="rocker weight"),
    )
    loaded = dataclasses.replace(m, counterweights=cws)
    crank = loaded.bodies[0]
    assert crank.mass == pytest.approx(m.bodies[0].mass + 20e3)
    com = (m.bodies[0].mass * 0.314871117 - 20e3 * 0.3) / crank.mass
    assert crank.center_of_mass[0] == pytest.approx(com)
    inertia = 16.6493 + m.bodies[0].mass * (0.314871117 - com) ** 2 + 5 + 20e3 * (0.3 + com) ** 2
    assert crank.inertia == pytest.approx(inertia, rel=1e-12)
    assert loaded.bare_bodies == m.bodies
    assert dataclasses.replace(loaded, name="x").bodies == loaded.bodies  # not folded twice
    assert dataclasses.replace(loaded, counterweights=()) == m
    path = mechdyn.save(loaded, tmp_path / "with_counterweights.toml")
    text = path.read_text()
    assert text.count("[[counterweights]]") == 2 and 'name = "rocker weight"' in text
    again = mechdyn.load(path).model
    assert again == loaded and again.counterweights == cws
    tables = loaded.to_frame(), model_tables(loaded)
    assert tables[1][-1].title.endswith("the counterweights") and len(tables[1][-1].rows) == 2


def _press_with(tmp_path, rows):
    text = PRESS.read_text() + "\n" + rows
    path = tmp_path / "press_cw.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize(
    ("row", "words"),
    [
        (
            '[[counterweights]]\nbody = "flywheel"\nmass = "2 t"\nposition = ["-300 mm", "0 mm"]\n',
            ["[[counterweights]] #1", "body", "'flywheel'", "put the counterweight on one of", "crank"],
        ),
        (
            '[[counterweights]]\nbody = "crank"\nmass = "-2 t"\nposition = ["-300 mm", "0 mm"]\n',
            ["[[counterweights]] #1", "mass", "-2000 kg", "must not be negative"],
        ),
        (
            '[[counterweights]]\nbody = "crank"\nmass = "2 t"\nposition = "Q"\n',
            ["[[counterweights]] #1", "position", "'Q'", "points: A"],
        ),
    ],
    ids=["unknown link", "negative mass", "unknown point"],
)
def test_a_bad_counterweight_in_a_file_names_file_field_value_and_fix(row, words, tmp_path):
    path = _press_with(tmp_path, row)
    with pytest.raises(ModelFileError) as err:
        mechdyn.load(path)
    message = str(err.value)
    print(message)
    assert str(path) in message or path.name in message
    for w in words:
        assert w in message


def test_bad_balance_input_names_the_field_and_the_fix():
    m = _load(FOURBAR)
    with pytest.raises(
        ModelError, match=r"'links'.*'flywheel' is not defined; links: crank, coupler, rocker"
    ):
        balance(m, ["flywheel"])
    with pytest.raises(ModelError, match=r"'mass'.*-1"):
        CounterweightSlot("crank", ("-1 kg", "2 kg"))
    with pytest.raises(ModelError, match=r"min 2 is above max 1; give \(min, max\)"):
        CounterweightSlot("crank", (0, 1), (2, 1))
    with pytest.raises(ModelError, match=r"'floor_force_rms' is not an objective \(the floor force needs"):
        balance(m, ["crank"], "floor_force_rms")
    with pytest.raises(ModelError, match="choose from shaking_force_rms"):
        balance(m, ["crank"], "force")


# -- press A: what counterweight buys -----------------------------------------------------------------


def test_press_a_counterweights_cut_the_floor_force(capsys):
    """Press A on its four mounts: counterweights of at most 60 t at most 1.5 m from the crank's and the
    rocker's pivots, chosen for the floor force's range (the transmitted-force fluctuation)."""
    sp = mechdyn.load(MOUNTS)
    e = sp.settings.excitation
    lines = []
    for links in (["crank"], ["crank", "rocker"]):
        slots = [CounterweightSlot(k, (0, "60 t"), (0, "1.5 m")) for k in links]
        r = balance(
            e.mechanism, slots, "floor_force_range", support=sp.model, placement=e.placement, front=False
        )
        s = r.summary()
        before, after = s["floor_force_range_before_N"], s["floor_force_range_after_N"]
        where = ", ".join(
            f"{d['mass_kg'] / 1e3:.1f} t at {d['radius_m'] * 1e3:.0f} mm, {d['angle_deg']:.0f}° on the {k}"
            for k, d in s["counterweights"].items()
        )
        lines.append(
            f"press A, {where}: floor force range {before / 1e3:.0f} kN → {after / 1e3:.0f} kN "
            f"({100 * (after / before - 1):+.0f} %)"
        )
        assert after < 0.8 * before
        # the floor force the maps give is the support's steady state of the balanced press
        from mechdyn.support.excitation import PeriodicLoad
        from mechdyn.support.response import periodic_response

        dyn = inverse_dynamics(r.mechanism, e.angles)
        floor = periodic_response(sp.model, PeriodicLoad.from_mechanism(dyn, e.placement)).floor_force
        x = Evaluator(r.influence).coefficients(r.design)
        np.testing.assert_allclose(r.floor.force(x), floor, atol=1e-9 * np.abs(floor).max())
    with capsys.disabled():
        print("\n" + "\n".join(lines))


def test_the_balance_command_runs_on_a_mechanism_and_on_a_support_file(tmp_path, monkeypatch, capsys):
    from mechdyn.cli.main import main

    monkeypatch.setenv("MECHDYN_DB", str(tmp_path / "b.db"))
    monkeypatch.chdir(tmp_path)
    assert main(["balance", str(PRESS), "--links", "crank", "rocker", "--radius-max", "1.5 m", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["shaking_force_rms_after_N"] < doc["shaking_force_rms_before_N"]
    assert set(doc["counterweights"]) == {"crank", "rocker"}
    args = [
        "balance",
        str(PRESS),
        "--support",
        str(MOUNTS),
        "--objective",
        "floor_force_rms=1,driving_torque_rms=0.2",
    ]
    assert main([*args, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["objective_ratio"] < 1 and "floor_force_rms_after_N" in doc
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main(["balance", str(FOURBAR), "--objective", "torque"]) != 0
    assert "not an objective" in capsys.readouterr().err


@pytest.mark.parametrize(
    "objective",
    [
        "shaking_force_peak",
        "shaking_force_range",
        "shaking_moment_rms",
        "driving_torque_range",
        pytest.param(  # the weighted sum of two: 7 s, in CI's heavy step
            {"shaking_force_rms": 1.0, "driving_torque_rms": 0.5}, marks=pytest.mark.slow
        ),
    ],
    ids=str,
)
def test_every_objective_is_no_worse_than_no_counterweight(objective):
    """The linear programmes (peak, range) and the SLSQP polish (moment, torque, weighted sums) never
    end above where they start without counterweights, and the front holds ten weightings."""
    m = _load(FOURBAR)
    slots = [CounterweightSlot(k, (0, "2 kg"), (0, "100 mm")) for k in ("crank", "coupler", "rocker")]
    r = balance(m, slots, objective, front=isinstance(objective, dict))
    s = r.summary()
    assert 0 <= s["objective_ratio"] <= 1 + 1e-9
    if isinstance(objective, str):
        assert (
            s[f"{objective}_after_{'N' if 'force' in objective else 'Nm'}"]
            < s[f"{objective}_before_{'N' if 'force' in objective else 'Nm'}"]
        )
    else:
        assert len(r.front) == 10 and len(r.front_frame()) == 10


def test_a_front_without_a_trade_off_is_one_row_that_says_so():
    """A crank turning at constant speed about the origin, without gravity: its counterweight moves
    neither the shaking moment nor the driving torque, so every weighting finds the same design."""
    press = mechdyn.load(EXAMPLES / "press_link_drive.toml").model
    result = balance(press, [CounterweightSlot("crank", (0, "60 t"), (0, "1.5 m"))], n_angles=72)
    front = next(t for t in result.tables() if t.title.startswith("trade-off front"))
    assert len(front.rows) == 1 and "no trade-off to make" in front.note
    summary = result.tables()[0]
    assert "objective" not in [r[0] for r in summary.rows] and summary.note.startswith("Objective: ")
    assert any("[kN]" in c for c in front.columns)  # forces in the unit a designer reads them in
