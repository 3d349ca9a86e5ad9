"""Mounts estimated from their drawing stand under a machine: drawing → stiffness → floor force."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.errors import MechdynError, ModelFileError
from mechdyn.mounts import MountEstimate
from mechdyn.mounts.calibration import fit_pad_factor
from mechdyn.registry import get
from mechdyn.store import ResultStore

PADS = EXAMPLES / "press_on_pads.toml"


@pytest.fixture(scope="module")
def pads():
    return mechdyn.load(PADS)


def test_every_mount_type_answers_the_one_stiffness_interface():
    for example in ("pad_shore60.toml", "anchor_concrete.toml", "wedge_mount.toml", "press_pad.toml"):
        est = mechdyn.load(EXAMPLES / example).model
        assert isinstance(est, MountEstimate)
        assert est.stiffness > 0 and est.loss_factor >= 0
        assert est.lateral_stiffness is None or est.lateral_stiffness > 0


def test_the_pads_of_the_drawing_stand_under_the_press(pads):
    pad = mechdyn.load(EXAMPLES / "press_pad.toml").model
    machine = pads.model
    assert len(machine.mounts) == 4
    for m in machine.mounts:
        # shear across the mount's axis, compression along it, as the pad estimate gives them
        np.testing.assert_allclose(
            m.stiffness, [pad.shear_stiffness, pad.shear_stiffness, pad.compression_stiffness]
        )
        # damping from the loss factor: ζ = η/2 at the machine's translational frequency per axis
        omega = np.sqrt(4 * m.stiffness / 600e3)
        np.testing.assert_allclose(m.damping, pad.loss_factor * m.stiffness / omega, rtol=1e-12)
    # the vertical mode is decoupled (symmetric layout): its frequency is √(4 k / m) exactly
    from mechdyn.support import modes

    md = modes(machine)
    z = md.dominant.index("z")
    assert md.frequencies_hz[z] == pytest.approx(
        math.sqrt(4 * pad.compression_stiffness / 600e3) / (2 * math.pi)
    )
    # each pad carries a quarter of the weight: δ = W / (4 k)
    np.testing.assert_allclose(machine.static_deflection, 600e3 * 9.80665 / (4 * pad.compression_stiffness))


def test_an_inline_estimate_equals_the_mount_file(tmp_path):
    text = PADS.read_text().replace(
        'mount = "press_pad.toml"',
        'estimate = { pad = { shore_a = 60, length = "600 mm", width = "600 mm", thickness = "30 mm" } }',
    )
    (tmp_path / "press_link_drive.toml").write_text((EXAMPLES / "press_link_drive.toml").read_text())
    path = tmp_path / "inline.toml"
    path.write_text(text)
    inline, ref = mechdyn.load(path).model, mechdyn.load(PADS).model
    for a, b in zip(inline.mounts, ref.mounts, strict=True):
        np.testing.assert_array_equal(a.stiffness, b.stiffness)
        np.testing.assert_array_equal(a.damping, b.damping)


def _support_with(tmp_path, mount_row: str) -> str:
    (tmp_path / "m.toml").write_text((EXAMPLES / "anchor_concrete.toml").read_text())
    path = tmp_path / "s.toml"
    rows = "".join(
        f'[[mounts]]\nname = "m{i}"\nposition = ["{x} m", "{y} m", "0 m"]\n{mount_row}\n'
        for i, (x, y) in enumerate([(-1, -1), (1, -1), (-1, 1), (1, 1)])
    )
    path.write_text(
        '[model]\ntype = "support"\n[machine]\nmass = "2 t"\ninertia = ["1 t*m^2", "1 t*m^2", "1 t*m^2"]\n'
        + rows
        + '[excitation]\nperiod = "0.1 s"\nharmonics = [[1, "1 kN", "0 deg"]]\n'
    )
    return path


def test_an_estimate_without_a_lateral_stiffness_asks_for_it(tmp_path):
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(_support_with(tmp_path, 'mount = "m.toml"'))
    assert "[[mounts]] #1 (name = 'm0') → lateral_stiffness" in str(info.value)
    assert "give lateral_stiffness" in str(info.value)
    loaded = mechdyn.load(_support_with(tmp_path, 'mount = "m.toml"\nlateral_stiffness = "2e7 N/m"'))
    anchor = mechdyn.load(tmp_path / "m.toml").model
    np.testing.assert_allclose(loaded.model.mounts[0].stiffness, [2e7, 2e7, anchor.joint_stiffness])
    np.testing.assert_array_equal(loaded.model.mounts[0].damping, 0.0)  # a bolted joint: η = 0


@pytest.mark.parametrize(
    "row, where, what",
    [
        (
            'estimate = { pad = { shore_a = 60, diameter = "50 mm" } }',
            "→ estimate → [pad] → thickness",
            "missing",
        ),
        ('mount = "nope.toml"', "→ mount", "no such file"),
        (
            'stiffness = ["1 N/m", "1 N/m", "1 N/m"]\nmount = "m.toml"',
            "[[mounts]] #1",
            "exactly one of the three",
        ),
    ],
)
def test_bad_mount_rows_are_named(tmp_path, row, where, what):
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(_support_with(tmp_path, row))
    assert where in str(info.value) and what in str(info.value)


def test_a_stored_calibration_is_applied_when_asked(tmp_path):
    text = PADS.read_text().replace(
        'mount = "press_pad.toml"', 'mount = "press_pad.toml"\ncalibration = "stored"', 1
    )
    for name in ("press_link_drive.toml", "press_pad.toml"):
        (tmp_path / name).write_text((EXAMPLES / name).read_text())
    path = tmp_path / "calibrated.toml"
    path.write_text(text)
    loaded = mechdyn.load(path)
    support = get("support")
    with pytest.raises(MechdynError, match="stored calibration"):
        support.run(loaded, cycles=1)
    pad = mechdyn.load(EXAMPLES / "press_pad.toml").model
    target = 0.8 * pad.compression_stiffness  # as if a test of the compound had found 80 %
    with ResultStore(tmp_path / "cal.db") as store:
        fit_pad_factor(pad, target, "load test of the pad, 2026").save(store)
        result = support.run(loaded, cycles=1, store=store)
    mounts = result.summary()["mounts_from_drawing"]
    cal = mounts["front left"]["calibration"]
    assert cal["provenance"] == "load test of the pad, 2026"
    assert cal["stiffness_after_N_per_m"][2] == pytest.approx(target, rel=1e-9)
    assert mounts["front right"]["calibration"] == "as drawn"
    k = {m.name: m.stiffness[2] for m in result.machine.mounts}
    assert k["front left"] == pytest.approx(target, rel=1e-9)
    assert k["front right"] == pytest.approx(pad.compression_stiffness, rel=1e-12)


def _rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _ry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def _rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


@pytest.mark.parametrize(
    "angles",
    [(30.0, 0.0, 0.0), (0.0, 30.0, 0.0), (0.0, 0.0, 30.0), (20.0, -35.0, 50.0)],
)
def test_a_mount_orientation_from_a_file_turns_about_x_then_y_then_z(tmp_path, angles):
    """`orientation = [about x, about y, about z]` as documented: axes = R_z R_y R_x, built by hand
    here. It was applied as z–y′–x″ with the angles in the given order, so ["30 deg", 0, 0] yawed
    the mount and left its compression axis at (0, 0, 1)."""
    orientation = ", ".join(f'"{a} deg"' for a in angles)
    rows = "".join(
        f'[[mounts]]\nname = "m{i}"\nposition = ["{x} m", "{y} m", "0 m"]\n'
        f'stiffness = ["1e5 N/m", "2e5 N/m", "1e6 N/m"]\norientation = [{orientation}]\nanchored = true\n'
        for i, (x, y) in enumerate([(-1, -1), (1, -1), (-1, 1), (1, 1)])
    )
    path = tmp_path / "tilted.toml"
    path.write_text(
        '[model]\ntype = "support"\n[machine]\nmass = "2 t"\ncenter_of_mass = ["0 m", "0 m", "0.5 m"]\n'
        'inertia = ["1 t*m^2", "1.5 t*m^2", "2 t*m^2"]\n'
        + rows
        + '[excitation]\nperiod = "0.1 s"\nharmonics = [[1, "1 kN", "0 deg"]]\n'
    )
    machine = mechdyn.load(path).model
    ax, ay, az = np.radians(angles)
    expected = _rz(az) @ _ry(ay) @ _rx(ax)
    for mount in machine.mounts:
        np.testing.assert_allclose(mount.axes, expected, atol=1e-15)
        # its stiffness in machine axes, assembled by hand: R diag(k) Rᵀ
        np.testing.assert_allclose(
            mount.stiffness_matrix, expected @ np.diag([1e5, 2e5, 1e6]) @ expected.T, rtol=1e-14, atol=1e-9
        )
    if angles == (30.0, 0.0, 0.0):  # tilted about x: the compression axis leans towards −y
        np.testing.assert_allclose(machine.mounts[0].axes[:, 2], [0.0, -0.5, math.sqrt(3) / 2], atol=1e-15)
