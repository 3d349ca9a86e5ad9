"""The single-DOF fit of examples/mount_frf.toml reproduced by the measurement path.

examples/mount_frf.csv is a synthetic receptance of a 2000 kg mass on a mount of k 1.2e7 N/m and
ζ 0.08 with 2 % complex noise (its header). The mount calibration fits k, c, m of 1/(k − m ω² + i c ω)
to it (:func:`mechdyn.mounts.fit_frf`); the measurement path reads it with
:func:`mechdyn.measurement.read_csv`, identifies the one mode (LSCF start, nonlinear least-squares
refinement) and reads the mode as a mass on a spring (:func:`mechdyn.measurement.single_dof`,
k = m ω_n²).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

import mechdyn
from mechdyn import registry
from mechdyn.errors import ModelFileError
from mechdyn.measurement import MeasuredFRF, identify_modes, read_csv, single_dof

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
K_TRUE, M_TRUE, ZETA_TRUE = 1.2e7, 2000.0, 0.08  # the CSV's header


@pytest.fixture(scope="module")
def both():
    measured = read_csv(EXAMPLES / "mount_frf.csv")
    found = identify_modes(measured, max_order=10)
    report = registry.get("mount").run(mechdyn.load(EXAMPLES / "mount_frf.toml"))
    return measured, found, report.summary()["frf_fit"]


def test_mount_frf_csv_is_read_as_one_driving_point_receptance(both):
    measured, _, _ = both
    assert measured.kind == "receptance"
    assert measured.H.shape == (64, 1, 1)
    assert measured.outputs == measured.references == (("mount", "z"),)
    assert measured.frequencies_hz[0] == pytest.approx(3.0) and measured.frequencies_hz[-1] == pytest.approx(
        30.0
    )
    # SI receptance: the static value is about 1/k
    assert abs(measured.H[0, 0, 0]) == pytest.approx(1 / K_TRUE, rel=0.1)


def test_single_dof_fit_of_mount_frf_reproduced_by_the_measurement_path(both):
    _, found, cal = both
    assert len(found.omega) == 1 and "refined" in found.method
    # k = m ω_n² with the mass the calibration's fit holds (it fits m with k and c)
    sd = single_dof(found, cal["mass_kg"])
    # the two paths agree within twice the stated scatter of the new one (the calibration's fit
    # states no uncertainty, only its relative residual)
    assert abs(sd.stiffness - cal["stiffness_N_per_m"]) <= 2 * sd.stiffness_std
    assert abs(sd.natural_frequency_hz - cal["natural_frequency_hz"]) <= 2 * sd.natural_frequency_std_hz
    assert abs(sd.damping_ratio - cal["damping_ratio"]) <= 2 * sd.damping_ratio_std
    assert abs(sd.damping - cal["damping_N_s_per_m"]) <= 2 * sd.damping_std
    # and both near the synthetic truth: the stiffness (with the true mass) within 2 scatters, the
    # damping ratio within 3 % (this draw's error is about 2.5 %, some 3 of its scatters: the
    # scatter from 64 lines is itself uncertain by about 20 %)
    true_m = single_dof(found, M_TRUE)
    assert abs(true_m.stiffness - K_TRUE) <= 2 * true_m.stiffness_std
    assert cal["stiffness_N_per_m"] == pytest.approx(K_TRUE, rel=0.01)
    assert sd.damping_ratio == pytest.approx(ZETA_TRUE, rel=0.03)
    assert cal["damping_ratio"] == pytest.approx(ZETA_TRUE, rel=0.03)
    # the residue gives the mass back: R = 1/(2 i m ω_d)
    assert sd.residue_mass == pytest.approx(M_TRUE, rel=0.02)
    assert sd.residue_mass == pytest.approx(cal["mass_kg"], rel=0.02)


def test_single_dof_of_an_exact_receptance_is_the_mass_spring_dashpot():
    # closed form: noise-free 1/(k − m ω² + i c ω) gives k, c, ζ and the residue mass exactly
    k, m, zeta = 3.0e6, 150.0, 0.05
    c = 2 * zeta * math.sqrt(k * m)
    f = np.linspace(2.0, 60.0, 300)
    w = 2 * np.pi * f
    H = 1.0 / (k - m * w**2 + 1j * c * w)
    meas = MeasuredFRF(w, H[:, None, None], (("p", "z"),), (("p", "z"),), "receptance")
    found = identify_modes(meas, max_order=6)
    sd = single_dof(found, m)
    assert sd.stiffness == pytest.approx(k, rel=1e-6)
    assert sd.damping == pytest.approx(c, rel=1e-5)
    assert sd.damping_ratio == pytest.approx(zeta, rel=1e-5)
    assert sd.residue_mass == pytest.approx(m, rel=1e-5)


def test_single_dof_names_a_bad_mass_or_mode(both):
    _, found, _ = both
    with pytest.raises(ValueError, match=re.escape("mass -1.0 kg must be positive")):
        single_dof(found, -1.0)
    with pytest.raises(ValueError, match="mode 3 is out of range: 1 modes"):
        single_dof(found, 2000.0, mode=3)
    with pytest.raises(ValueError, match=re.escape("mass_std -5.0 kg")):
        single_dof(found, 2000.0, mass_std=-5.0)


def test_a_single_frf_csv_with_a_bad_kind_or_columns_is_named(tmp_path):
    bad_kind = tmp_path / "kind.csv"
    bad_kind.write_text("# kind: velocity\nfrequency_Hz,real,imag\n1,1e-7,0\n2,1e-7,0\n")
    with pytest.raises(ModelFileError, match="is 'velocity'; write receptance, mobility or accelerance"):
        read_csv(bad_kind)
    bad_cols = tmp_path / "cols.csv"
    bad_cols.write_text("frequency_Hz,re,im\n1,1e-7,0\n2,1e-7,0\n")
    with pytest.raises(ModelFileError, match="give real and imag, or magnitude and phase_deg"):
        read_csv(bad_cols)
    accelerance = tmp_path / "acc.csv"
    accelerance.write_text("# kind: accelerance\nfrequency_Hz,real,imag\n1,1e-3,0\n2,2e-3,1e-4\n")
    m = read_csv(accelerance)
    assert m.kind == "accelerance" and m.H[1, 0, 0] == pytest.approx(2e-3 + 1e-4j)
