"""The forced response by modal superposition and by the direct solve: the same answer where both
apply, the direct solve where only it is exact, and the method said in the result."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, GroundDamper, GroundSpring, Shaft, frf, modal
from mechdyn.drivetrain.response import ModalDamping, RayleighDamping
from mechdyn.errors import ModelError
from mechdyn.registry import get

DRIVETRAINS = sorted(p.name for p in EXAMPLES.glob("turret_*.toml"))


def _agree(a, b, rtol=1e-9):
    """Every column of complex amplitudes the same to ``rtol`` of its largest magnitude."""
    scale = np.maximum(np.abs(b).max(axis=0, keepdims=True), 1e-300)
    assert np.all(np.abs(a - b) <= rtol * scale), float((np.abs(a - b) / scale).max())


@pytest.mark.filterwarnings("ignore::mechdyn.errors.ModelWarning")  # turret B's ratio, on purpose
@pytest.mark.parametrize("name", DRIVETRAINS)
def test_every_example_frf_is_the_same_by_modes_and_by_direct_solve(name):
    loaded = mechdyn.load(EXAMPLES / name)
    result = get("frf").run(loaded, excite=[loaded.model.disk_names[0]], points=300)
    own_dampers = any(b.damping is not None for _, b in loaded.model.element_blocks)
    if own_dampers:  # turret C's start-up model damps its meshes and shafts: the modes do not apply
        assert result.method == "direct solve at each frequency (the model's own dampers couple the modes)"
    else:
        assert result.method.startswith("modal superposition over all")
    direct = frf(
        loaded.model,
        result.frequencies_hz,
        result.excitation,
        damping=result.damping,
        method="direct",
    )
    assert direct.method == "direct solve at each frequency (as asked)"
    _agree(result.angles, direct.angles)
    _agree(result.element_loads, direct.element_loads)
    assert result.summary()["method"] == result.method


def _chain(n=6, *, damped=None, ground=False):
    rng = np.random.default_rng(3)
    J, k = rng.uniform(0.5, 2.0, n) * 1e-2, rng.uniform(0.5, 2.0, n - 1) * 1e5
    disks = [Disk(f"d{i}", J[i]) for i in range(n)]
    shafts = [
        Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), k[i], damping=0.0 if damped is None else damped(i, k[i]))
        for i in range(n - 1)
    ]
    extra = [GroundSpring("g", "d0", 2e4)] if ground else []
    return Drivetrain(disks, [*shafts, *extra])


@pytest.mark.parametrize("ground", [False, True], ids=["free", "grounded"])
@pytest.mark.parametrize(
    "damping", [ModalDamping(0.03), ModalDamping((0.01, 0.02, 0.03, 0.04, 0.05)), RayleighDamping(2.0, 3e-6)]
)
def test_modal_and_proportional_damping_sum_the_modes_exactly(ground, damping):
    dt = _chain(ground=ground)
    f = np.geomspace(0.5, 5e3, 400)
    if ground and isinstance(damping, ModalDamping) and np.size(damping.ratio) == 5:
        damping = ModalDamping((0.01, 0.02, 0.03, 0.04, 0.05, 0.06))  # one more flexible mode
    fast = frf(dt, f, {"d0": 1.0, "d4": 0.3j}, damping=damping)
    slow = frf(dt, f, {"d0": 1.0, "d4": 0.3j}, damping=damping, method="direct")
    assert fast.method == f"modal superposition over all {len(dt.disks)} modes"
    _agree(fast.angles, slow.angles)
    _agree(fast.element_loads, slow.element_loads)


def test_own_dampers_proportional_to_the_shafts_keep_the_modes_and_others_need_the_direct_solve():
    f = np.geomspace(1.0, 5e3, 300)
    beta = 4e-6
    proportional = _chain(damped=lambda i, k: beta * k)  # C = β K: the modes stay uncoupled
    fast = frf(proportional, f, {"d0": 1.0})
    assert fast.method.startswith("modal superposition")
    _agree(fast.angles, frf(proportional, f, {"d0": 1.0}, method="direct").angles)
    # the same as Rayleigh damping β on the undamped chain, with the modal ratios on top
    bare = _chain()
    ray = frf(bare, f, {"d0": 1.0}, damping=RayleighDamping(0.0, beta))
    mixed = frf(proportional, f, {"d0": 1.0}, damping=ModalDamping(0.0))
    _agree(mixed.angles, ray.angles)

    coupled = _chain(damped=lambda i, k: 30.0 if i == 2 else 0.0)  # one damper in the middle
    auto = frf(coupled, f, {"d0": 1.0})
    assert auto.method == "direct solve at each frequency (the model's own dampers couple the modes)"
    assert auto.summary()["method"] == auto.method
    with pytest.raises(ModelError, match=r"own dampers couple the modes.*method='direct'"):
        frf(coupled, f, {"d0": 1.0}, method="modal")
    grounded = Drivetrain(bare.disks, [*bare.elements, GroundDamper("drag", "d5", 5.0)])
    assert frf(grounded, f, {"d0": 1.0}).method.startswith("direct solve")


def test_the_sum_matches_the_closed_form_of_one_disk_on_a_spring():
    # θ = T / (k − J ω² + i ω c) with c = 2 ζ √(k J) (Rao, Mechanical Vibrations, §3.4)
    J, k, zeta = 0.2, 8e4, 0.05
    dt = Drivetrain([Disk("a", J)], [GroundSpring("g", "a", k)])
    f = np.linspace(10.0, 200.0, 77)
    w = 2 * np.pi * f
    r = frf(dt, f, {"a": 3.0}, damping=ModalDamping(zeta))
    assert r.method == "modal superposition over all 1 modes"
    want = 3.0 / (k - J * w**2 + 1j * w * 2 * zeta * np.sqrt(k * J))
    np.testing.assert_allclose(r.angles[:, 0], want, rtol=1e-12)
    np.testing.assert_allclose(r.element_loads[:, 0], k * want, rtol=1e-12)


def test_a_free_pair_with_rigid_gears_reduced_out_sums_its_rigid_body_mode():
    # two disks geared rigidly to a third: the reduced coordinates are fewer than the disks, one of
    # them a free rigid-body motion; the sum needs that mode (−1/ω² J_eff) to match the direct solve
    dt = Drivetrain(
        [Disk("m", 1e-3), Disk("p", 2e-4), Disk("g", 4e-3), Disk("t", 0.05)],
        [
            Shaft("s1", ("m", "p"), 5e3),
            GearMesh("mesh", ("p", "g"), base_radii=(0.02, 0.06)),  # rigid
            Shaft("s2", ("g", "t"), 2e4),
        ],
    )
    f = np.geomspace(0.2, 2e3, 300)
    fast = frf(dt, f, {"m": 1.0})
    assert fast.method == "modal superposition over all 3 modes"
    _agree(fast.angles, frf(dt, f, {"m": 1.0}, method="direct").angles)
    # far above every mode the free train follows the low-frequency asymptote of its rigid body
    fast_low = frf(dt, [1e-3], {"m": 1.0})
    J_eff = 1e-3 + 2e-4 + (4e-3 + 0.05) * (0.02 / 0.06) ** 2
    assert fast_low.angles[0, 0] == pytest.approx(-1.0 / ((2 * np.pi * 1e-3) ** 2 * J_eff), rel=1e-4)


def test_an_unknown_method_and_an_undamped_resonance_are_refused():
    dt = Drivetrain([Disk("a", 0.2)], [GroundSpring("g", "a", 8e4)])
    with pytest.raises(ModelError, match="method 'fast'"):
        frf(dt, [10.0], {"a": 1.0}, method="fast")  # type: ignore[arg-type]
    f_n = np.sqrt(8e4 / 0.2) / (2 * np.pi)
    with pytest.raises(ModelError, match="not finite"):
        frf(dt, [f_n], {"a": 1.0}, damping=ModalDamping(0.0))


# -- a study's block of drivetrain variants, assembled and solved as a batch -------------------------


def _rows(params, n, seed=0):
    rng = np.random.default_rng(seed)
    return np.array([[rng.uniform(p.low, p.high) for p in params] for _ in range(n)])


@pytest.mark.filterwarnings("ignore::mechdyn.errors.ModelWarning")
@pytest.mark.parametrize(
    ("name", "paths", "options"),
    [
        ("turret_milling.toml", ("disks.*.inertia", "shafts.*.stiffness", "meshes.*.stiffness"), {}),
        ("turret_milling.toml", ("disks.3.inertia", "shafts.shaft 2.stiffness"), {"rigid_gears": True}),
        ("turret_indexing.toml", ("disks.*.inertia", "meshes.mesh 1.stiffness"), {"modes": 3}),
    ],
)
def test_the_modal_batch_equals_the_modal_analysis_variant_by_variant(name, paths, options):
    from mechdyn.io.modelfile import read
    from mechdyn.studies import Evaluator, ModelTree, Parameter

    source = read(EXAMPLES / name)
    tree = ModelTree(source)
    params = [q for p in paths for q in Parameter.from_spec(tree, p, range="±40 %")]
    n_out = options.get("modes", 3)
    outputs = [f"frequencies_hz.{m}" for m in range(1, n_out + 1)] + [
        "modes.2.frequency_hz",
        "rigid_body_modes",
    ]
    X = _rows(params, 6)
    fast_eval = Evaluator(source, "modal", params, outputs, options)
    fast = fast_eval(X)
    assert fast_eval.batch  # the batch took the block
    slow = Evaluator(source, "modal", params, outputs, options, batch=False)(X)
    for a, b in zip(fast, slow, strict=True):
        assert a.status == b.status == "ok"
        for k in outputs:
            assert a.outputs[k] == pytest.approx(b.outputs[k], rel=1e-11), k


def test_the_modal_batch_hands_back_what_it_does_not_compute_and_solves_doubtful_variants_alone(tmp_path):
    from mechdyn.drivetrain.batch import modal_batch
    from mechdyn.registry import NotBatchable

    loaded = mechdyn.load(EXAMPLES / "turret_milling.toml")
    col = {((), ("disks", 0, "inertia")): np.array([1e-3, 2e-3])}
    with pytest.raises(NotBatchable, match="natural frequencies only"):
        modal_batch(loaded, col, ["modes.1.dominant_element"])
    with pytest.raises(NotBatchable, match="does not vary"):
        modal_batch(loaded, {((), ("disks", 0, "thickness")): np.array([1.0])}, ["frequencies_hz.1"])
    with pytest.raises(NotBatchable, match="not positive"):
        modal_batch(loaded, {((), ("disks", 0, "inertia")): np.array([-1.0])}, ["frequencies_hz.1"])
    with pytest.raises(NotBatchable, match="rigid-gear"):
        modal_batch(loaded, col, ["frequencies_hz.1"], compare_rigid=True)
    # a disk 10¹² times lighter than the rest: the batched solve cannot vouch for the lowest mode,
    # and the variant is solved by the single path's accurate solvers (the same answer as modal())
    tiny = np.array([loaded.model.disks[0].inertia, 1e-15])
    got, errors = modal_batch(
        loaded, {((), ("disks", 0, "inertia")): tiny}, ["frequencies_hz.1", "frequencies_hz.6"]
    )
    assert errors == [None, None]
    light = dataclasses.replace(
        loaded.model,
        disks=(dataclasses.replace(loaded.model.disks[0], inertia=1e-15), *loaded.model.disks[1:]),
    )
    want = modal(light).frequencies_hz
    assert got["frequencies_hz.1"][1] == pytest.approx(want[0], rel=1e-9)
    assert got["frequencies_hz.6"][1] == pytest.approx(want[5], rel=1e-9)


def test_the_frf_plots_draw_disk_angles_shaft_torques_and_mesh_forces_with_their_phase(tmp_path):
    from mechdyn.plotting import save_figure

    result = get("frf").run(mechdyn.load(EXAMPLES / "turret_milling.toml"), points=200)
    plots = result.plots()
    assert set(plots) == {"frf.png", "frf_torques.png", "frf_mesh_forces.png"}
    ax = plots["frf_mesh_forces.png"]()
    magnitude, phase = ax.figure.axes
    assert magnitude is ax and phase.get_ylabel() == "phase (deg)"
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["mesh 1", "mesh 2"]
    j = result.element_names.index("mesh 1")
    np.testing.assert_allclose(
        phase.lines[0].get_ydata(), np.degrees(np.unwrap(np.angle(result.element_loads[:, j])))
    )
    np.testing.assert_allclose(ax.lines[0].get_ydata(), np.abs(result.element_loads[:, j]))  # N: under 1 kN
    torques = plots["frf_torques.png"]()
    assert "shaft torque amplitude (N·m)" == torques.get_ylabel()
    # the log axes' tick labels (10⁻¹, 10⁰) stay mathtext when names are shown as written
    save_figure(ax, tmp_path / "forces.png")
    assert all(t.get_parse_math() for t in magnitude.yaxis.get_ticklabels())
    assert not ax.title.get_parse_math()
