"""Invariants of assembled drivetrains, as properties over random geared forests (hypothesis)."""

from __future__ import annotations

import warnings

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mechdyn
from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, GroundSpring, Shaft, assemble, modal
from mechdyn.errors import ModelWarning


@st.composite
def forests(draw):
    """A random forest of disks joined by shafts, rigid or flexible meshes, some grounded."""
    n = draw(st.integers(1, 10))
    J = draw(st.lists(st.floats(1e-3, 1.0), min_size=n, max_size=n))
    disks = [Disk(f"d{i}", J[i]) for i in range(n)]
    elements, edges = [], []
    for i in range(1, n):
        if not draw(st.booleans()) and i > 1 and draw(st.integers(0, 3)) == 0:
            continue  # leave this disk on a new branch
        j = draw(st.integers(0, i - 1))
        edges.append((j, i))
        kind = draw(st.sampled_from(["shaft", "rigid", "flexible"]))
        name = f"e{i}"
        if kind == "shaft":
            elements.append(Shaft(name, (f"d{j}", f"d{i}"), draw(st.floats(1e3, 1e6))))
        else:
            ra, rb = draw(st.floats(0.02, 0.2)), draw(st.floats(0.02, 0.2))
            mesh_kind = draw(st.sampled_from(["external", "internal"]))
            kc = draw(st.floats(1e8, 1e9)) if kind == "flexible" else None
            elements.append(
                GearMesh(name, (f"d{j}", f"d{i}"), kind=mesh_kind, base_radii=(ra, rb), stiffness=kc)
            )
    grounded = draw(st.lists(st.integers(0, n - 1), max_size=2, unique=True))
    for g in grounded:
        elements.append(GroundSpring(f"ground{g}", f"d{g}", draw(st.floats(1e3, 1e6))))
    return Drivetrain(disks, elements), edges, grounded


def _expected_free_branches(n, edges, grounded) -> int:
    # union–find over the edges, written here independently of the model's own graph code
    parent = list(range(n))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for a, b in edges:
        parent[find(a)] = find(b)
    roots = {find(i) for i in range(n)}
    return len(roots - {find(g) for g in grounded})


PROPS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@PROPS
@given(forests())
def test_assembled_matrices_are_symmetric_semidefinite_with_one_zero_mode_per_free_branch(case):
    dt, edges, grounded = case
    asm = assemble(dt)
    K = asm.K.toarray()
    np.testing.assert_array_equal(K, K.T)
    scale = 1.0 / np.sqrt(asm.mass)
    A = scale[:, None] * K * scale[None, :]
    lam = np.linalg.eigvalsh(A)
    big = max(np.abs(lam).max(), 1.0)
    assert lam.min() >= -1e-9 * big
    expected = _expected_free_branches(len(dt.disks), edges, grounded)
    assert int(np.sum(lam <= 1e-9 * big)) == expected
    assert asm.n_rigid_body == expected
    # the exact rigid-body motions carry no strain energy
    for r in asm.rigid_body_vectors.T:
        assert np.abs(asm.K_full @ r).max() <= 1e-9 * np.abs(asm.K_full).max()


@PROPS
@given(forests())
def test_modes_are_mass_orthonormal_and_diagonalise_k(case):
    dt, _, _ = case
    r = modal(dt)
    asm = r.assembly
    Q = r.reduced_shapes
    np.testing.assert_allclose(Q.T @ (asm.mass[:, None] * Q), np.eye(Q.shape[1]), atol=1e-8)
    KQ = Q.T @ (asm.K @ Q)
    np.testing.assert_allclose(
        KQ, np.diag(r.omega**2), atol=1e-7 * max(1.0, float(r.omega.max(initial=0.0)) ** 2)
    )
    # modal energies partition each mode completely
    _, share = r.strain_energy
    if share.size:
        np.testing.assert_allclose(share.sum(axis=0), 1.0, rtol=1e-9)
    np.testing.assert_allclose(r.kinetic_energy.sum(axis=0), 1.0, rtol=1e-9)


UNIT_SETS = {
    "SI": {"J": ("kg*m^2", 1.0), "k": ("N*m/rad", 1.0), "r": ("m", 1.0), "kc": ("N/m", 1.0)},
    "mm-g": {"J": ("g*mm^2", 1e9), "k": ("N*mm/rad", 1e3), "r": ("mm", 1e3), "kc": ("N/mm", 1e-3)},
    "imperial": {
        "J": ("lb*inch^2", 1 / 2.926396534292e-4),
        "k": ("lbf*ft/rad", 1 / 1.3558179483314004),
        "r": ("inch", 1 / 0.0254),
        "kc": ("lbf/inch", 1 / 175.12683524647636),
    },
}


def _toml(dt: Drivetrain, units: dict) -> str:
    """The model as a file, every quantity written in the given units."""

    def q(value, key):
        unit, factor = units[key]
        return f'"{value * factor!r} {unit}"'

    def table(header, /, **fields):
        body = "\n".join(f"{k} = {v}" for k, v in fields.items())
        return f"[[{header}]]\n{body}\n"

    def pair(a, b):
        return f'["{a}", "{b}"]'

    parts = ['[model]\ntype = "drivetrain"\nname = "unit test"\n']
    parts += [table("disks", name=f'"{d.name}"', inertia=q(d.inertia, "J")) for d in dt.disks]
    for e in dt.elements:
        if isinstance(e, Shaft):
            parts.append(
                table("shafts", name=f'"{e.name}"', disks=pair(*e.disks), stiffness=q(e.stiffness, "k"))
            )
        elif isinstance(e, GearMesh):
            fields = {"name": f'"{e.name}"', "disks": pair(*e.disks), "kind": f'"{e.kind}"'}
            fields["base_radii"] = f"[{q(e.base_radii[0], 'r')}, {q(e.base_radii[1], 'r')}]"
            if e.stiffness is not None:
                fields["stiffness"] = q(e.stiffness, "kc")
            parts.append(table("meshes", **fields))
        elif isinstance(e, GroundSpring):
            stiffness = q(e.stiffness, "k")
            parts.append(table("ground_springs", name=f'"{e.name}"', disk=f'"{e.disk}"', stiffness=stiffness))
    return "\n".join(parts)


@settings(
    max_examples=25,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(forests())
def test_frequencies_do_not_depend_on_the_units_in_the_file(tmp_path_factory, case):
    dt, _, _ = case
    reference = modal(dt).frequencies_hz
    folder = tmp_path_factory.mktemp("units")
    for label, units in UNIT_SETS.items():
        path = folder / f"{label}.toml"
        path.write_text(_toml(dt, units))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ModelWarning)
            loaded = mechdyn.load(path).model
        got = modal(loaded).frequencies_hz
        # round-off in the eigenvalue λ = ω² is about ε λ_max, so ω_i moves by ~ ε (ω_max/ω_i)² / 2
        rtol = 1e-13 * (reference.max() / reference) ** 2 + 1e-11 if reference.size else 0.0
        assert np.all(np.abs(got - reference) <= rtol * reference)
