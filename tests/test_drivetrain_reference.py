"""Drivetrain modes against an independent reference: openTorsion, and textbook examples.

openTorsion (Aalto ARotor, https://github.com/Aalto-Arotor/openTorsion) assembles its own matrices
and solves the unsymmetric problem with :func:`scipy.linalg.eig`; its rigid gears use the same
convention as mechdyn (R_a θ_a + R_b θ_b = 0 for an external pair).
"""

from __future__ import annotations

import numpy as np
import pytest

from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, Shaft, modal

ot = pytest.importorskip("opentorsion")


def _ot_frequencies(assembly) -> np.ndarray:
    lam, _ = assembly.undamped_modal_analysis()
    lam = np.sort(np.real(lam))
    return np.sqrt(np.clip(lam, 0, None)) / (2 * np.pi)


@pytest.mark.parametrize("seed", range(5))
def test_random_free_chain_against_opentorsion(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 25))
    J = rng.uniform(1e-4, 1e-1, n)
    k = rng.uniform(1e3, 1e6, n - 1)
    ours = modal(
        Drivetrain(
            [Disk(f"{i}", J[i]) for i in range(n)],
            [Shaft(f"s{i}", (f"{i}", f"{i + 1}"), k[i]) for i in range(n - 1)],
        )
    )
    ref = ot.Assembly(
        [ot.Shaft(i, i + 1, 0, 0, k=k[i]) for i in range(n - 1)],
        disk_elements=[ot.Disk(i, J[i]) for i in range(n)],
    )
    f_ref = _ot_frequencies(ref)
    assert f_ref[0] == pytest.approx(0.0, abs=1e-3 * f_ref[1])  # its rigid-body mode
    np.testing.assert_allclose(ours.frequencies_hz, f_ref[1:], rtol=1e-8)


@pytest.mark.parametrize("seed", range(5))
def test_random_geared_chain_against_opentorsion(seed):
    # motor –k1– pinion =gear pair (radii R1, R2)= gear –k2– pinion2 =pair (R3, R4)= gear2 –k3– load
    rng = np.random.default_rng(100 + seed)
    J = rng.uniform(1e-4, 1e-1, 6)
    k = rng.uniform(1e3, 1e6, 3)
    R = rng.uniform(0.02, 0.2, 4)
    ours = modal(
        Drivetrain(
            [Disk(str(i), J[i]) for i in range(6)],
            [
                Shaft("k1", ("0", "1"), k[0]),
                GearMesh("g1", ("1", "2"), teeth=None, base_radii=(R[0], R[1])),
                Shaft("k2", ("2", "3"), k[1]),
                GearMesh("g2", ("3", "4"), base_radii=(R[2], R[3])),
                Shaft("k3", ("4", "5"), k[2]),
            ],
        )
    )
    g1 = ot.Gear(1, J[1], R[0])
    g2 = ot.Gear(2, J[2], R[1], parent=g1)
    g3 = ot.Gear(3, J[3], R[2])
    g4 = ot.Gear(4, J[4], R[3], parent=g3)
    ref = ot.Assembly(
        [ot.Shaft(0, 1, 0, 0, k=k[0]), ot.Shaft(2, 3, 0, 0, k=k[1]), ot.Shaft(4, 5, 0, 0, k=k[2])],
        disk_elements=[ot.Disk(0, J[0]), ot.Disk(5, J[5])],
        gear_elements=[g1, g2, g3, g4],
    )
    f_ref = _ot_frequencies(ref)
    np.testing.assert_allclose(ours.frequencies_hz, f_ref[1:], rtol=1e-8)


def test_friswell_geared_branch():
    # Friswell, Penny, Garvey & Lees, Dynamics of Rotating Machines (2010), geared example as
    # reproduced in openTorsion's tests: 425.4, 634.1, 3247.2 Hz.
    Im, Ir, Ig, km, kR = 400e-6, 700e-6, 25e-6, 1e4, 5e3
    dt = Drivetrain(
        [Disk("motor", Im), Disk("gear 1", Ig), Disk("gear 2", Ig), Disk("rotor 3", Ir), Disk("rotor 4", Ir)],
        [
            Shaft("k_m", ("motor", "gear 1"), km),
            Shaft("k_R 2-3", ("gear 2", "rotor 3"), kR),
            Shaft("k_R 1-4", ("gear 1", "rotor 4"), kR),
            GearMesh("mesh", ("gear 1", "gear 2"), teeth=(40, 40)),
        ],
    )
    np.testing.assert_allclose(modal(dt).frequencies_hz.round(1), [425.4, 634.1, 3247.2])


def test_friswell_example_9_7_1():
    # Friswell et al. (2010) example 9.7.1: 81.21, 141.21, 378.95, 536.36 Hz
    J = [3.5e-3, 3.5e-3, 3.5e-3, 0.15, 0.05]
    k = [12e3, 12e3, 14e3, 10e3]
    dt = Drivetrain(
        [Disk(str(i), J[i]) for i in range(5)], [Shaft(f"k{i}", (str(i), str(i + 1)), k[i]) for i in range(4)]
    )
    np.testing.assert_allclose(modal(dt).frequencies_hz.round(2), [81.21, 141.21, 378.95, 536.36])


def test_turret_b_rigid_gears_against_opentorsion(turret_b):
    # the rigid-gear indexing path (ratios 4 and 6) against openTorsion with radii in that ratio
    J = turret_b.inertias
    k = [e.stiffness for e in turret_b.elements if isinstance(e, Shaft)]
    g1, g3 = ot.Gear(1, J[1], 1.0), ot.Gear(3, J[3], 1.0)
    gears = [g1, ot.Gear(2, J[2], 4.0, parent=g1), g3, ot.Gear(4, J[4], 6.0, parent=g3)]
    ref = ot.Assembly(
        [ot.Shaft(0, 1, 0, 0, k=k[0]), ot.Shaft(2, 3, 0, 0, k=k[1]), ot.Shaft(4, 5, 0, 0, k=k[2])],
        disk_elements=[ot.Disk(0, J[0]), ot.Disk(5, J[5])],
        gear_elements=gears,
    )
    np.testing.assert_allclose(
        modal(turret_b, rigid_gears=True).frequencies_hz, _ot_frequencies(ref)[1:], rtol=1e-8
    )
