"""Counterweights with a cost (issue 44, item 3): budgets of total added mass and rotary inertia, the
lightest design among equal ones, the minimax (peak) solved to its optimum, the rocking rocker's
inertia in the floor force, and the mass front of press A — each against a reference that does not
share mechdyn's solver."""

from __future__ import annotations

import json

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.balance import CounterweightSlot, balance
from mechdyn.balance.solve import Evaluator
from mechdyn.errors import ModelError

PRESS = EXAMPLES / "press_link_drive.toml"
MOUNTS = EXAMPLES / "press_on_mounts.toml"


@pytest.fixture(scope="module")
def press_a():
    """Press A on its four mounts: the mechanism, the machine and where the press sits in it."""
    sp = mechdyn.load(MOUNTS)
    e = sp.settings.excitation
    return {"mechanism": e.mechanism, "support": sp.model, "placement": e.placement, "n_angles": e.angles}


def _slots(mass, radius, links=("crank", "rocker")):
    return [CounterweightSlot(k, (0, mass), (0, radius)) for k in links]


def _search(ev, slots, name, method, starts, constraints=()):
    """Scipy's own minimisation of ``name`` over each link's (mass, radius, angle) within the slots'
    bounds, on the full linear maps (the rocking links' J + m r² included), best of ``starts``."""
    from scipy.optimize import minimize

    lo = np.array([v for s in slots for v in (s.mass[0], s.radius[0], -np.pi)])
    hi = np.array([v for s in slots for v in (s.mass[1], s.radius[1], 3 * np.pi)])

    def design(z):
        return (lo + np.clip(z, 0, 1) * (hi - lo)).reshape(len(slots), 3)

    def f(z):
        return float(ev.metrics(ev.coefficients(design(z)), [name])[name])

    cons = [{"type": "ineq", "fun": (lambda z, g=g: g(design(z)))} for g in constraints]
    best = np.inf
    for z0 in starts:
        z0 = np.clip((np.asarray(z0, dtype=float).ravel() - lo) / (hi - lo), 0, 1)
        opts = {"maxiter": 20000} if method != "SLSQP" else {"maxiter": 1000, "ftol": 1e-14}
        res = minimize(f, z0, method=method, bounds=[(0, 1)] * z0.size, constraints=cons, options=opts)
        if all(g(design(res.x)) >= -1e-9 for g in constraints):  # SLSQP may end outside
            best = min(best, f(res.x))
    return best


# -- the minimax, solved to its optimum ------------------------------------------------------------


def _epigraph_peak(ev, quantity, links):
    """The peak's optimum by SLSQP on its smooth epigraph form, min t subject to t² ≥ |F(θ_i) − F̄|² at
    every crank angle, over the links' mass moments (bounds too wide to bind): no linear programme and
    no sampled directions."""
    from scipy.optimize import minimize

    if quantity == "floor_force":
        cols, base = ev.floor.columns, ev.floor.base
    else:
        cols, base = ev.infl.columns[:, :2], ev.infl.base[:, :2]
    free = [4 * k + j for k in range(len(links)) for j in (1, 2)]
    A = cols[:, :, free] - cols[:, :, free].mean(axis=0)
    b = base - base.mean(axis=0)
    scale, P = 1e5, float(np.sqrt((b**2).sum(axis=1)).max())

    def squares(y):
        f = (A @ (y[:-1] * scale) + b) / P
        return y[-1] ** 2 - (f**2).sum(axis=1)

    y0 = np.r_[np.zeros(len(free)), 1.0]
    res = minimize(
        lambda y: y[-1],
        y0,
        jac=lambda y: np.r_[np.zeros(len(free)), 1.0],
        constraints=[{"type": "ineq", "fun": squares}],
        method="SLSQP",
        options={"ftol": 1e-14, "maxiter": 1000},
    )
    assert res.success, res.message
    return float(np.sqrt(((A @ (res.x[:-1] * scale) + b) ** 2).sum(axis=1)).max())


@pytest.mark.parametrize(
    ("quantity", "links"),
    [("shaking_force", ("crank", "rocker")), ("floor_force", ("crank",))],
    ids=["shaking force, crank and rocker", "floor force, crank"],
)
def test_the_peak_is_solved_to_its_minimax_optimum(press_a, quantity, links):
    """Press A, counterweights up to 500 t at up to 2 m: the peak of the force's fluctuation (the
    largest magnitude over the cycle) equals the optimum of its epigraph form to 1e-6, and says so.
    32 sampled directions left the shaking force 0.21 % and the floor force (26 directions in space)
    4.3 % above it."""
    name = f"{quantity}_peak"
    kw = (
        {"support": press_a["support"], "placement": press_a["placement"]}
        if quantity == "floor_force"
        else {}
    )
    r = balance(press_a["mechanism"], _slots("500 t", "2 m", links), name, front=False, **kw)
    reference = _epigraph_peak(Evaluator(r.influence, r.floor), quantity, links)
    found = r.after[name]
    print(f"{name}: mechdyn {found:.7g} N, epigraph SLSQP {reference:.7g} N ({found / reference - 1:+.1e})")
    assert r.exact and r.method.startswith("exact")
    assert found == pytest.approx(reference, rel=1e-6)
    assert 0 <= r.summary()["optimality_gap_ratio"] < 1e-6


# -- the floor force counts the rocking rocker's inertia ----------------------------------------------


@pytest.mark.parametrize(("statistic", "method"), [("rms", "L-BFGS-B"), ("range", "Powell")])
def test_the_floor_objective_counts_the_rocking_links_inertia(press_a, statistic, method):
    """The rocker swings, so its counterweight's J + m r² moves the floor force. The result is exact
    (the inertia a variable I ≥ ρ²/m of the cone programme) and no search on the full maps, from its
    design or elsewhere, beats it; the design found with that term left out is 3e-5 (RMS) to 4e-3
    (range) worse."""
    name = f"floor_force_{statistic}"
    slots = _slots("60 t", "1.5 m")
    r = balance(press_a["mechanism"], slots, name, front=False, **_mounts(press_a))
    ev = Evaluator(r.influence, r.floor)
    starts = [r.design, [[30e3, 1.5, 4.5], [30e3, 1.5, 4.0]], [[12e3, 1.3, 4.4], [55e3, 1.4, 4.1]]]
    best = _search(ev, r.slots, name, method, starts)
    print(f"{name}: mechdyn {r.after[name]:.8g} N ({r.method}), {method} {best:.8g} N")
    assert r.exact
    assert r.after[name] <= best * (1 + 1e-6)


def _mounts(press_a):
    return {k: press_a[k] for k in ("support", "placement", "n_angles")}


# -- budgets of total mass and inertia ----------------------------------------------------------------


@pytest.mark.parametrize(
    ("budget", "value", "words"),
    [("max_added_mass", "40 t", "total mass ≤ 40 t"), ("max_added_inertia", "6e4 kg*m^2", "total inertia")],
)
def test_a_budget_is_kept_named_and_spent_best(press_a, budget, value, words):
    """Press A on its mounts, the floor force's RMS, up to 60 t at 1.5 m per link and a total budget:
    the design keeps it, the summary names it as the bound that holds the design, and SLSQP on each
    link's (mass, radius, angle) with the budget as its constraint finds nothing better."""
    slots = _slots("60 t", "1.5 m")
    r = balance(
        press_a["mechanism"], slots, "floor_force_rms", front=False, **_mounts(press_a), **{budget: value}
    )
    free = balance(press_a["mechanism"], slots, "floor_force_rms", front=False, **_mounts(press_a))
    s = r.summary()
    limit = s[f"{budget}_{'kg' if budget == 'max_added_mass' else 'kg_m2'}"]
    used = (
        s["counterweight_mass_total_kg"]
        if budget == "max_added_mass"
        else s["counterweight_inertia_total_kg_m2"]
    )
    mass = free.summary()["counterweight_mass_total_kg"]
    print(
        f"{budget} {limit:.4g}: uses {used:.6g}; floor force RMS {s['floor_force_rms_after_N']:.6g} N "
        f"(free: {free.after['floor_force_rms']:.6g} N with {mass:.6g} kg, {free.added_inertia:.6g} kg·m²); "
        f"active: {s['active_bounds']}"
    )
    assert used <= limit * (1 + 1e-9) and used >= limit * (1 - 1e-4)
    assert words in s["active_bounds"]
    assert r.exact and s["floor_force_rms_after_N"] > free.after["floor_force_rms"]

    def spare(d):
        total = d[:, 0].sum() if budget == "max_added_mass" else np.sum(d[:, 0] * d[:, 1] ** 2)
        return 1.0 - total / limit

    half = free.design.copy()
    half[:, 0] /= 2
    ev = Evaluator(r.influence, r.floor)
    best = _search(ev, r.slots, "floor_force_rms", "SLSQP", [r.design, half], [spare])
    assert s["floor_force_rms_after_N"] <= best * (1 + 1e-6)


def test_the_torque_only_end_of_the_front_carries_no_idle_mass(press_a):
    """Press A (no gravity, the crank at constant speed about the origin): the crank's counterweight
    moves neither the driving torque nor the shaking moment. The front's torque-only end carried
    48.7 t and its moment-only end 14 t on the crank; they carry none."""
    r = balance(press_a["mechanism"], _slots("60 t", "1.5 m"), "floor_force_rms", **_mounts(press_a))
    rows = {
        (row["weight_shaking_moment_rms_ratio"], row["weight_driving_torque_rms_ratio"]): row
        for row in r.front
    }
    torque, moment = rows[(0.0, 1.0)], rows[(1.0, 0.0)]
    print(
        f"torque-only: {torque['counterweight_mass_kg']:.3g} kg; moment-only: "
        f"crank {moment['mass_on_crank_kg']:.3g} kg, rocker {moment['mass_on_rocker_kg']:.4g} kg"
    )
    assert torque["counterweight_mass_kg"] == 0.0
    assert torque["driving_torque_range_Nm"] == pytest.approx(r.before["driving_torque_range"], rel=1e-12)
    assert moment["mass_on_crank_kg"] == 0.0 and moment["mass_on_rocker_kg"] > 1e3
    front = next(t for t in r.tables() if t.title.startswith("trade-off front"))
    assert any("mass on crank" in c for c in front.columns)


# -- what mass buys -----------------------------------------------------------------------------------


def test_slack_gives_up_a_stated_fraction_of_the_objective_for_mass(press_a):
    """With loose bounds (500 t at 2 m) the floor force's RMS optimum puts 500 t at 0.18 m on the
    rocker (its rotary inertia rocks the machine); 0.1 % of the objective buys the same with a tenth
    of the mass, near the largest radius."""
    slots = _slots("500 t", "2 m")
    best = balance(press_a["mechanism"], slots, "floor_force_rms", front=False, **_mounts(press_a))
    light = balance(
        press_a["mechanism"], slots, "floor_force_rms", front=False, slack=1e-3, **_mounts(press_a)
    )
    m0, m1 = best.summary()["counterweight_mass_total_kg"], light.summary()["counterweight_mass_total_kg"]
    v0, v1 = best.after["floor_force_rms"], light.after["floor_force_rms"]
    print(
        f"slack 0: {m0 / 1e3:.1f} t, rocker at {best.design[1, 1]:.3f} m, {v0:.6g} N; slack 1e-3: "
        f"{m1 / 1e3:.1f} t, rocker at {light.design[1, 1]:.3f} m, {v1:.6g} N"
    )
    assert best.design[1, 0] > 400e3 and best.design[1, 1] < 0.25
    assert v0 < v1 <= v0 * (1 + 1e-3) * (1 + 1e-6)
    assert m1 < 0.15 * m0 and light.summary()["slack_ratio"] == 1e-3


def test_the_mass_front_states_what_each_tonne_buys(press_a):
    """Press A on its mounts, the floor force's peak, up to 60 t at 1.5 m per link: the mass front
    runs from no counterweight to the design found, each row within its budget, its optimum falling
    and convex in the budget (the value of a convex programme in a constraint's bound), the share of
    the reduction from 0 to 1; the summary says what 90 % of it takes."""
    r = balance(press_a["mechanism"], _slots("60 t", "1.5 m"), "floor_force_peak", **_mounts(press_a))
    rows = r.mass_front
    budget = np.array([row["max_added_mass_kg"] for row in rows])
    used = np.array([row["counterweight_mass_kg"] for row in rows])
    value = np.array([row["floor_force_peak_N"] for row in rows])
    for row in rows:
        print(
            f"{row['max_added_mass_kg'] / 1e3:6.1f} t: {row['floor_force_peak_N'] / 1e3:6.1f} kN "
            f"({row['gain_share_ratio']:.0%} of the reduction)"
        )
    assert used[0] == 0 and value[0] == pytest.approx(r.before["floor_force_peak"], rel=1e-12)
    assert used[-1] == pytest.approx(r.summary()["counterweight_mass_total_kg"], rel=1e-12)
    assert np.all(used <= budget * (1 + 1e-9)) and np.all(np.diff(budget) > 0)
    assert np.all(np.diff(value) < 0)
    slope = np.diff(value) / np.diff(budget)
    assert np.all(np.diff(slope) >= -1e-6 * np.abs(slope).max())
    share = [row["gain_share_ratio"] for row in rows]
    assert share[0] == 0 and share[-1] == pytest.approx(1.0)
    need = r.summary()["mass_for_90_percent_of_gain_kg"]
    assert 0 < need < used[-1]
    table = next(t for t in r.tables() if t.title.startswith("mass front"))
    assert len(table.rows) == len(rows) and "90 % of the reduction" in table.note
    assert "balance_mass_front.png" in r.plots()


# -- the command and bad input ------------------------------------------------------------------------


def test_the_balance_command_takes_the_budgets(tmp_path, monkeypatch, capsys):
    from mechdyn.cli.main import main

    monkeypatch.setenv("MECHDYN_DB", str(tmp_path / "b.db"))
    monkeypatch.chdir(tmp_path)
    argv = [
        *("balance", str(PRESS), "--links", "crank", "rocker", "--radius-max", "1.5 m"),
        *("--max-added-mass", "30 t", "--max-added-inertia", "50000 kg*m^2", "--slack", "0.001", "--json"),
    ]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["max_added_mass_kg"] == 30e3 and doc["max_added_inertia_kg_m2"] == 5e4
    assert doc["counterweight_mass_total_kg"] <= 30e3 * (1 + 1e-9)
    assert doc["counterweight_inertia_total_kg_m2"] <= 5e4 * (1 + 1e-9)
    assert doc["slack_ratio"] == 1e-3 and isinstance(doc["active_bounds"], str)


def test_a_bad_budget_names_the_field_and_the_fix():
    m = mechdyn.load(EXAMPLES / "fourbar.toml").model
    with pytest.raises(ModelError, match=r"'max_added_mass'.*must not be negative"):
        balance(m, ["crank"], max_added_mass="-1 kg")
    with pytest.raises(ModelError, match=r"'max_added_inertia'"):
        balance(m, ["crank"], max_added_inertia="2 m")
    with pytest.raises(ModelError, match=r"slack 1.5 must be a fraction, 0 ≤ slack < 1"):
        balance(m, ["crank"], slack=1.5)
