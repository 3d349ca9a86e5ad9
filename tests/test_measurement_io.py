"""Measured FRFs read from Universal Files (dataset 58, written by pyuff's own writer) and CSV, in SI."""

from __future__ import annotations

import numpy as np
import pytest

from mechdyn.errors import ModelFileError
from mechdyn.measurement import MeasuredFRF, read_csv, read_uff

pyuff = pytest.importorskip("pyuff")

F = np.arange(1.0, 50.0, 0.5)  # Hz


def _h(fn: float, out: int, ref: int) -> np.ndarray:
    return (out + 1) * (ref + 2) / (1 - (F / fn) ** 2 + 0.05j * F / fn)


def _dataset(h, rsp_node, rsp_dir, ref_node, ref_dir, num="m/s^2", den="N", x=F, absc="Hz", **extra):
    fields = dict(
        func_type=4,
        rsp_node=rsp_node,
        rsp_dir=rsp_dir,
        ref_node=ref_node,
        ref_dir=ref_dir,
        data=h,
        x=x,
        id1="FRF",
        abscissa_spec_data_type=18,
        abscissa_axis_units_lab=absc,
        ordinate_spec_data_type=12,
        ordinate_axis_units_lab=num,
        orddenom_spec_data_type=13,
        orddenom_axis_units_lab=den,
        binary=0,
    )
    fields.update(extra)
    return pyuff.prepare_58(**fields)


def _write(path, sets):
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    return path


def test_uff58_written_by_pyuff_read_back_in_si_with_points_and_directions(tmp_path):
    # two outputs (node 3 along −z, node 5 along +x) to two references (node 1 +z, node 2 +y), in mm/s²/N
    outputs, refs = [(3, -3), (5, 1)], [(1, 3), (2, 2)]
    sets = [
        _dataset(_h(10.0, i, j), n, d, rn, rd, num="mm/s^2")
        for j, (rn, rd) in enumerate(refs)
        for i, (n, d) in enumerate(outputs)
    ]
    m = read_uff(_write(tmp_path / "tap.uff", sets))
    assert m.kind == "accelerance"
    assert m.outputs == (("3", "z"), ("5", "x"))
    assert m.references == (("1", "z"), ("2", "y"))
    assert m.H.shape == (F.size, 2, 2)
    np.testing.assert_allclose(m.omega, 2 * np.pi * F)
    # mm → m, and the −z response turned to +z
    np.testing.assert_allclose(m.H[:, 0, 1], -1e-3 * _h(10.0, 0, 1), rtol=1e-9)
    np.testing.assert_allclose(m.H[:, 1, 0], 1e-3 * _h(10.0, 1, 0), rtol=1e-9)
    assert m.summary()["outputs"] == ["3:z", "5:x"]


def test_uff58_in_inches_and_a_moment_reference(tmp_path):
    m = read_uff(_write(tmp_path / "in.uff", [_dataset(_h(8.0, 0, 0), 1, 3, 1, 3, num="in/s", den="lbf")]))
    assert m.kind == "mobility"
    np.testing.assert_allclose(m.H[:, 0, 0], _h(8.0, 0, 0) * 0.0254 / 4.4482216152605, rtol=1e-9)
    r = read_uff(_write(tmp_path / "rot.uff", [_dataset(_h(8.0, 0, 0), 1, 6, 1, 6, num="rad", den="N*m")]))
    assert r.kind == "receptance" and r.outputs == (("1", "rz"),)


def test_uff_without_unit_labels_takes_the_given_unit(tmp_path):
    path = _write(tmp_path / "bare.uff", [_dataset(_h(8.0, 0, 0), 1, 3, 1, 3, num="", den="")])
    with pytest.raises(ModelFileError, match=r"bare\.uff: dataset #1 .*ordinate_axis_units_lab.*units="):
        read_uff(path)
    m = read_uff(path, units="g_n/N")  # standard gravity per newton
    np.testing.assert_allclose(m.H[:, 0, 0], 9.80665 * _h(8.0, 0, 0), rtol=1e-9)


def test_as_receptance_divides_by_minus_omega_squared():
    w = 2 * np.pi * F
    m = MeasuredFRF(w, (-(w**2) * _h(9.0, 0, 0))[:, None, None], (("a", "z"),), (("a", "z"),), "accelerance")
    np.testing.assert_allclose(m.as_receptance().H[:, 0, 0], _h(9.0, 0, 0))


@pytest.mark.parametrize(
    ("num", "den", "match"),
    [
        ("m*s", "N", r"unit '\(m\*s\)/\(N\)'.*not a displacement, velocity or acceleration"),
        ("m/s^2", "kelvin", r"not a displacement"),
        ("bananas", "N", r"unit '\(bananas\)/\(N\)' is not understood"),
    ],
)
def test_uff_bad_units_name_the_file_dataset_and_value(tmp_path, num, den, match):
    path = _write(tmp_path / "bad.uff", [_dataset(_h(8.0, 0, 0), 1, 3, 1, 3, num=num, den=den)])
    with pytest.raises(ModelFileError, match=r"bad\.uff: dataset #1 \(type 58, FRF\).*" + match):
        read_uff(path)


def test_uff_bad_direction_and_mixed_grids(tmp_path):
    path = _write(tmp_path / "dir.uff", [_dataset(_h(8.0, 0, 0), 1, 0, 1, 3)])
    with pytest.raises(ModelFileError, match=r"dir\.uff: dataset #1 .*rsp_dir: direction code 0"):
        read_uff(path)
    x2 = np.arange(1.0, 50.0, 0.25)
    h2 = 1 / (1 - (x2 / 8) ** 2 + 0.05j)
    path = _write(
        tmp_path / "grid.uff", [_dataset(_h(8.0, 0, 0), 1, 3, 1, 3), _dataset(h2, 2, 3, 1, 3, x=x2)]
    )
    with pytest.raises(ModelFileError, match=r"grid\.uff: type-58 FRF datasets #2: frequencies .* resample"):
        read_uff(path)


def test_not_a_universal_file(tmp_path):
    path = tmp_path / "junk.uff"
    path.write_text("this is not a universal file\n")
    with pytest.raises(ModelFileError, match=r"junk\.uff"):
        read_uff(path)
    with pytest.raises(ModelFileError, match=r"nothing\.uff: file: does not exist"):
        read_uff(tmp_path / "nothing.uff")


def _csv(path, header, rows):
    lines = ["# a hammer test", ",".join(header)] + [",".join(f"{v:.12g}" for v in r) for r in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_csv_several_channels_re_im_and_magnitude_phase(tmp_path):
    h1, h2 = _h(10.0, 0, 0), _h(12.0, 1, 0)
    header = [
        "frequency [Hz]",
        "c1:z/c1:z re [mm/s^2/N]",
        "c1:z/c1:z im [mm/s^2/N]",
        "c2:x/c1:z mag [mm/s^2/N]",
        "c2:x/c1:z phase_deg [deg]",
    ]
    rows = np.column_stack([F, h1.real, h1.imag, np.abs(h2), np.degrees(np.angle(h2))])
    m = read_csv(_csv(tmp_path / "tap.csv", header, rows))
    assert m.kind == "accelerance"
    assert m.outputs == (("c1", "z"), ("c2", "x")) and m.references == (("c1", "z"),)
    np.testing.assert_allclose(m.H[:, 0, 0], 1e-3 * h1, rtol=1e-9)
    np.testing.assert_allclose(m.H[:, 1, 0], 1e-3 * h2, rtol=1e-9)
    np.testing.assert_allclose(m.frequencies_hz, F)


@pytest.mark.parametrize(
    ("header", "row", "match"),
    [
        (
            ["freq", "a:z/a:z re [m/N]", "a:z/a:z im [m/N]"],
            [1, 2, 3],
            r"header column 1: is 'freq'; it must be",
        ),
        (
            ["frequency [Hz]", "a:q/a:z re [m/N]", "a:q/a:z im [m/N]"],
            [1, 2, 3],
            r"header column 2: is 'a:q/a:z re",
        ),
        (["frequency [Hz]", "a:z/a:z re [m/N]"], [1, 2], r"FRF a:z/a:z: has columns \['re'\]"),
        (
            ["frequency [Hz]", "a:z/a:z re [m/N]", "a:z/a:z im [m/s/N]"],
            [1, 2, 3],
            r"two units 'm/N' and 'm/s/N'",
        ),
        (["frequency [s]", "a:z/a:z re [m/N]", "a:z/a:z im [m/N]"], [1, 2, 3], r"frequency unit 's' is not"),
        (
            ["frequency [Hz]", "a:z/a:z re [kg]", "a:z/a:z im [kg]"],
            [1, 2, 3],
            r"unit 'kg' .*not a displacement",
        ),
    ],
)
def test_csv_errors_name_the_file_column_and_value(tmp_path, header, row, match):
    path = _csv(tmp_path / "bad.csv", header, [row, [2.0, *row[1:]]])
    with pytest.raises(ModelFileError, match=r"bad\.csv: .*" + match):
        read_csv(path)


def test_csv_a_value_that_is_not_a_number(tmp_path):
    path = tmp_path / "nan.csv"
    path.write_text("frequency [Hz],a:z/a:z re [m/N],a:z/a:z im [m/N]\n1,2,3\n2,oops,3\n")
    with pytest.raises(
        ModelFileError, match=r"nan\.csv: data row 3, column 2 \(a:z/a:z re \[m/N\]\): is 'oops'"
    ):
        read_csv(path)


# ---- UFF 55: mode shapes ----------------------------------------------------------------------


def _machine_modes():
    from mechdyn.support import Mount, MountedMachine, RigidBody, modes

    corners = {
        f"{i + 1}": (sx * 1.2, sy * 0.8, 0.0)
        for i, (sx, sy) in enumerate([(-1, -1), (1, -1), (-1, 1), (1, 1)])
    }
    body = RigidBody(2000.0, (0.05, -0.03, 0.4), (400.0, 700.0, 900.0))
    k = (0.5e6, 0.8e6, 2.0e6)
    machine = MountedMachine(
        body, [Mount(n, xyz, k, tuple(1e-3 * v for v in k)) for n, xyz in corners.items()]
    )
    return machine, modes(machine), corners


def _shapes_at_corners(machine, found, corners):
    from mechdyn.measurement import observation_matrix

    outputs = [(n, d) for n in corners for d in "xyz"]
    return (observation_matrix(machine.dofs, outputs, corners) @ found.shapes).reshape(len(corners), 3, -1)


def test_uff55_normal_modes_written_by_pyuff_read_as_identified_modes(tmp_path):
    from mechdyn.measurement import compare_modes, read_uff_modes

    machine, found, corners = _machine_modes()
    at = _shapes_at_corners(machine, found, corners)
    zeta = 1e-3 * found.omega / 2  # stiffness-proportional damping
    sets = [
        pyuff.prepare_55(
            model_type=1,
            id1="modes",
            analysis_type=2,
            data_ch=2,
            spec_data_type=8,
            data_type=2,
            n_data_per_node=3,
            node_nums=[1, 2, 3, 4],
            load_case=1,
            mode_n=j + 1,
            freq=float(found.frequencies_hz[j]),
            modal_m=1.0,
            modal_damp_vis=float(zeta[j]),
            modal_damp_his=0.0,
            r1=-3.0 * at[:, 0, j],
            r2=-3.0 * at[:, 1, j],
            r3=-3.0 * at[:, 2, j],
        )
        for j in reversed(range(6))  # written highest first: read back sorted
    ]
    m = read_uff_modes(_write(tmp_path / "modes.uff", sets))
    np.testing.assert_allclose(m.frequencies_hz, found.frequencies_hz, rtol=5e-6)  # 6 digits in the file
    np.testing.assert_allclose(m.damping, zeta, rtol=1e-5)
    assert m.outputs == tuple((n, d) for n in corners for d in "xyz")
    assert np.abs(m.shapes).max() == pytest.approx(1.0)
    # paired with the model's own modes: MAC 1 on the diagonal (the scale and sign of a shape do not matter)
    cmp = compare_modes(m, found, corners)
    np.testing.assert_array_equal(cmp.pairs, np.column_stack([np.arange(6), np.arange(6)]))
    np.testing.assert_allclose(cmp.paired_mac, 1.0, atol=1e-9)
    np.testing.assert_allclose(cmp.frequency_error, 0.0, atol=5e-6)
    assert np.all(m.frequency_scatter_hz == 0)
    with pytest.raises(ValueError, match="no stabilisation chart"):
        m.plot()
    # the vertical components only
    z = read_uff_modes(tmp_path / "modes.uff", directions=("z",))
    assert z.outputs == tuple((n, "z") for n in corners)


def test_uff55_complex_modes_give_frequency_and_damping_from_the_eigenvalue(tmp_path):
    from mechdyn.measurement import read_uff_modes

    wn, zeta = 2 * np.pi * np.array([12.0, 30.0]), np.array([0.02, 0.05])
    lam = -zeta * wn + 1j * wn * np.sqrt(1 - zeta**2)
    shapes = np.array([[1.0, 0.5j, 0.0], [0.3, -1.0, 0.0]])  # (mode, node); r2 = 0: not measured
    sets = [
        pyuff.prepare_55(
            model_type=1,
            id1="complex",
            analysis_type=3,
            data_ch=2,
            spec_data_type=12,
            data_type=5,
            n_data_per_node=3,
            node_nums=[7, 8, 9],
            load_case=1,
            mode_n=j + 1,
            eig=lam[j],
            modal_a=0j,
            modal_b=0j,
            r1=shapes[j],
            r2=np.zeros(3, complex),
            r3=2j * shapes[j],
        )
        for j in range(2)
    ]
    m = read_uff_modes(_write(tmp_path / "complex.uff", sets))
    np.testing.assert_allclose(m.omega, wn, rtol=1e-5)  # the file keeps 6 digits
    np.testing.assert_allclose(m.damping, zeta, rtol=1e-5)
    # node 9 is zero in both modes and r2 everywhere: not measured, left out
    assert m.outputs == (("7", "x"), ("7", "z"), ("8", "x"), ("8", "z"))
    assert m.shapes.shape == (4, 2)


def test_uff55_errors_name_the_file_and_dataset(tmp_path):
    from mechdyn.measurement import read_uff_modes

    frf = _dataset(_h(10.0, 0, 0), 1, 3, 1, 3)
    with pytest.raises(ModelFileError, match=r"frf\.uff.*no dataset 55"):
        read_uff_modes(_write(tmp_path / "frf.uff", [frf]))
    bad = pyuff.prepare_55(
        model_type=1,
        id1="x",
        analysis_type=2,
        data_ch=2,
        spec_data_type=8,
        data_type=2,
        n_data_per_node=3,
        node_nums=[1],
        load_case=1,
        mode_n=1,
        freq=0.0,
        modal_m=1.0,
        modal_damp_vis=0.0,
        modal_damp_his=0.0,
        r1=np.ones(1),
        r2=np.ones(1),
        r3=np.ones(1),
    )
    with pytest.raises(ModelFileError, match=r"dataset #1 \(type 55, mode 1\) → freq"):
        read_uff_modes(_write(tmp_path / "zero.uff", [bad]))
