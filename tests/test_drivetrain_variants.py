"""A new variant of a built drivetrain (:meth:`Drivetrain.with_values`): checked once where the values
enter, built on its base's structure, and analysed exactly as the same model built from element lists.

The references are models built afresh from ``Disk``/``Shaft``/``GearMesh`` objects with the new values
(every check and the whole assembly redone), so the fast path is compared with the path it replaces.
"""

from __future__ import annotations

import pickle

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
from mechdyn.errors import ModelError

# -- three models, each built from element lists for given values ------------------------------------


def _chain(values):
    """A 10-disk free chain: inertias J0..J9 (kg·m²), stiffnesses k0..k8 (N·m/rad)."""
    disks = [Disk(f"d{i}", values[("inertia", f"d{i}")]) for i in range(10)]
    shafts = [Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), values[("stiffness", f"s{i}")]) for i in range(9)]
    return Drivetrain(disks, shafts)


def _geared(values):
    """Motor, pinion, gear, table and a load behind a rigid mesh: a flexible mesh (N/m on base radii),
    a rigid one (reduced out, θ = T q), a shaft divided into three elements with its own inertia and a
    grounded spring."""
    v = values
    return Drivetrain(
        [Disk(n, v[("inertia", n)]) for n in ("m", "p", "g", "t", "u")],
        [
            Shaft("s1", ("m", "p"), v[("stiffness", "s1")]),
            GearMesh("mesh", ("p", "g"), base_radii=(0.02, 0.06), stiffness=v[("stiffness", "mesh")]),
            Shaft("s2", ("g", "t"), v[("stiffness", "s2")], inertia=v[("inertia", "s2")], elements=3),
            GearMesh("rigid", ("t", "u"), teeth=(20, 40)),
            GroundSpring("k", "u", v[("stiffness", "k")]),
        ],
    )


def _damped(values):
    """A 6-disk chain with damped shafts, a damped mesh and a damper to the ground."""
    v = values
    disks = [Disk(f"d{i}", v[("inertia", f"d{i}")]) for i in range(6)]
    shafts = [
        Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), v[("stiffness", f"s{i}")], damping=v[("damping", f"s{i}")])
        for i in (0, 1, 3, 4)
    ]
    mesh = GearMesh(
        "mesh",
        ("d2", "d3"),
        base_radii=(0.03, 0.05),
        stiffness=v[("stiffness", "mesh")],
        damping=v[("damping", "mesh")],
    )
    return Drivetrain(disks, [*shafts, mesh, GroundDamper("c", "d0", v[("damping", "c")])])


def _base_values(kind):
    rng = np.random.default_rng(3)
    if kind == "chain":
        out = {("inertia", f"d{i}"): float(rng.uniform(0.5, 2.0) * 1e-2) for i in range(10)}
        out.update({("stiffness", f"s{i}"): float(rng.uniform(0.5, 2.0) * 1e5) for i in range(9)})
        return out
    if kind == "geared":
        out = {
            ("inertia", n): float(rng.uniform(0.5, 2.0) * j)
            for n, j in zip("mpgtu", (1e-3, 2e-4, 4e-3, 0.05, 0.02), strict=True)
        }
        out.update({("stiffness", "s1"): 5e3, ("stiffness", "mesh"): 2e8, ("stiffness", "s2"): 2e4})
        out.update({("inertia", "s2"): 1e-3, ("stiffness", "k"): 1e3})
        return out
    out = {("inertia", f"d{i}"): float(rng.uniform(0.5, 2.0) * 1e-2) for i in range(6)}
    for i in (0, 1, 3, 4):
        out[("stiffness", f"s{i}")] = float(rng.uniform(0.5, 2.0) * 1e5)
        out[("damping", f"s{i}")] = float(rng.uniform(1.0, 5.0))
    out.update({("stiffness", "mesh"): 3e8, ("damping", "mesh"): 400.0, ("damping", "c"): 2.0})
    return out


BUILD = {"chain": _chain, "geared": _geared, "damped": _damped}


def _scaled(values, seed):
    """Every value times a factor from 0.6 to 1.4."""
    rng = np.random.default_rng(seed)
    return {key: v * float(rng.uniform(0.6, 1.4)) for key, v in values.items()}


def _as_changes(values):
    changes: dict[str, dict[str, float]] = {}
    for (field, name), v in values.items():
        changes.setdefault(field, {})[name] = v
    return changes


def _rel(a, b):
    """Largest difference of each column relative to that column's largest magnitude."""
    scale = np.maximum(np.abs(b).max(axis=0), 1e-300)
    return float((np.abs(a - b).max(axis=0) / scale).max()) if b.size else 0.0


# -- results identical to the model built from element lists -----------------------------------------


@pytest.mark.parametrize("kind", ["chain", "geared", "damped"])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_variant_gives_the_frequencies_and_shapes_of_the_model_built_from_lists(kind, seed):
    base_values = _base_values(kind)
    base = BUILD[kind](base_values)
    modal(base)  # the base is built, checked and analysed once
    new = _scaled(base_values, seed)
    variant = base.with_values(**_as_changes(new))
    assert "_values" in variant.__dict__  # made on the base's structure
    rebuilt = BUILD[kind](new)
    a, b = modal(variant), modal(rebuilt)
    assert a.omega.size == b.omega.size > 0 and a.solver == b.solver
    np.testing.assert_allclose(a.omega, b.omega, rtol=1e-12, atol=0)
    assert _rel(a.unit_shapes, b.unit_shapes) < 1e-12
    assert _rel(a.rigid_body_shapes, b.rigid_body_shapes) < 1e-12
    # and not the base's: the new values did reach the solve
    assert np.max(np.abs(a.omega / modal(base).omega - 1)) > 1e-3
    # the model is the same model, element for element
    assert variant == rebuilt and hash(variant) == hash(rebuilt)


def test_a_damped_variant_responds_as_the_model_built_from_lists():
    base_values = _base_values("damped")
    base = _damped(base_values)
    new = _scaled(base_values, 5)
    variant, rebuilt = base.with_values(**_as_changes(new)), _damped(new)
    for X in ("M", "K", "C"):
        A, B = getattr(variant.assembly, X).toarray(), getattr(rebuilt.assembly, X).toarray()
        np.testing.assert_allclose(A, B, rtol=1e-14, atol=1e-14 * np.abs(B).max())
    f = np.geomspace(5.0, 5e3, 40)
    x, y = frf(variant, f, {"d5": 1.0}), frf(rebuilt, f, {"d5": 1.0})
    assert x.method == y.method
    assert _rel(x.angles, y.angles) < 1e-12 and _rel(x.element_loads, y.element_loads) < 1e-12


def test_a_variant_of_a_variant_is_built_from_the_first_model():
    base_values = _base_values("geared")
    base = _geared(base_values)
    one = _scaled(base_values, 7)
    first = base.with_values(**_as_changes(one))
    two = dict(one)
    two[("stiffness", "mesh")] = 2.5e8
    second = first.with_values(stiffness={"mesh": 2.5e8})
    assert second._value_layout is base._value_layout
    assert second == _geared(two) and first == _geared(one)
    np.testing.assert_allclose(modal(second).omega, modal(_geared(two)).omega, rtol=1e-12)


# -- the structure reused, the values checked once at the edge ---------------------------------------


def test_a_variant_shares_its_bases_structure_and_is_not_checked_again(monkeypatch):
    base = _chain(_base_values("chain"))
    base.assembly
    variant = base.with_values(stiffness={"s3": 2e5}, inertia={"d0": 0.03})
    for key in ("dof_names", "dof_index", "_components"):
        assert variant.__dict__[key] is base.__dict__[key]
    assert variant._value_layout is base._value_layout

    def refuse(*args, **kwargs):
        raise AssertionError("checked again")

    monkeypatch.setattr("mechdyn.drivetrain.assembly._check_elements", refuse)
    monkeypatch.setattr("mechdyn.drivetrain.assembly._check_rigid_body", refuse)
    monkeypatch.setattr("mechdyn.vibration.harmonic.finite_matrices", refuse)
    result = modal(variant)
    assert variant.assembly.T is base.assembly.T
    assert result.omega.size == 9
    # its element objects are made when read, with the new values, and nothing else changed
    assert "elements" not in variant.__dict__
    assert variant.elements[3].stiffness == 2e5 and variant.disks[0].inertia == 0.03
    assert variant.elements[2] is base.elements[2]


@pytest.mark.parametrize(
    ("field", "name", "value", "words"),
    [
        ("stiffness", "s4", -5.0, "must be positive"),
        ("inertia", "d2", float("nan"), "not finite"),
        ("inertia", "d2", float("inf"), "not finite"),
        ("stiffness", "s0", 1e30, "beyond any machine"),
        ("inertia", "d7", 0.0, "must be positive"),
    ],
)
def test_a_bad_value_is_refused_naming_the_element_the_field_and_the_value(field, name, value, words):
    base = _chain(_base_values("chain"))
    base.assembly
    good = {f"d{i}": 0.01 for i in range(10)} if field == "inertia" else {f"s{i}": 1e5 for i in range(9)}
    good[name] = value
    with pytest.raises(ModelError, match=words) as err:
        base.with_values(**{field: good})
    assert err.value.element == name and err.value.field == field
    assert str(value)[:3] in str(err.value) or f"{value:g}" in str(err.value)


def test_names_and_fields_the_model_does_not_have_are_refused():
    base = _damped(_base_values("damped"))
    with pytest.raises(ModelError, match="not a disk or element"):
        base.with_values(stiffness={"nowhere": 1.0})
    with pytest.raises(ModelError, match="has no value 'damping'"):
        base.with_values(damping={"d0": 1.0})
    with pytest.raises(ModelError, match="as a mapping"):
        base.with_values(stiffness=[1.0])


def test_quantities_and_numpy_numbers_give_the_same_variant():
    base_values = _base_values("chain")
    base = _chain(base_values)
    plain = base.with_values(inertia={"d1": 0.02}, stiffness={"s1": 1.5e5})
    numpy_numbers = base.with_values(inertia={"d1": np.float64(0.02)}, stiffness={"s1": np.float64(1.5e5)})
    quantities = base.with_values(inertia={"d1": "200 kg*cm^2"}, stiffness={"s1": "150 kN*m/rad"})
    assert plain == numpy_numbers == quantities
    np.testing.assert_allclose(modal(plain).omega, modal(quantities).omega, rtol=1e-14)


def test_a_lazily_built_variant_pickles_and_copies_as_the_model():
    base = _geared(_base_values("geared"))
    variant = base.with_values(stiffness={"mesh": 3e8}, inertia={"s2": 2e-3})
    again = pickle.loads(pickle.dumps(variant))
    assert again == variant and again.elements[1].stiffness == 3e8 and again.elements[2].inertia == 2e-3
    assert repr(variant).startswith("Drivetrain(")
    with pytest.raises(AttributeError, match="no_such_attribute"):
        variant.no_such_attribute
