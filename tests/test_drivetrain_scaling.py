"""Large drivetrains at their algorithm's cost: the banded direct solve, the truncated modal sum with its
residual, the outputs asked for only, chains built from arrays, variants of a built model, and the
finite-value check made once where the model enters. Each fast path is checked against the exact answer
(all modes, or a dense solve) on models small enough for it."""

from __future__ import annotations

import contextlib
import dataclasses
import tracemalloc
import warnings

import numpy as np
import pytest

from mechdyn.drivetrain import (
    Disk,
    Drivetrain,
    GearMesh,
    GroundDamper,
    GroundSpring,
    Shaft,
    frf,
    modal,
)
from mechdyn.drivetrain.response import ModalDamping, RayleighDamping
from mechdyn.errors import ModelError, ModelWarning
from mechdyn.vibration import harmonic_solve


def _values(n, seed=0):
    rng = np.random.default_rng(seed)
    return rng.uniform(0.5, 2.0, n) * 1e-2, rng.uniform(0.5, 2.0, n - 1) * 1e5


def _chain(n, *, ground=False, seed=0, shaft_inertia=0.0, elements=1, damping=None):
    J, k = _values(n, seed)
    disks = [Disk(f"d{i}", J[i]) for i in range(n)]
    shafts = [
        Shaft(
            f"s{i}",
            (f"d{i}", f"d{i + 1}"),
            k[i],
            damping=0.0 if damping is None else damping(i, k[i]),
            inertia=shaft_inertia,
            elements=elements,
        )
        for i in range(n - 1)
    ]
    return Drivetrain(disks, [*shafts, *([GroundSpring("g", "d0", 1e5)] if ground else [])])


def _geared(n=30):
    """Two chains joined by a rigid mesh (reduced out, θ = T q) and a flexible one."""
    J, k = _values(3 * n, 7)
    disks = [Disk(f"d{i}", J[i]) for i in range(3 * n)]
    shafts = [
        Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), k[i]) for i in range(3 * n - 1) if i not in (n - 1, 2 * n - 1)
    ]
    meshes = [
        GearMesh("rigid", (f"d{n - 1}", f"d{n}"), base_radii=(0.06, 0.02)),
        GearMesh("flexible", (f"d{2 * n - 1}", f"d{2 * n}"), base_radii=(0.03, 0.05), stiffness=2e8),
    ]
    return Drivetrain(disks, [*shafts, *meshes])


def _rel(a, b):
    """Largest difference of each column, relative to that column's largest magnitude."""
    scale = np.maximum(np.abs(b).max(axis=0), 1e-300)
    return float((np.abs(a - b).max(axis=0) / scale).max())


# -- the banded direct solve: exact, the same as every mode summed or a dense solve --------------------


@pytest.mark.parametrize(
    "model",
    [
        _chain(300),
        _chain(300, ground=True, damping=lambda i, k: 40.0 if i == 150 else 0.0),
        _chain(80, shaft_inertia=1e-3, elements=3),  # a band of 1 after reordering, M not diagonal
        _geared(80),
    ],
    ids=["free chain", "grounded chain, one damper", "divided shafts", "geared"],
)
def test_the_banded_direct_solve_is_the_exact_response(model):
    f = np.geomspace(0.5, 2e3, 120)
    damping = RayleighDamping(2.0, 3e-6)
    first = model.disk_names[0]
    direct = frf(model, f, {first: 1.0, model.disk_names[5]: 0.4j}, damping=damping, method="direct")
    assert "banded" in direct.method or "as asked" in direct.method
    asm = model.assembly
    # the same response by the vibration core's own solve (SuperLU) on the same matrices
    F = np.zeros(asm.n, dtype=complex)
    dofs = model.dof_index
    for name, amp in direct.excitation.items():
        F += amp * asm.T.toarray()[dofs[name]]
    C = asm.C + damping.alpha * asm.mass_operator() + damping.beta * asm.K
    reference = np.asarray((asm.T @ harmonic_solve(asm.K, C, asm.mass_operator(), F, 2 * np.pi * f).T).T)
    assert _rel(direct.angles, reference) < 1e-9
    if model.assembly.C.nnz == 0:  # proportional damping: every mode summed gives it too
        summed = frf(model, f, direct.excitation, damping=damping, method="modal")
        assert summed.method.startswith("modal superposition over all")
        # the sum's own error is about ε times the largest response, not each column's
        assert _rel(direct.angles, summed.angles) < 1e-8
        assert _rel(direct.element_loads, summed.element_loads) < 1e-8


def test_rayleigh_damping_on_a_large_chain_is_solved_banded_and_a_wide_band_by_superlu(monkeypatch):
    model = _chain(400)
    f = np.geomspace(1.0, 1e3, 60)
    auto = frf(model, f, {"d0": 1.0}, damping=RayleighDamping(1.0, 1e-5))
    assert auto.method.startswith("direct solve at each frequency (Rayleigh damping keeps K, C and M banded")
    assert auto.natural_frequencies_hz.size == 399  # a model of up to 1000 coordinates: all its modes
    monkeypatch.setattr("mechdyn.drivetrain.banded.BAND_LIMIT", 0)  # as if the band were wide
    sparse = frf(model, f, {"d0": 1.0}, damping=RayleighDamping(1.0, 1e-5))
    assert "sparse" in sparse.method
    assert _rel(sparse.angles, auto.angles) < 1e-10


# -- the modes below a cut-off with the residual of the others ----------------------------------------


@pytest.mark.parametrize(
    "model",
    [_chain(60), _chain(60, ground=True), _chain(20, shaft_inertia=1e-3, elements=3), _geared(20)],
    ids=["free chain", "grounded chain", "divided shafts (shift-invert path)", "geared"],
)
@pytest.mark.parametrize(
    "damping", [ModalDamping(0.02), RayleighDamping(1.0, 1e-5)], ids=["modal", "Rayleigh"]
)
def test_the_truncated_sum_is_within_its_estimated_error_and_converges(model, damping):
    f = np.geomspace(0.5, 40.0, 150)
    first = model.disk_names[0]
    exact = frf(model, f, {first: 1.0}, damping=damping)
    assert exact.method.startswith("modal superposition over all") and exact.truncation_error == 0.0
    errors = []
    for cutoff in (3.0, 6.0, 12.0):
        with _quiet():
            cut = frf(model, f, {first: 1.0}, damping=damping, mode_cutoff=cutoff)
        assert cut.summary()["method"] == cut.method
        err = max(_rel(cut.angles, exact.angles), _rel(cut.element_loads, exact.element_loads))
        # the stated accuracy: the estimate bounds each left-out term and takes them to add up; where
        # they partly cancel in the residual it may fall a little short
        assert err <= 1.5 * cut.truncation_error + 1e-12, (cutoff, err, cut.truncation_error)
        if "all" not in cut.method:
            assert "with the residual of the other" in cut.method
            assert f"estimated truncation error {cut.truncation_error:.2g}" in cut.method
        errors.append(err)
    assert errors[-1] < 2e-3  # the residual's ω² term: second order in ω/ω_cut, first in the damping
    assert errors[-1] <= errors[0]


@contextlib.contextmanager
def _quiet():
    """Ignore the truncation warning (tested on its own below)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        yield


def test_a_truncation_that_keeps_every_mode_is_exact_and_a_poor_one_warns():
    model = _chain(40)
    f = np.geomspace(1.0, 200.0, 80)
    exact = frf(model, f, {"d0": 1.0})
    with _quiet():
        everything = frf(model, f, {"d0": 1.0}, mode_cutoff=1e3)
    assert _rel(everything.angles, exact.angles) < 1e-10
    with pytest.warns(ModelWarning, match="may change the response by up to"):
        poor = frf(model, np.geomspace(1.0, 40.0, 50), {"d0": 1.0}, mode_cutoff=1.5, tolerance=1e-6)
    assert poor.truncation_error > 1e-6
    with pytest.raises(ModelError, match="mode_cutoff"):
        frf(model, f, {"d0": 1.0}, mode_cutoff=1.0)


def test_a_large_model_sums_its_low_modes_and_solves_rayleigh_damping_banded():
    n = 20_000
    J, k = _values(n)
    model = Drivetrain.chain(J, k)
    f = np.geomspace(0.05, 2.0, 200)
    with _quiet():
        modal_damped = frf(model, f, {"d0": 1.0}, select=("d0", "d19999", "s0"))
    assert (
        modal_damped.method.startswith("modal superposition over the")
        and "of the other" in modal_damped.method
    )
    assert modal_damped.angles.shape == (200, 2) and modal_damped.element_loads.shape == (200, 1)
    kept = modal_damped.natural_frequencies_hz
    assert 0 < kept.size < 200 and kept.max() <= 4 * 2.0
    rayleigh = frf(model, f, {"d0": 1.0}, damping=RayleighDamping(0.05, 1e-6), select=("d0", "s0"))
    assert "banded, 20000 coordinates" in rayleigh.method and rayleigh.natural_frequencies_hz.size == 0
    # modal damping with every mode in the band of a model too large for them all: said, not attempted
    with pytest.raises(ModelError, match="RayleighDamping"):
        frf(model, np.geomspace(1.0, 1e4, 10), {"d0": 1.0}, select=("d0",))


def test_own_dampers_that_are_not_proportional_take_the_direct_solve_on_a_large_model():
    model = _chain(1200, damping=lambda i, k: 30.0 if i == 600 else 0.0)
    f = np.geomspace(0.5, 5.0, 20)
    r = frf(model, f, {"d0": 1.0}, damping=RayleighDamping(0.5, 0.0), select=("d0",))
    assert r.method.startswith("direct solve at each frequency (the model's own dampers couple the modes")
    with pytest.raises(ModelError, match="not proportional"):
        frf(model, f, {"d0": 1.0}, method="modal", select=("d0",))
    proportional = _chain(1200, damping=lambda i, k: 4e-6 * k)  # C = β K: still the modes
    with _quiet():
        p = frf(proportional, f, {"d0": 1.0}, select=("d0",))
    assert p.method.startswith("modal superposition over the")


# -- only the outputs asked for ---------------------------------------------------------------------


def test_select_keeps_exactly_the_columns_asked_for():
    model = _geared(10)
    f = np.geomspace(1.0, 500.0, 90)
    whole = frf(model, f, {"d0": 1.0})
    part = frf(model, f, {"d0": 1.0}, select=("d12", "flexible", "s3"), outputs=("d25",))
    assert part.disk_names == ("d12", "d25") and part.element_names == ("flexible", "s3")
    for j, name in enumerate(part.disk_names):
        np.testing.assert_allclose(
            part.angles[:, j], whole.angles[:, whole.disk_names.index(name)], rtol=1e-12
        )
    for j, name in enumerate(part.element_names):
        np.testing.assert_allclose(
            part.element_loads[:, j], whole.element_loads[:, whole.element_names.index(name)], rtol=1e-12
        )
    assert set(part.peaks) == {"d25", "flexible", "s3"}
    with pytest.raises(ModelError, match="neither a disk nor an element"):
        frf(model, f, {"d0": 1.0}, select=("nowhere",))


def test_memory_grows_with_the_outputs_not_with_the_model_per_frequency():
    model = Drivetrain.chain(*_values(3000))
    model.assembly
    peaks = []
    for n_f in (50, 400):
        tracemalloc.start()
        frf(
            model,
            np.geomspace(1.0, 1e3, n_f),
            {"d0": 1.0},
            damping=RayleighDamping(1.0, 1e-5),
            select=("d0",),
        )
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    # one complex vector of the whole model per frequency would be 48 kB
    assert (peaks[1] - peaks[0]) / 350 < 3000 * 16 / 8


# -- a chain built from arrays ----------------------------------------------------------------------


def test_a_chain_from_arrays_is_the_model_the_element_lists_give():
    J, k = _values(12)
    c = np.where(np.arange(11) % 3 == 0, 0.0, 2.0)
    built = Drivetrain.chain(J, k, damping=c, name="c12")
    listed = Drivetrain(
        [Disk(f"d{i}", J[i]) for i in range(12)],
        [Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), k[i], damping=c[i]) for i in range(11)],
        name="c12",
    )
    assert built == listed
    for which in ("mass", "stiffness", "damping"):
        for a, b in zip(built.block_groups(which), listed.block_groups(which), strict=True):
            np.testing.assert_array_equal(a.elements, b.elements)
            np.testing.assert_array_equal(a.dofs, b.dofs)
            np.testing.assert_array_equal(a.blocks, b.blocks)
    for X in ("M", "K", "C"):
        np.testing.assert_array_equal(
            getattr(built.assembly, X).toarray(), getattr(listed.assembly, X).toarray()
        )
    np.testing.assert_array_equal(modal(built).omega, modal(listed).omega)
    f = np.geomspace(1.0, 1e3, 40)
    a, b = frf(built, f, {"d0": 1.0}), frf(listed, f, {"d0": 1.0})
    assert a.element_names == b.element_names and a.method == b.method
    np.testing.assert_allclose(a.element_loads, b.element_loads, rtol=1e-13)
    assert built.free_branches()[0].tolist() == [1.0] * 12


def test_a_chain_converts_quantity_arrays_once_and_names_a_bad_entry():
    from mechdyn.units import registry

    Q = registry().Quantity
    J, k = _values(5)
    a = Drivetrain.chain(Q(J * 1e4, "kg*cm^2"), Q(k / 1e3, "kN*m/rad"))
    b = Drivetrain.chain(J, k)
    np.testing.assert_allclose([d.inertia for d in a.disks], J, rtol=1e-14)
    np.testing.assert_allclose(
        [e.stiffness for e in a.elements], [e.stiffness for e in b.elements], rtol=1e-14
    )
    c = Drivetrain.chain([f"{x} kg*m^2" for x in J], k)
    assert [d.inertia for d in c.disks] == pytest.approx(J.tolist(), rel=1e-15)
    bad = J.copy()
    bad[3] = -1.0
    with pytest.raises(ModelError, match=r"inertias\[3\]"):
        Drivetrain.chain(bad, k)
    with pytest.raises(ModelError, match="4 values"):
        Drivetrain.chain(J, k[:3])
    with pytest.raises(ModelError, match="used twice"):
        Drivetrain.chain(J, k, disk_names=["a", "b", "c", "d", "s0"])


# -- a new variant of a built model -----------------------------------------------------------------


def _turret_like():
    return Drivetrain(
        [Disk("m", 1e-3), Disk("p", 2e-4), Disk("g", 4e-3), Disk("t", 0.05), Disk("u", 0.02)],
        [
            Shaft("s1", ("m", "p"), 5e3, damping=0.3),
            GearMesh("mesh", ("p", "g"), base_radii=(0.02, 0.06), stiffness=2e8, damping=50.0),
            Shaft("s2", ("g", "t"), 2e4, inertia=1e-3, elements=3),
            GearMesh("rigid", ("t", "u"), teeth=(20, 40)),
            GroundSpring("k", "u", 1e3),
            GroundDamper("c", "m", 0.01),
        ],
        provenance={
            "s2": "from geometry",
            "s2 (inertia)": "from density",
            "m": "catalogue",
            "s1": "measured",
        },
    )


def test_a_variant_is_the_model_rebuilt_with_the_new_values():
    base = _turret_like()
    changes = {
        "stiffness": {"mesh": 3e8, "s2": 3.5e4, "k": 2e3},
        "damping": {"s1": 0.5, "c": 0.02, "mesh": 80.0},
        "inertia": {"t": 0.06, "s2": 2e-3, "m": "2e-3 kg*m^2"},
    }
    variant = base.with_values(**changes)
    rebuilt = dataclasses.replace(base, disks=variant.disks, elements=variant.elements)
    assert "_values" in variant.__dict__  # made on the base's structure
    assert variant == rebuilt and variant.disks[0].inertia == 2e-3
    for X in ("M", "K", "C"):
        np.testing.assert_allclose(
            getattr(variant.assembly, X).toarray(), getattr(rebuilt.assembly, X).toarray(), rtol=1e-14, atol=0
        )
    np.testing.assert_allclose(modal(variant).omega, modal(rebuilt).omega, rtol=1e-13)
    f = np.geomspace(1.0, 2e3, 60)
    a, b = frf(variant, f, {"m": 1.0}), frf(rebuilt, f, {"m": 1.0})
    assert a.method == b.method
    assert _rel(a.angles, b.angles) < 1e-12 and _rel(a.element_loads, b.element_loads) < 1e-12
    # the variant of a variant shares the structure too; provenance of changed values is dropped
    again = variant.with_values(stiffness={"s1": 6e3})
    assert again.elements[0].stiffness == 6e3 and again.elements[1].stiffness == 3e8
    assert set(variant.provenance) == {"s1"} and set(again.provenance) == set()


def test_a_value_that_appears_or_vanishes_rebuilds_the_model_and_bad_values_are_refused():
    base = _turret_like()
    undamped = base.with_values(damping={"s1": 0.0})
    assert "_values" not in undamped.__dict__ and undamped.elements[0].damping == 0.0
    assert modal(undamped).omega.size == modal(base).omega.size
    with pytest.raises(ModelError, match="must be positive"):
        base.with_values(stiffness={"s1": -5.0})
    with pytest.raises(ModelError, match="not finite"):
        base.with_values(inertia={"g": float("nan")})
    with pytest.raises(ModelError, match="beyond any machine"):
        base.with_values(stiffness={"k": 1e30})
    with pytest.raises(ModelError, match="has no value 'stiffness'"):
        base.with_values(stiffness={"m": 1.0})
    with pytest.raises(ModelError, match="not a disk or element"):
        base.with_values(inertia={"nowhere": 1.0})
    with pytest.raises(ModelError, match="needs base_radii"):
        Drivetrain(base.disks, [GearMesh("r", ("m", "p"), teeth=(10, 20))]).with_values(stiffness={"r": 1e8})


# -- the finite-value check, once where the model enters --------------------------------------------


def test_modal_of_a_checked_model_does_not_check_its_matrices_again(monkeypatch):
    model = _chain(10)
    model.assembly

    def refuse(*args, **kwargs):
        raise AssertionError("the matrices were checked again")

    monkeypatch.setattr("mechdyn.vibration.harmonic.finite_matrices", refuse)
    assert modal(model).omega.size == 9
    with pytest.raises(ModelError, match="not finite"):
        Disk("bad", float("inf"))  # the check where the model enters
    with pytest.raises(ModelError, match="not finite"):
        Drivetrain.chain([1.0, float("nan")], [1e3])


def test_the_eigen_solver_still_refuses_a_bad_matrix_handed_to_it():
    from mechdyn.vibration import solve_eigen

    K = np.array([[1.0, -1.0], [-1.0, np.nan]])
    with pytest.raises(ModelError, match="not finite"):
        solve_eigen(K, np.ones(2))
