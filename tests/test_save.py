"""``mechdyn.save(model, path)``: a model built in Python (or loaded) written to a model file that
``mechdyn.load`` reads back equal — every float written as its ``repr`` with its SI unit."""

from __future__ import annotations

import dataclasses
import inspect
import json
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
from mechdyn.gear_dynamics.file import DrivetrainTimeSettings
from mechdyn.gears import GearPair, SpurGear
from mechdyn.mechanism import (
    Body,
    Counterweight,
    Driver,
    GearJoint,
    Mechanism,
    Prismatic,
    ProcessForce,
    Revolute,
    pitch,
)
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
    if isinstance(a, dict) and isinstance(b, dict):
        if list(a) != list(b):
            return f"{where}: keys {list(a)} vs {list(b)}"
        return next((d for k in a if (d := same(a[k], b[k], f"{where}[{k!r}]"))), None)
    if a == b:
        return None
    if inspect.isfunction(a) and inspect.isfunction(b):
        return _same_function(a, b, where)
    return f"{where}: {a!r} vs {b!r}"


# where a model holds a function (a pitch curve's radius, a tabulated process force, a speed profile),
# two models are equal when the functions were made by the same code and give the same values to the
# bit: a file's tables come back as new functions of the same tables
_PROBE = np.linspace(-7.0, 7.0, 1001)


def _same_function(a, b, where):
    if a.__code__ is not b.__code__:
        return f"{where}: {a.__qualname__} vs {b.__qualname__}"
    arguments = (_PROBE, np.linspace(-2.0, 2.0, _PROBE.size))[: a.__code__.co_argcount]
    return same(a(*arguments), b(*arguments), f"{where}(probe)")


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
    assert again.settings == DrivetrainTimeSettings()  # no analysis tables
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
    assert "[campbell]" in text or loaded.settings.campbell is None


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
    assert all(kind in str(info.value) for kind in ("Drivetrain", "Mechanism", "MountedMachine", "GearPair"))
    assert not (tmp_path / "x.toml").exists()


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


# -- mechanisms ----------------------------------------------------------------------------------------

MECHANISM_EXAMPLES = [
    "press_link_drive.toml",
    "press_tonnage.toml",  # rated torque and force, a forming force against crank angle
    "fourbar.toml",
    "slider_crank.toml",
    "transplanter_rp1.toml",
    "transplanter_rp1_design.toml",
]


def same_mechanism(a, b):
    """None when two mechanisms are equal field by field (their pitch curves by the function of their
    radius) and their gear pairs roll by the same law, to the bit; else where they first differ."""
    return same(a, b) or same(a.gear_laws, b.gear_laws, "gear_laws")


@pytest.mark.parametrize("example", MECHANISM_EXAMPLES)
def test_a_mechanism_example_comes_back_equal_with_its_settings(example, tmp_path):
    """load → save → load: the same mechanism and the same [settings] record (crank angles, traced
    points, field velocity); saving what came back writes the same text again."""
    loaded = mechdyn.load(EXAMPLES / example)
    again = round_trip(loaded, tmp_path)
    assert again.type == loaded.type
    assert same_mechanism(loaded.model, again.model) is None
    assert same(loaded.settings, again.settings) is None  # MechanismSpec: n_angles, trace, field velocity
    # plain equality, where no field is a function (a pitch curve, a tabulated process force)
    if not any(isinstance(j, GearJoint) for j in loaded.model.joints) and not loaded.model.process_forces:
        assert again.model == loaded.model and again.settings == loaded.settings
    text = (tmp_path / "saved.toml").read_text()
    assert mechdyn.save(again, tmp_path / "twice.toml").read_text() == text


def test_a_planting_mechanism_is_saved_by_its_design(tmp_path):
    loaded = mechdyn.load(EXAMPLES / "transplanter_rp1_design.toml")
    text = mechdyn.save(loaded, tmp_path / "rp1.toml").read_text()
    assert '[model]\ntype = "planting_mechanism"' in text and "[design]" in text
    assert "[[bodies]]" not in text  # the design variables, not the mechanism they build
    assert 'arm_radius = "0.0768 m"' in text and "eccentricity_ratio = 0.13" in text
    assert 'trace = ["F1", "F2"]' in text


def _fourbar():
    """A crank-rocker with its coupler point drawn by trigonometry (floats with every bit set),
    quantities given with units."""
    a, b, c, d = 0.05, 0.2, 0.15, 0.18
    theta = math.radians(60.0)
    A = (a * math.cos(theta), a * math.sin(theta))
    e = math.hypot(d - A[0], A[1])
    phi = math.atan2(-A[1], d - A[0]) + math.acos((b * b + e * e - c * c) / (2 * b * e))
    B = (A[0] + b * math.cos(phi), A[1] + b * math.sin(phi))
    return Mechanism(
        points={
            "O2": ("0 mm", "0 mm"),
            "A": A,
            "B": B,
            "O4": (f"{d * 1e3} mm", 0.0),
            "coupler point": (0.1, 0.1),
        },
        bodies=(
            Body("crank", ("O2", "A"), "0.3 kg", "6.25e-5 kg*m^2"),
            Body("coupler", ("A", "B", "coupler point"), 1.2, 4.0e-3 / 3, (0.11, 0.09)),
            Body("rocker", ("B", "O4"), 0.9, 1.6875e-3, "B"),
        ),
        joints=(
            Revolute("O2", ("ground", "crank"), "O2"),
            Revolute("A", ("crank", "coupler"), "A"),
            Revolute("B", ("coupler", "rocker"), "B"),
            Revolute("O4", ("rocker", "ground"), "O4"),
        ),
        driver=Driver("crank", "O2", "A", "114.59155902616465 rpm"),
        gravity=(0.0, "-9.80665 m/s^2"),
        angle_datum="12.5 deg",
        name="four-bar, built in Python",
    )


def _slider_crank(axis="0 deg"):
    return Mechanism(
        points={"O": (0.0, 0.0), "A": (0.1 / 3, 0.0), "B": (0.4, 0.0)},
        bodies=(
            Body("crank", ("O", "A"), 2.0, 0.002, (0.1 / 6, 0.0)),
            Body("rod", ("A", "B"), 3.0, 0.04),
            Body("slider", ("B",), 5.0, 0.0, "B"),
        ),
        joints=(
            Revolute("O", ("ground", "crank"), "O"),
            Revolute("A", ("crank", "rod"), "A"),
            Revolute("B", ("rod", "slider"), "B"),
            Prismatic("guide", ("slider", "ground"), "B", axis),
        ),
        driver=Driver("crank", "O", "A", "-1480 rpm"),
        output=("slider", "B"),
        angle_datum="bdc",
        name="slider-crank, built in Python",
    )


def _fourbar_with_counterweights():
    """The four-bar with counterweights: one at coordinates with its own inertia, one at a point,
    named; they come back as written, and folded into their links alike."""
    return dataclasses.replace(
        _fourbar(),
        counterweights=(
            Counterweight("crank", "0.375 kg", ("-50 mm", 0.1 / 3), "2e-5 kg*m^2"),
            Counterweight("rocker", 1.575, "O4", name="rocker weight"),
        ),
    )


@pytest.mark.parametrize(
    "build", [_fourbar, _slider_crank, lambda: _slider_crank("0.1 rad"), _fourbar_with_counterweights]
)
def test_a_mechanism_built_in_python_comes_back_equal(build, tmp_path):
    model = build()
    again = round_trip(model, tmp_path)
    assert again.type == "mechanism" and again.model == model
    assert again.model.counterweights == model.counterweights
    assert again.model.bare_bodies == model.bare_bodies
    assert again.settings.n_angles == 360 and again.settings.trace == ()  # the file's defaults
    assert mechdyn.mechanism.kinematics(again.model, 36).q == pytest.approx(
        mechdyn.mechanism.kinematics(model, 36).q, rel=0, abs=0
    )


def _gear_train(curve, *, internal=False, planetary=False, flank="load", a=None):
    """Gear 1, turned by the driver, meshing with gear 2 at ``a`` (by default 50 mm, 30 mm inside for a
    ring gear); ``planetary``: gear 1 is a fixed sun and the driver turns the carrier of gear 2."""
    a = a or (-0.03 if internal else 0.05)
    points = {"O1": (0.0, 0.0), "T1": (0.01, 0.0), "O2": (a, 0.0), "T2": (a, 0.01)}
    first = Body(
        "carrier" if planetary else "g1", ("O1", "T1", "O2") if planetary else ("O1", "T1"), 1.0, 2e-3
    )
    carrier = first.name if planetary else "ground"
    mesh = GearJoint(
        "mesh",
        ("ground" if planetary else "g1", "g2"),
        ("O1", "O2"),
        curve,
        carrier=carrier,
        orientation="7 deg",
        pressure_angle="22.5 deg",
        internal=internal,
        flank=flank,
    )
    return Mechanism(
        points,
        (first, Body("g2", ("O2", "T2"), 3.0, 5e-3, "O2")),
        (Revolute("A", ("ground", first.name), "O1"), Revolute("B", (carrier, "g2"), "O2"), mesh),
        Driver(first.name, "O1", "T1", 20.0),
        name="gear train",
    )


def _eccentric_closing(ratio):
    rho = 0.05 / pitch.closing_centre_distance(pitch.eccentric_circle(1.0, ratio))
    return pitch.eccentric_circle(rho, ratio * rho)


GEAR_TRAINS = {
    "circle": lambda: _gear_train(pitch.circle(0.02)),
    "ring": lambda: _gear_train(pitch.circle(0.015), internal=True, flank="fixed"),
    "eccentric": lambda: _gear_train(_eccentric_closing(0.17)),
    "ellipse": lambda: _gear_train(pitch.ellipse_about_focus(0.025, 0.2)),
    "planetary": lambda: _gear_train(pitch.circle(0.02), planetary=True),
}


@pytest.mark.parametrize("kind", sorted(GEAR_TRAINS))
def test_a_geared_mechanism_built_in_python_comes_back_equal(kind, tmp_path):
    model = GEAR_TRAINS[kind]()
    again = round_trip(model, tmp_path).model
    assert same_mechanism(model, again) is None


def test_a_planting_mechanism_built_in_python_is_saved_as_its_mechanism(tmp_path):
    from mechdyn.mechanism.planter import PlanterDesign, planter

    model = planter(PlanterDesign(eccentricity_ratio=0.11, com_offset="15 mm"), name="a variant")
    again = round_trip(model, tmp_path)
    assert again.type == "mechanism"  # its design is not kept by the mechanism: written body by body
    assert same_mechanism(model, again.model) is None


def test_a_file_with_every_table_comes_back_equal(tmp_path):
    """A speed profile, process forces against angle and position, a sampled pitch curve, the angle
    datum at bottom dead centre, traced points and a field velocity: written from what the mechanism
    keeps of them, and read back the same."""
    slider = (EXAMPLES / "slider_crank.toml").read_text()
    slider = slider.replace(
        'speed = "100 rad/s"',
        'speed = "-100 rad/s"\nspeed_profile = [["0 deg", "100 rad/s"], ["120 deg", "130 rad/s"], '
        '["200 deg", "90 rad/s"]]',
    )
    slider = slider.replace(
        "n_angles = 360",
        'n_angles = 90\nangle_datum = "bdc"\ntrace = ["A"]\nfield_velocity = ["1 km/h", "0.1 m/s"]\n'
        'gravity = ["0 m/s^2", "-9.81 m/s^2"]',
    )
    slider += (
        '\n[[process_forces]]\nbody = "slider"\npoint = "B"\ndirection = "180 deg"\nversus = "position"\n'
        'table = [["-0.2 m", "0 N"], ["0 m", "1 kN"]]\n'
        '\n[[process_forces]]\nbody = "rod"\npoint = "A"\ndirection = "33 deg"\nversus = "angle"\n'
        'table = [["10 deg", "0.5 kN"], ["30 deg", "2 kN"], ["50 deg", "0 N"]]\n'
    )
    gears = (EXAMPLES / "slider_crank.toml").parent / "transplanter_rp1.toml"
    radii = pitch.eccentric_circle(1.0, 0.1).radius(np.linspace(0, 2 * np.pi, 48, endpoint=False))
    rho = 0.0384 / pitch.closing_centre_distance(pitch.sampled(radii))
    sampled = 'pitch = { kind = "samples", radii = [' + ", ".join(f'"{r * rho} m"' for r in radii) + "] }"
    rp1 = gears.read_text().replace(
        'pitch = { kind = "eccentric", radius = "closing", eccentricity_ratio = 0.13 }\n'
        'orientation = "-35.000000000 deg"',
        f'{sampled}\norientation = "-35.000000000 deg"',
    )
    assert "samples" in rp1
    for name, text in (("slider.toml", slider), ("rp1.toml", rp1)):
        (tmp_path / name).write_text(text)
        loaded = load_quiet(tmp_path / name)  # a sampled planet meshing with an eccentric idler warns
        again = round_trip(loaded, tmp_path, f"saved_{name}")
        assert same_mechanism(loaded.model, again.model) is None, name
        assert same(loaded.settings, again.settings) is None, name
    written = (tmp_path / "saved_slider.toml").read_text()
    assert "speed_profile = [[" in written and written.count("[[process_forces]]") == 2
    assert 'angle_datum = "bdc"' in written
    assert "[joints.pitch]" in (tmp_path / "saved_rp1.toml").read_text()


def _summary(capsys, path):
    from mechdyn.cli.main import main

    assert main(["mechanism", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    return {k: v for k, v in doc.items() if k not in ("run_id", "model_file", "model_sha256", "created")}


def _figures(doc, where=""):
    """The numbers of a summary, by their path."""
    if isinstance(doc, dict):
        return {k: v for key, value in doc.items() for k, v in _figures(value, f"{where}/{key}").items()}
    if isinstance(doc, list):
        return {k: v for i, value in enumerate(doc) for k, v in _figures(value, f"{where}/{i}").items()}
    return {where: doc}


def test_the_saved_press_gives_the_same_summary(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("MECHDYN_DB", str(tmp_path / "runs.db"))
    monkeypatch.chdir(tmp_path)
    saved = mechdyn.save(mechdyn.load(EXAMPLES / "press_link_drive.toml"), tmp_path / "press.toml")
    original, again = _summary(capsys, EXAMPLES / "press_link_drive.toml"), _summary(capsys, saved)
    first, second = _figures(original), _figures(again)
    assert first.keys() == second.keys() and len(first) > 30
    for key, value in first.items():
        if isinstance(value, float):
            assert second[key] == pytest.approx(value, rel=1e-12, abs=1e-12), key
        elif not key.endswith("_s"):  # timings differ from run to run
            assert second[key] == value, key


def _python_force(theta, position):
    return 1e3 * np.cos(theta), 0.0 * theta


def _python_profile(angle):
    return 100.0 * (1.0 + 0.1 * np.cos(angle))


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (
            lambda m: dataclasses.replace(m, process_forces=(ProcessForce("slider", "B", _python_force),)),
            r"process force on body 'slider' at point 'B' is a Python function \(_python_force\).*"
            r"only as a table against crank angle or output position",
        ),
        (
            lambda m: dataclasses.replace(m, driver=Driver("crank", "O", "A", 100.0, _python_profile)),
            r"speed profile is a Python function .*only as rows \[angle, speed\] \(speed_profile\)",
        ),
    ],
)
def test_what_a_mechanism_file_cannot_hold_is_refused_by_name(change, message, tmp_path):
    model = change(mechdyn.load(EXAMPLES / "slider_crank.toml").model)
    with pytest.raises(MechdynError, match=message):
        mechdyn.save(model, tmp_path / "m.toml")
    assert not (tmp_path / "m.toml").exists()


def _unwritable_eccentricity():
    """An eccentric circle whose eccentricity no float ratio of its radius gives back to the bit."""
    rho, e = 0.0191, 0.17 * 0.0191
    while any((e / rho + k * math.ulp(e / rho)) * rho == e for k in range(-8, 9)):
        e = math.nextafter(e, 1.0)
    return pitch.eccentric_circle(rho, e)


def test_a_pitch_curve_the_file_cannot_rebuild_is_refused_by_name(tmp_path):
    radii = pitch.eccentric_circle(1.0, 0.1).radius(np.linspace(0, 2 * np.pi, 48, endpoint=False))
    rho = 0.05 / pitch.closing_centre_distance(pitch.sampled(radii))
    cases = [
        (
            pitch.PitchCurve("my gear", lambda th: np.full(np.shape(th), 0.02), circular=True),
            r"gear joint 'mesh' has a pitch curve 'my gear' whose radius is a Python function",
        ),
        (pitch.sampled(radii * rho), r"gear joint 'mesh' has a sampled pitch curve.*only to rounding"),
        (_unwritable_eccentricity(), r"no ratio times the radius 0.0191 m gives its eccentricity"),
    ]
    for curve, message in cases:
        model = _gear_train(curve, a=pitch.closing_centre_distance(curve) if not curve.circular else None)
        with pytest.raises(MechdynError, match=message):
            mechdyn.save(model, tmp_path / "m.toml")
        assert not (tmp_path / "m.toml").exists()
