"""``mechdyn.save(model, path)``: a model built in Python (or loaded) written to a model file that
``mechdyn.load`` reads back equal — every float written as its ``repr`` with its SI unit."""

from __future__ import annotations

import dataclasses
import math
import os
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import mechdyn
from conftest import EXAMPLES
from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, GroundDamper, GroundSpring, Shaft
from mechdyn.errors import MechdynError, ModelWarning
from mechdyn.gears import GearPair, SpurGear
from mechdyn.support import PLANAR, Mount, MountedMachine, PeriodicLoad, RigidBody, Rotor


def same(a, b, where="model"):
    """None when ``a`` and ``b`` are equal field by field (dataclass equality, with NumPy arrays
    compared exactly), else where they first differ."""
    if dataclasses.is_dataclass(a) and not isinstance(a, type):
        if type(a) is not type(b):
            return f"{where}: {type(a).__name__} vs {type(b).__name__}"
        for f in dataclasses.fields(a):
            if f.compare:
                found = same(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}")
                if found:
                    return found
        return None
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        ok = np.shape(a) == np.shape(b) and np.array_equal(a, b)
        return None if ok else f"{where}: {a!r} vs {b!r}"
    if isinstance(a, tuple | list) and isinstance(b, tuple | list):
        if type(a) is not type(b) or len(a) != len(b):
            return f"{where}: {a!r} vs {b!r}"
        return next(
            (d for i, (x, y) in enumerate(zip(a, b, strict=True)) if (d := same(x, y, f"{where}[{i}]"))), None
        )
    return None if a == b else f"{where}: {a!r} vs {b!r}"


def round_trip(model, tmp_path, name="saved.toml", **options):
    path = mechdyn.save(model, tmp_path / name, **options)
    assert path == tmp_path / name
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)  # the published turret ratios warn, as they should
        return mechdyn.load(path)


def load_quiet(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        return mechdyn.load(path)


EXAMPLE_MODELS = [
    "turret_indexing.toml",
    "turret_milling.toml",
    "turret_indexing_gear_data.toml",
    "turret_milling_gear_data.toml",
    "press_on_support.toml",
    "press_on_mounts.toml",
    "press_on_pads.toml",
    "pump_set_unbalance.toml",
    "spur_pair.toml",
]


@pytest.mark.parametrize("example", EXAMPLE_MODELS)
def test_a_shipped_example_comes_back_equal(example, tmp_path):
    """load example → save → load: the same model, the same analysis settings (a support's mechanism
    file named relative to the new file, its mounts estimated from drawings written as numbers)."""
    loaded = load_quiet(EXAMPLES / example)
    again = round_trip(loaded, tmp_path)
    assert again.type == loaded.type
    assert same(loaded.model, again.model) is None
    if loaded.type == "drivetrain":
        assert loaded.model == again.model  # plain dataclass equality
        assert again.settings == loaded.settings  # [campbell] and [response]
    if loaded.type == "gear_pair":
        assert loaded.model == again.model and again.settings == loaded.settings
    if loaded.type == "support":
        spec, back = loaded.settings, again.settings
        assert back.settings == spec.settings and back.speed_range == spec.speed_range
        if spec.mechanism_path is not None:
            assert back.mechanism_path is not None
            assert Path(back.mechanism_path).resolve() == Path(spec.mechanism_path).resolve()
            assert same(spec.excitation.placement, back.excitation.placement) is None
            assert spec.excitation.angles == back.excitation.angles
        else:
            assert same(spec.load, back.load) is None  # rotors come back exactly


def test_a_support_file_names_its_mechanism_relative_to_where_it_is_saved(tmp_path):
    loaded = mechdyn.load(EXAMPLES / "press_on_mounts.toml")
    (tmp_path / "deep" / "er").mkdir(parents=True)
    text = mechdyn.save(loaded, tmp_path / "deep" / "er" / "press.toml").read_text()
    expected = os.path.relpath(EXAMPLES / "press_link_drive.toml", tmp_path / "deep" / "er")
    assert f'mechanism = "{expected}"' in text
    again = mechdyn.load(tmp_path / "deep" / "er" / "press.toml")
    assert same(loaded.model, again.model) is None


def _gearbox(elements=None, name="gearbox"):
    disks = (
        Disk("motor", "4.0369e-3 kg*m^2"),
        Disk("pinion", 1.3e-4),
        Disk("gear", 0.031),
        Disk("ring", 0.7),
    )
    disks += (Disk("planet", 2.2e-3), Disk("out", 1.1))
    if elements is None:
        elements = (
            Shaft("input shaft", ("motor", "pinion"), "0.95e6 N*m/rad", damping=0.1),
            Shaft("output shaft", ("ring", "out"), 3.3e5),
            GearMesh(
                "flexible", ("pinion", "gear"), teeth=(19, 77), base_radii=(0.0179, 0.07254), stiffness=2.7e9
            ),
            GearMesh(
                "damped", ("gear", "ring"), ratio=2.5, base_radii=(0.04, 0.1), stiffness=1e9, damping=120.0
            ),
            GearMesh("rigid", ("ring", "planet"), kind="internal", teeth=(80, 20)),
            GroundSpring("motor mount", "motor", 1234.5),
            GroundDamper("drag", "out", 0.37),
        )
    return Drivetrain(disks, elements, name=name)


def test_a_drivetrain_built_in_python_comes_back_equal(tmp_path):
    """Meshes by teeth, ratio and base radii, flexible, damped, internal and rigid; shaft damping;
    grounded springs and dampers; quantities given with units or as SI floats."""
    model = _gearbox()
    again = round_trip(model, tmp_path)
    assert again.type == "drivetrain" and again.model == model
    assert again.settings == (None, None)
    text = (tmp_path / "saved.toml").read_text()
    assert 'inertia = "0.0040369 kg*m^2"' in text and 'kind = "internal"' in text
    assert "[[ground_dampers]]" in text and "ratio = 2.5" in text
    # the same analysis on both
    assert mechdyn.drivetrain.modal(again.model).frequencies_hz == pytest.approx(
        mechdyn.drivetrain.modal(model).frequencies_hz, rel=0, abs=0
    )


def test_a_drivetrain_comes_back_with_its_elements_grouped_as_the_file_lists_them(tmp_path):
    model = _gearbox()
    shuffled = dataclasses.replace(model, elements=tuple(reversed(model.elements)))
    again = round_trip(shuffled, tmp_path).model
    kinds = [type(e).__name__ for e in again.elements]
    assert kinds == sorted(kinds, key=["Shaft", "GearMesh", "GroundSpring", "GroundDamper"].index)
    by_name = {e.name: e for e in shuffled.elements}
    assert all(by_name[e.name] == e for e in again.elements)
    assert again.disks == shuffled.disks


positive = st.floats(min_value=1e-6, max_value=1e6, allow_nan=False, allow_infinity=False)


@given(inertias=st.lists(positive, min_size=2, max_size=4), k=positive, c=st.floats(0.0, 1e4), kc=positive)
def test_any_float_of_a_drivetrain_comes_back_bit_for_bit(tmp_path_factory, inertias, k, c, kc):
    disks = tuple(Disk(f"d{i}", J) for i, J in enumerate(inertias))
    elements = (
        Shaft("s", ("d0", "d1"), k, damping=c),
        GearMesh(
            "m",
            ("d1", disks[-1].name) if len(disks) > 2 else ("d0", "d1"),
            ratio=1.7,
            base_radii=(0.01, 0.017),
            stiffness=kc * 1e3,
        ),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        model = Drivetrain(disks, elements)
    again = round_trip(model, tmp_path_factory.mktemp("h"))
    assert again.model == model


def test_a_drivetrain_keeps_its_analysis_tables_and_provenance_comments(tmp_path):
    loaded = load_quiet(EXAMPLES / "turret_milling_gear_data.toml")
    text = mechdyn.save(loaded, tmp_path / "c.toml").read_text()
    assert "# gear pair" in text  # where the mesh stiffness came from, as a comment
    assert "[campbell]" in text or loaded.settings[0] is None


def _machine(**kw):
    body = RigidBody(
        "1200 kg", ("0.1 m", "0.05 m", "0.7 m"), [[300.0, 12.0, -4.0], [12.0, 450.0, 3.0], [-4.0, 3.0, 380.0]]
    )
    corners = [(-0.9, -0.6), (0.9, -0.6), (-0.9, 0.6), (0.9, 0.6)]
    mounts = [
        Mount(f"m{i}", (x, y, 0.0), (2e6, 2.1e6, 7.3e6), damping=(1e3, 1.1e3, 3e3), anchored=i == 0)
        for i, (x, y) in enumerate(corners)
    ]
    return MountedMachine(body, mounts, name="test machine", gravity=9.81, **kw)


LOADS = {
    "harmonics": PeriodicLoad.from_harmonics("0.05 s", {1: 3000 * np.exp(0.3j), 3: 500j}, 200.0),
    "samples": PeriodicLoad.from_samples(0.1, np.array([0.0, 1e3, 2.5e3, -1e3, 7.0])),
    "rotors": PeriodicLoad.from_unbalance(
        [
            Rotor("0.02 kg*m", "1480 rpm", "y", ("0.1 m", "0 m", "0.7 m"), "30 deg", "fan"),
            Rotor("0.01 kg*m", "2960 rpm", [1.0, 1.0, 0.0], name="pump"),
        ]
    ),
}


@pytest.mark.parametrize("kind", sorted(LOADS))
def test_a_machine_on_mounts_built_in_python_comes_back_equal_with_its_load(kind, tmp_path):
    machine, load = _machine(), LOADS[kind]
    again = round_trip(machine, tmp_path, load=load)
    assert again.type == "support"
    assert same(machine, again.model) is None
    back = again.settings.load
    if kind == "rotors":
        assert same(load, back) is None  # the rotors exactly, and so their load
    else:  # a vertical force as samples or amplitude and phase: to rounding
        assert back.period == load.period
        np.testing.assert_allclose(
            back.coefficients, load.coefficients, rtol=0, atol=1e-12 * abs(load.coefficients).max()
        )


def test_a_planar_machine_and_the_one_degree_of_freedom_support_come_back_equal(tmp_path):
    planar = _machine(dofs=PLANAR)
    assert same(planar, round_trip(planar, tmp_path, "p.toml", load=LOADS["harmonics"]).model) is None
    for zeta in (0.0, 0.05, 0.0537, 1.0 / 3.0, 2.0):
        single = MountedMachine.single_dof("600 t", "4.5e8 N/m", zeta, name="press")
        again = round_trip(single, tmp_path, "s.toml", load=LOADS["samples"]).model
        assert same(single, again) is None, zeta
    assert "[support]" in (tmp_path / "s.toml").read_text()


def test_mount_orientations_come_back_to_rounding(tmp_path):
    mounts = [
        Mount.with_orientation(f"m{i}", (x, y, 0.0), (2e6, 2e6, 8e6), angles, anchored=True)
        for i, ((x, y), angles) in enumerate(
            zip(
                [(-1, -1), (1, -1), (-1, 1), (1, 1)],
                [(0.3, 0.0, 0.0), (0.0, 0.0, 0.0), (0.1, -0.2, 1.1), (0, 0, 0)],
                strict=True,
            )
        )
    ]
    machine = MountedMachine(RigidBody(900.0, (0, 0, 0.5), (200.0, 200.0, 300.0)), mounts)
    again = round_trip(machine, tmp_path, load=LOADS["harmonics"]).model
    for a, b in zip(machine.mounts, again.mounts, strict=True):
        np.testing.assert_allclose(b.axes, a.axes, rtol=0, atol=1e-15)
        assert np.array_equal(b.stiffness, a.stiffness) and np.array_equal(b.position, a.position)
    assert np.array_equal(again.mounts[0].axes, machine.mounts[0].axes)  # one turn: exact
    assert np.array_equal(again.mounts[1].axes, np.eye(3))


def test_a_gear_pair_built_in_python_comes_back_equal(tmp_path):
    pinion = SpurGear(
        21,
        "2.5 mm",
        "18 mm",
        profile_shift=0.2,
        youngs_modulus="210 GPa",
        poisson_ratio=0.29,
        bore_diameter="20 mm",
        rim_thickness="9 mm",
        web_width="7 mm",
        name="pinion",
    )
    gear = SpurGear(53, "2.5 mm", "18 mm", profile_shift=-0.1, fillet_radius=0.3, name="gear")
    pair = GearPair(pinion, gear, tooth_model="truncated")
    again = round_trip(pair, tmp_path)
    assert again.type == "gear_pair" and again.model == pair


@pytest.mark.parametrize(
    ("model", "named"),
    [
        (object(), "builtins.object"),
        ((1, 2), "builtins.tuple"),
        (Disk("d", 1.0), "mechdyn.drivetrain.elements.Disk"),
    ],
)
def test_an_unsupported_model_names_its_type_and_what_can_be_saved(model, named, tmp_path):
    with pytest.raises(MechdynError, match=re.escape(named)) as info:
        mechdyn.save(model, tmp_path / "x.toml")
    assert "Drivetrain, MountedMachine, GearPair" in str(info.value)
    assert not (tmp_path / "x.toml").exists()


def test_a_mechanism_is_not_saved_yet_and_says_how_to_write_one(tmp_path):
    mechanism = mechdyn.load(EXAMPLES / "fourbar.toml").model
    with pytest.raises(MechdynError, match=r"Mechanism.*mechdyn new mechanism"):
        mechdyn.save(mechanism, tmp_path / "m.toml")


def test_a_machine_needs_its_load_and_a_load_the_file_can_hold(tmp_path):
    with pytest.raises(MechdynError, match="needs the machine's load"):
        mechdyn.save(_machine(), tmp_path / "x.toml")
    sideways = PeriodicLoad.from_samples(0.1, np.array([[1.0, 0, 2.0, 0, 0, 0], [0.0, 0, 1.0, 0, 0, 0]]))
    with pytest.raises(MechdynError, match=r"vertical force.*also has Fx"):
        mechdyn.save(_machine(), tmp_path / "x.toml", load=sideways)
    with pytest.raises(MechdynError, match=r"give a mechdyn\.support\.PeriodicLoad"):
        mechdyn.save(_machine(), tmp_path / "x.toml", load=[1.0, 2.0])


def test_save_refuses_a_folder_or_a_missing_folder(tmp_path):
    with pytest.raises(MechdynError, match="is a folder"):
        mechdyn.save(_gearbox(), tmp_path)
    with pytest.raises(MechdynError, match="is not a folder"):
        mechdyn.save(_gearbox(), tmp_path / "no" / "x.toml")


def test_a_saved_file_reads_as_a_person_would_write_it(tmp_path):
    model = Drivetrain((Disk("motor", 0.02), Disk("load", 0.5)), (Shaft("shaft", ("motor", "load"), 2e4),))
    text = mechdyn.save(model, tmp_path / "two.toml").read_text()
    assert text.startswith("# A drivetrain, written by mechdyn.save")
    assert '[model]\ntype = "drivetrain"\nname = "drivetrain"' in text
    assert '[[shafts]]\nname = "shaft"\ndisks = ["motor", "load"]\nstiffness = "20000.0 N*m/rad"' in text
    assert math.isclose(
        mechdyn.drivetrain.modal(mechdyn.load(tmp_path / "two.toml").model).frequencies_hz[0],
        162.3068321,
        rel_tol=1e-9,
    )
