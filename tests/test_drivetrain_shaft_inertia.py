"""Shafts with their own distributed inertia: consistent and lumped mass, divided into elements.

Closed forms of the continuous uniform shaft (torsional wave speed c = √(G/ρ), length L, β = ω/c):

* free–free: f_k = k c / (2L);
* fixed–free: f_k = (2k − 1) c / (4L);
* held at x = 0 by a spring k_g, a disk J_d at x = L: θ = A cos βx + B sin βx with G J_p θ'(0) = k_g θ(0)
  and ω² J_d θ(L) = G J_p θ'(L) give, with u = βL, g = k_g/K, r = J_d/J_s (K = G J_p/L,
  J_s = ρ J_p L), h(u) = u r (u cos u / g + sin u) + u sin u / g − cos u = 0. For g → ∞ this is the
  classic u tan u = J_s/J_d (Rao, *Mechanical Vibrations*, 5th ed., 2011, §8.4, the shaft with a disk
  at its end), for r → 0 the spring-held free shaft u tan u = g.

Linear elements of length h = L/N approximate the wave number β with a phase error: ω_h/ω = 1 + (βh)²/24
(consistent mass) and 1 − (βh)²/24 (lumped) to leading order (the dispersion of the linear rod element,
e.g. Hughes, *The Finite Element Method*, 2000, ch. 9): an error ∝ 1/N², from above and from below.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import brentq

import mechdyn
from conftest import EXAMPLES, load_quiet
from mechdyn.drivetrain import (
    Disk,
    Drivetrain,
    GearMesh,
    GroundSpring,
    ModalDamping,
    RayleighDamping,
    Shaft,
    assemble,
    frf,
    modal,
    model_frame,
)
from mechdyn.errors import ModelError, ModelFileError
from mechdyn.vibration import solve_eigen

G, RHO, LENGTH, D = 80e9, 7850.0, 0.5, 0.03
C = math.sqrt(G / RHO)
TINY = 1e-9  # end disks of a free shaft: this fraction of the shaft's inertia (a drivetrain needs disks)
CLAMP = 1e8  # a grounded spring this many times the shaft's stiffness holds an end


def _shaft(n: int, mass_model: str = "consistent", disks: tuple[str, str] = ("a", "b")) -> Shaft:
    return Shaft.from_geometry(
        "s", disks, length=LENGTH, diameter=D, shear_modulus=G, density=RHO, mass_model=mass_model, elements=n
    )


def _free(n: int, mass_model: str) -> Drivetrain:
    s = _shaft(n, mass_model)
    return Drivetrain([Disk("a", TINY * s.inertia), Disk("b", TINY * s.inertia)], [s])


def _held(n: int, mass_model: str, disk_ratio: float = TINY, clamp: float = CLAMP) -> Drivetrain:
    """The shaft held at a by a grounded spring clamp·K, a disk of disk_ratio·J_s at b."""
    s = _shaft(n, mass_model)
    disks = [Disk("a", TINY * s.inertia), Disk("b", disk_ratio * s.inertia)]
    return Drivetrain(disks, [s, GroundSpring("clamp", "a", clamp * s.stiffness)])


def _roots(r: float, g: float, count: int) -> np.ndarray:
    """The lowest roots u = βL of h(u) = u r (u cos u / g + sin u) + u sin u / g − cos u."""

    def h(u: float) -> float:
        return u * r * (u * math.cos(u) / g + math.sin(u)) + u * math.sin(u) / g - math.cos(u)

    grid = np.linspace(1e-9, (count + 1) * math.pi, 20_000)
    values = np.array([h(u) for u in grid])
    at = np.flatnonzero(np.sign(values[:-1]) != np.sign(values[1:]))[:count]
    return np.array([brentq(h, grid[i], grid[i + 1], xtol=1e-15, rtol=1e-15) for i in at])


def _relative_errors(model: Drivetrain, exact_hz: np.ndarray) -> np.ndarray:
    return modal(model, n_modes=exact_hz.size).frequencies_hz / exact_hz - 1.0


# -- (a) convergence to the continuous shaft ------------------------------------------------------------


@pytest.mark.parametrize("mass_model, sign", [("consistent", 1.0), ("lumped", -1.0)])
def test_free_free_shaft_converges_as_one_over_n_squared(mass_model, sign):
    exact = np.arange(1, 4) * C / (2 * LENGTH)
    errors = {n: _relative_errors(_free(n, mass_model), exact) for n in (8, 16, 32, 64)}
    for n, e in errors.items():
        print(f"{mass_model:10s} N = {n:3d}: errors {e}")
        assert np.all(sign * e > 0)  # consistent mass over-estimates, lumped under-estimates
        beta_h = np.arange(1, 4) * math.pi / n
        assert e == pytest.approx(sign * beta_h**2 / 24, rel=0.04)  # the leading phase error
    for n in (8, 16, 32):
        assert errors[n][0] / errors[2 * n][0] == pytest.approx(4.0, rel=0.01)  # ∝ 1/N²
    assert abs(errors[64][2]) < 1.1e-3


@pytest.mark.parametrize("mass_model, sign", [("consistent", 1.0), ("lumped", -1.0)])
def test_fixed_free_shaft_converges_to_the_quarter_waves(mass_model, sign):
    exact = (2 * np.arange(1, 4) - 1) * C / (4 * LENGTH)
    for n in (16, 64):
        e = _relative_errors(_held(n, mass_model), exact)
        beta_h = (2 * np.arange(1, 4) - 1) * math.pi / (2 * n)
        assert np.all(sign * e > 0)
        assert e == pytest.approx(sign * beta_h**2 / 24, rel=0.04)


def test_a_softly_held_shaft_matches_its_exact_frequency_equation():
    """u tan u = k_g/K (a free end held by a spring of 1000 K), not the clamped limit."""
    g = 1e3
    s = _shaft(1)
    exact = _roots(TINY, g, 3) * C / (2 * math.pi * LENGTH)
    assert not np.allclose(exact, (2 * np.arange(1, 4) - 1) * C / (4 * LENGTH), rtol=1e-4)
    e = _relative_errors(_held(128, "consistent", clamp=g), exact)
    assert np.all(e > 0) and np.all(e < ((2 * np.arange(1, 4) - 1) * math.pi / 256) ** 2 / 24 * 1.05)
    assert s.inertia == pytest.approx(RHO * math.pi * D**4 / 32 * LENGTH, rel=1e-15)


# -- (b) the shaft with a disk at its end ---------------------------------------------------------------


@pytest.mark.parametrize("disk_ratio", [0.5, 1.0, 2.0])
def test_shaft_with_a_disk_at_its_end_matches_u_tan_u(disk_ratio):
    exact = _roots(disk_ratio, CLAMP, 2) * C / (2 * math.pi * LENGTH)
    u1 = 2 * math.pi * exact[0] * LENGTH / C
    assert u1 * math.tan(u1) == pytest.approx(1 / disk_ratio, rel=1e-6)  # the clamped limit, g = 1e8
    consistent = _relative_errors(_held(64, "consistent", disk_ratio), exact)
    lumped = _relative_errors(_held(64, "lumped", disk_ratio), exact)
    assert np.all(consistent > 0) and np.all(lumped < 0)
    assert np.all(np.abs(consistent) < 3e-4) and np.all(np.abs(lumped) < 3e-4)


def test_one_consistent_element_is_rayleighs_third_of_the_shaft_on_the_disk():
    """Clamped shaft, disk at the end, one element: ω² = K / (J_d + J_s/3) exactly (Rayleigh's
    third of the shaft's inertia added to the disk, e.g. Rao, *Mechanical Vibrations*, §8.4)."""
    model = _held(1, "consistent", disk_ratio=1.0)
    s = model.elements[0]
    assert isinstance(s, Shaft)
    j_d = model.disks[1].inertia
    rayleigh = math.sqrt(s.stiffness / (j_d + s.inertia / 3)) / (2 * math.pi)
    assert modal(model, n_modes=1).frequencies_hz[0] == pytest.approx(rayleigh, rel=1e-7)  # clamp 1e8 K
    exact = _roots(1.0, CLAMP, 1)[0] * C / (2 * math.pi * LENGTH)  # u tan u = 1: u = 0.8603
    assert rayleigh / exact - 1 == pytest.approx(0.0066, abs=2e-4)  # 0.75 K/J_s against u² = 0.7402


# -- (c) existing models unchanged ----------------------------------------------------------------------

# natural frequencies (Hz) of the published turret examples as computed before shafts had inertia
# (float.hex, from the code at the start of this change); the rtol below only absorbs LAPACK builds
BEFORE = {
    ("turret_indexing", False): ["0x1.8c2af63e031aap+9", "0x1.61a9b27e9cbcfp+12", "0x1.f4b3d11b24e94p+13",
                                 "0x1.7906c822a7276p+15", "0x1.9916026005e36p+15"],
    ("turret_indexing", True): ["0x1.acd8ac26b6833p+9", "0x1.652fc8f6cec19p+12", "0x1.f94efb6c8a66bp+13"],
    ("turret_milling", False): ["0x1.135199af5c0bbp+10", "0x1.52bfd5090b96dp+11", "0x1.7913e721e155dp+12",
                                "0x1.83e88898db6b0p+13", "0x1.52ffd7cdf9c7fp+15", "0x1.59adb98dff2a8p+15"],
    ("turret_milling", True): ["0x1.13d652356dbaep+10", "0x1.5377d910299a7p+11", "0x1.795ed36591737p+12",
                               "0x1.868997761c085p+13"],
}  # fmt: skip


@pytest.mark.parametrize("name, rigid", list(BEFORE))
def test_models_without_shaft_inertia_are_unchanged(name, rigid):
    model = load_quiet(EXAMPLES / f"{name}.toml")
    result = modal(model, rigid_gears=rigid)
    before = np.array([float.fromhex(x) for x in BEFORE[(name, rigid)]])
    assert result.frequencies_hz == pytest.approx(before, rel=1e-12, abs=0)
    asm = result.assembly
    # the fast path, fed exactly what it was fed before: the disks' inertias, Tᵀ diag(J) T
    assert asm.diagonal_mass and model.dof_names == model.disk_names
    expected = (
        np.asarray(asm.T.multiply(asm.T).T @ model.inertias) if asm.T.shape[0] != asm.T.shape[1] else None
    )
    assert np.array_equal(asm.mass, model.inertias if expected is None else expected)
    assert np.array_equal(result.coordinate_mass(), model.inertias)
    lam, _, _ = solve_eigen(asm.K, asm.mass, n_rigid=asm.n_rigid_body, factor=lambda: None)
    assert np.array_equal(np.sqrt(np.clip(lam[asm.n_rigid_body :], 0, None)), result.omega)
    assert "inertia" not in " ".join(model_frame(model)["kind"])


def test_a_massless_shaft_has_the_blocks_it_always_had():
    s = Shaft("s", ("a", "b"), 1e4, 2.0)
    b = s.blocks()
    assert b.mass is None and b.internal == () and b.stiffness_rows is None
    assert np.array_equal(b.stiffness, 1e4 * np.array([[1.0, -1.0], [-1.0, 1.0]]))
    assert s == Shaft("s", ("a", "b"), 1e4, 2.0, inertia=0.0, mass_model="consistent", elements=1)


# -- (d) the mass matrix ---------------------------------------------------------------------------------


def _geared(mass_model: str = "consistent", rigid: bool = True) -> Drivetrain:
    """Motor –(shaft 1, 3 elements)– pinion ⟂ gear (ratio 3) –(shaft 2)– load."""
    return Drivetrain(
        [Disk("motor", 0.02), Disk("pinion", 1e-3), Disk("gear", 8e-3), Disk("load", 0.5)],
        [
            Shaft("shaft 1", ("motor", "pinion"), 2e4, inertia=4e-3, mass_model=mass_model, elements=3),
            GearMesh(
                "mesh", ("pinion", "gear"), teeth=(20, 60), base_radii=(0.019, 0.057),
                stiffness=None if rigid else 3e8,
            ),
            Shaft("shaft 2", ("gear", "load"), 6e4, inertia=0.03, mass_model=mass_model),
        ],
    )  # fmt: skip


@pytest.mark.parametrize("rigid", [True, False])
def test_mass_matrix_symmetric_positive_definite_and_rigid_body_modes_kept(rigid):
    model = _geared(rigid=rigid)
    asm = assemble(model)
    assert model.dof_names == ("motor", "pinion", "gear", "load", "shaft 1[1]", "shaft 1[2]")
    assert not asm.diagonal_mass and sp.issparse(asm.M)
    M = asm.M.toarray()
    assert np.array_equal(M, M.T)
    assert np.linalg.eigvalsh(M).min() > 0
    M_reduced = np.asarray((asm.T.T @ asm.M_full @ asm.T).toarray())
    assert M == pytest.approx(M_reduced, rel=1e-14, abs=1e-18)
    if rigid:
        assert np.count_nonzero(M - np.diag(np.diag(M))) > 0  # TᵀMT couples the geared coordinates
    with pytest.raises(ModelError, match="not diagonal"):
        _ = asm.mass
    result = modal(model)
    assert result.rigid_body_modes == asm.n_rigid_body == 1
    Q = result.reduced_shapes
    assert Q.T @ asm.M @ Q == pytest.approx(np.eye(Q.shape[1]), abs=1e-9)
    assert asm.K @ Q == pytest.approx(
        asm.M @ Q * result.omega**2, rel=1e-8, abs=1e-8 * np.abs(asm.K @ Q).max()
    )
    assert result.kinetic_energy.sum(axis=0) == pytest.approx(1.0)
    held = Drivetrain(model.disks, (*model.elements, GroundSpring("brake", "load", 1e5)))
    assert modal(held).rigid_body_modes == 0


def test_rigid_rotation_carries_the_disks_and_the_shafts_inertia():
    s1 = _shaft(5, "consistent", ("a", "b"))
    s2 = Shaft("t", ("b", "c"), 3e4, inertia="2e-3 kg*m^2", mass_model="lumped", elements=2)
    model = Drivetrain([Disk("a", 0.01), Disk("b", 0.02), Disk("c", 0.03)], [s1, s2])
    asm = assemble(model)
    r = asm.rigid_body_vectors[:, 0]
    assert np.all(r == 1.0)
    total = 0.01 + 0.02 + 0.03 + RHO * math.pi * D**4 / 32 * LENGTH + 2e-3
    assert r @ (asm.M_full @ r) == pytest.approx(total, rel=1e-14)
    assert model.total_inertia == pytest.approx(total, rel=1e-14)
    # through a rigid mesh of ratio n = 3 the driven side turns at 1/3 and counts 1/n²
    geared = _geared()
    q = assemble(geared).rigid_body_vectors[:, 0]
    assert q[geared.dof_index["load"]] == pytest.approx(-1 / 3, rel=1e-15)
    J = 0.02 + 1e-3 + 4e-3 + (8e-3 + 0.5 + 0.03) / 9
    assert q @ (assemble(geared).M_full @ q) == pytest.approx(J, rel=1e-14)


def test_lumped_shafts_keep_the_diagonal_fast_path():
    model = Drivetrain(
        [Disk("a", 0.01), Disk("b", 0.02)], [Shaft("s", ("a", "b"), 1e4, inertia=4e-3, mass_model="lumped")]
    )
    asm = assemble(model)
    assert asm.diagonal_mass
    assert np.array_equal(asm.mass, [0.01 + 2e-3, 0.02 + 2e-3])
    f = modal(model).frequencies_hz[0]
    assert f == pytest.approx(math.sqrt(1e4 * (1 / 0.012 + 1 / 0.022)) / (2 * math.pi), rel=1e-12)


# -- forced response and the other analyses with a consistent M -----------------------------------------


@pytest.mark.parametrize("damping", [ModalDamping(0.03), RayleighDamping(alpha=20.0, beta=2e-6)])
def test_frf_modal_sum_and_direct_solve_agree_with_consistent_mass(damping):
    model = _geared()
    f = np.geomspace(5.0, 3000.0, 60)
    modal_sum = frf(model, f, {"motor": 1.0}, damping=damping, method="modal")
    direct = frf(model, f, {"motor": 1.0}, damping=damping, method="direct")
    assert modal_sum.disk_names == model.dof_names
    scale = np.abs(direct.angles).max()
    assert modal_sum.angles == pytest.approx(direct.angles, abs=1e-9 * scale)
    assert modal_sum.element_loads == pytest.approx(
        direct.element_loads, abs=1e-9 * np.abs(direct.element_loads).max()
    )


def test_campbell_and_tables_show_the_shaft_inertia():
    model = _geared(rigid=False)
    camp = mechdyn.drivetrain.campbell(model, ("0 rpm", "3000 rpm"))
    assert {line.kind for line in camp.lines} == {"shaft", "mesh"}
    frame = model.to_frame()
    row = frame[frame["name"] == "shaft 1 (inertia)"].iloc[0]
    assert row["value"] == 4e-3 and row["kind"] == "shaft inertia, consistent, 3 elements"
    assert row["from"] == "given"


# -- (e) the model file ---------------------------------------------------------------------------------

FILE = """
[model]
type = "drivetrain"
name = "shafts with inertia"

[material]
shear_modulus = "80 GPa"

[[disks]]
name = "motor"
inertia = "0.02 kg*m^2"
[[disks]]
name = "load"
inertia = "0.05 kg*m^2"
[[disks]]
name = "tail"
inertia = "0.01 kg*m^2"

[[shafts]]
name = "long"
disks = ["motor", "load"]
length = "500 mm"
diameter = "30 mm"
density = "7850 kg/m^3"
elements = 6

[[shafts]]
name = "short"
disks = ["load", "tail"]
stiffness = "2e4 N*m/rad"
inertia = "1e-3 kg*m^2"
mass_model = "lumped"
"""


def test_model_file_round_trip(tmp_path):
    path = tmp_path / "shafts.toml"
    path.write_text(FILE)
    loaded = mechdyn.load(path)
    model = loaded.model
    long, short = model.elements
    assert isinstance(long, Shaft) and isinstance(short, Shaft)
    assert long.inertia == pytest.approx(RHO * math.pi * D**4 / 32 * LENGTH, rel=1e-15)
    assert (long.mass_model, long.elements, short.mass_model, short.inertia) == (
        "consistent",
        6,
        "lumped",
        1e-3,
    )
    frame = model.to_frame()
    assert frame.loc[frame["name"] == "long (inertia)", "from"].item().startswith("from geometry: ρ J_p l")
    out = tmp_path / "saved.toml"
    mechdyn.save(loaded, out)
    text = out.read_text()
    assert 'mass_model = "lumped"' in text and "elements = 6" in text
    again = mechdyn.load(out).model
    assert again == model
    assert modal(again).frequencies_hz.tolist() == modal(model).frequencies_hz.tolist()


# -- (f) bad input ----------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs, field, words",
    [
        ({"density": "-7850 kg/m^3"}, "density", "density"),
        ({"density": RHO, "elements": 0}, "elements", "whole number from 1"),
        ({"density": RHO, "elements": 2.5}, "elements", "whole number from 1"),
        ({"density": RHO, "elements": True}, "elements", "whole number from 1"),
        ({"elements": 4}, "elements", "no inertia"),
        ({"density": RHO, "mass_model": "distributed"}, "mass_model", "'consistent' or 'lumped'"),
    ],
)
def test_bad_shaft_input_is_named(kwargs, field, words):
    with pytest.raises(ModelError, match=words) as caught:
        Shaft.from_geometry("s", ("a", "b"), length=LENGTH, diameter=D, shear_modulus=G, **kwargs)
    assert caught.value.element == "s" and caught.value.field == field


def test_negative_given_inertia_is_named():
    with pytest.raises(ModelError) as caught:
        Shaft("s", ("a", "b"), 1e4, inertia=-1.0)
    assert caught.value.field == "inertia" and "-1" in str(caught.value)


@pytest.mark.parametrize(
    "replace_with, words",
    [
        ("elements = 6", "elements = 0"),
        ('density = "7850 kg/m^3"', 'density = "7850 kg/m^3"\ninertia = "1e-3 kg*m^2"'),
    ],
)
def test_bad_shaft_rows_in_a_model_file_are_named(tmp_path, replace_with, words):
    path = tmp_path / "bad.toml"
    path.write_text(FILE.replace(replace_with, words))
    with pytest.raises(ModelFileError) as caught:
        mechdyn.load(path)
    assert "[[shafts]] #1 (name = 'long')" in str(caught.value)


def test_density_needs_the_geometry_in_a_model_file(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(FILE.replace('inertia = "1e-3 kg*m^2"', 'density = "7850 kg/m^3"'))
    with pytest.raises(ModelFileError, match="density needs the shaft's geometry") as caught:
        mechdyn.load(path)
    assert "[[shafts]] #2 (name = 'short')" in str(caught.value)


def test_a_node_name_that_clashes_is_named():
    with pytest.raises(ModelError, match="node 's\\[1\\]'"):
        Drivetrain([Disk("a", 1.0), Disk("b", 1.0), Disk("s[1]", 1.0)], [_shaft(2, "consistent")])


def test_check_matrices_takes_a_consistent_mass_matrix_and_refuses_a_singular_one():
    from mechdyn.drivetrain import check_matrices
    from mechdyn.errors import ModelCheckError

    asm = assemble(_free(4, "consistent"))
    M, K = asm.M.toarray(), asm.K.toarray()
    check_matrices(M, K, expected_rigid_body_modes=1, rigid_body_vectors=asm.rigid_body_vectors)
    singular = M.copy()
    singular[:, 0] = singular[0, :] = 0.0
    with pytest.raises(ModelCheckError, match="M is not positive definite"):
        check_matrices(singular, K, expected_rigid_body_modes=1)


# -- design studies' batch path ---------------------------------------------------------------------------


def test_batch_takes_lumped_shafts_and_hands_consistent_ones_to_the_single_path(tmp_path):
    from mechdyn.drivetrain.batch import modal_batch
    from mechdyn.registry import NotBatchable

    lumped = tmp_path / "lumped.toml"
    lumped.write_text(FILE.replace("elements = 6", 'elements = 6\nmass_model = "lumped"'))
    loaded = mechdyn.load(lumped)
    inertias = np.array([0.01, 0.02, 0.04])
    columns = {((), ("disks", 0, "inertia")): inertias}
    out, errors = modal_batch(loaded, columns, ["frequencies_hz.1", "frequencies_hz.2"])
    assert errors == [None] * 3
    for v, j in enumerate(inertias):
        one = Drivetrain(
            (Disk("motor", j), *loaded.model.disks[1:]), loaded.model.elements, name=loaded.model.name
        )
        f = modal(one).frequencies_hz
        assert out["frequencies_hz.1"][v] == pytest.approx(f[0], rel=1e-10)
        assert out["frequencies_hz.2"][v] == pytest.approx(f[1], rel=1e-10)
    consistent = tmp_path / "consistent.toml"
    consistent.write_text(FILE)
    with pytest.raises(NotBatchable, match="not diagonal"):
        modal_batch(mechdyn.load(consistent), columns, ["frequencies_hz.1"])


def test_a_divided_shaft_is_drawn_between_its_disks():
    """The mode-shape plot puts a divided shaft's nodes between its two disks (in the model they come
    after every disk) and joins them in one line with the disks: the first free-free mode is one
    smooth half-wave, drawn left to right; the nodes are not named on the axis."""
    import matplotlib

    matplotlib.use("Agg")
    from mechdyn.drivetrain.plots import _dof_order, plot_mode_shapes

    model = Drivetrain(
        (Disk("motor", 0.01), Disk("a", 0.001), Disk("b", 0.001)),
        (Shaft("coupling", ("motor", "a"), 1e5), _shaft(4)),
    )
    result = modal(model)
    names = [result.disk_names[i] for i in _dof_order(result)]
    assert names == ["motor", "a", "s[1]", "s[2]", "s[3]", "b"]
    ax = plot_mode_shapes(result, modes=[1])
    lines = [line for line in ax.get_lines() if len(line.get_xdata()) > 1 and line.get_marker() == "o"]
    assert len(lines) == 1 and list(lines[0].get_xdata()) == [0, 1, 2, 3, 4, 5]
    labels = [t.get_text() for t in ax.figure.axes[-1].get_xticklabels()]
    assert labels == ["motor", "a", "", "", "", "b"]
    matplotlib.pyplot.close(ax.figure)
