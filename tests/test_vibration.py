"""The shared linear-vibration core: one eigen path, one harmonic solve, one modal interface."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

from mechdyn.drivetrain import Disk, Drivetrain, Shaft, frf, modal
from mechdyn.support import Mount, MountedMachine, RigidBody, modes
from mechdyn.vibration import Modes, check_matrices, harmonic_solve, solve_eigen
from mechdyn.vibration import harmonic as harmonic_module


def _spd(n, seed):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    return A @ A.T + n * np.eye(n)


def _chain(n, k=1e5, j=1e-2):
    main = np.full(n, 2 * k)
    main[[0, -1]] = k
    return sp.csr_array(sp.diags_array([main, np.full(n - 1, -k), np.full(n - 1, -k)], offsets=[0, 1, -1])), (
        j * (1 + np.arange(n) / n)
    )


def test_a_full_mass_matrix_gives_the_generalised_eigenpairs_mass_normalised():
    K, M = _spd(7, 1), _spd(7, 2)
    lam, Q, used = solve_eigen(K, M)
    np.testing.assert_allclose(lam, sla.eigh(K, M, eigvals_only=True), rtol=1e-12)
    np.testing.assert_allclose(Q.T @ M @ Q, np.eye(7), atol=1e-12)
    np.testing.assert_allclose(K @ Q, M @ Q * lam, atol=1e-9 * np.abs(K).max())
    assert used == "dense"
    lam3, _, _ = solve_eigen(K, M, n_modes=3)
    np.testing.assert_allclose(lam3, lam[:3], rtol=1e-12)


@pytest.mark.parametrize("solver", ["dense", "banded", "sparse"])
def test_every_solver_gives_the_same_lowest_modes_of_a_chain(solver):
    K, mass = _chain(60)
    lam, Q, used = solve_eigen(K, mass, n_modes=5, solver=solver)
    ref = sla.eigh(K.toarray(), np.diag(mass), eigvals_only=True)[:5]
    np.testing.assert_allclose(lam[1:], ref[1:], rtol=1e-9)
    assert abs(lam[0]) < 1e-9 * ref[-1] and used == solver
    np.testing.assert_allclose(Q.T @ (mass[:, None] * Q), np.eye(5), atol=1e-9)
    # a diagonal mass given as a matrix takes the diagonal path
    again = solve_eigen(K, np.diag(mass), n_modes=5, solver=solver)[0]
    np.testing.assert_allclose(again, lam, rtol=1e-12, atol=1e-12 * lam[-1])


def test_an_unknown_solver_is_named():
    with pytest.raises(ValueError, match="unknown eigen solver 'qr'"):
        solve_eigen(np.eye(2), np.ones(2), solver="qr")


@pytest.mark.parametrize("n", [6, 300])  # LAPACK in blocks; SuperLU on sparse matrices
def test_harmonic_solve_matches_a_direct_solve_at_every_frequency(n, monkeypatch):
    K, mass = _chain(n)
    K = K + sp.diags_array(np.full(n, 1e3))  # grounded: finite at 0 rad/s
    C = 1e-4 * K
    M = sp.diags_array(mass)
    w = np.linspace(0.0, 3e3, 23)
    F = np.zeros(n)
    F[0] = 1.0
    monkeypatch.setattr(harmonic_module, "_BLOCK_ENTRIES", 5 * n * n)  # blocks of 5 frequencies
    for Ks, Cs, Ms in ((K, C, M), (K.toarray(), C.toarray(), M.toarray())):
        X = harmonic_solve(Ks, Cs, Ms, F, w)
        assert X.shape == (w.size, n)
        for i in (0, 4, 5, 22):
            Z = K.toarray() + 1j * w[i] * C.toarray() - w[i] ** 2 * M.toarray()
            np.testing.assert_allclose(X[i], np.linalg.solve(Z, F), rtol=1e-9, atol=1e-15)
    # a load that differs per frequency
    rows = np.outer(np.arange(1, w.size + 1), F)
    np.testing.assert_allclose(harmonic_solve(K, C, M, rows, w)[7], 8 * X[7], rtol=1e-9)


@pytest.mark.parametrize("method", ["modal", pytest.param("direct", marks=pytest.mark.slow)])
def test_frf_memory_does_not_grow_with_the_number_of_frequencies(method):
    # the (frequencies × n × n) array of the past grew as n_f n²; now only the output grows (n_f n)
    n = 250
    dt = Drivetrain(
        [Disk(f"d{i}", 1e-2) for i in range(n)],
        [Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), 1e5) for i in range(n - 1)],
    )
    peaks = []
    for nf in (20, 400):
        tracemalloc.start()
        frf(dt, np.linspace(1.0, 50.0, nf), {"d0": 1.0}, outputs=("d0",), method=method)
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    output_growth = 380 * (2 * n) * 16 * 2  # angles and element loads, complex
    assert peaks[1] - peaks[0] < 3 * output_growth  # the old path grew by 380 n² 16 = 380 MB


def test_drivetrain_and_support_modes_share_one_interface(turret_c):
    body = RigidBody("2 t", ("0 m", "0 m", "0.6 m"), ("400 kg*m^2", "700 kg*m^2", "900 kg*m^2"))
    corners = [(-1.2, -0.8), (1.2, -0.8), (-1.2, 0.8), (1.3, 0.8)]
    machine = MountedMachine(
        body, [Mount(f"m{i}", (x, y, 0.0), (5e5, 5e5, 2e6)) for i, (x, y) in enumerate(corners)]
    )
    for m in (modal(turret_c), modes(machine)):
        assert isinstance(m, Modes)
        np.testing.assert_allclose(m.frequencies_hz, m.omega / (2 * np.pi), rtol=1e-15)
        ke = m.kinetic_energy
        assert ke.shape == (len(m.coordinate_names), m.omega.size)
        np.testing.assert_allclose(ke.sum(axis=0), 1.0, atol=1e-9)
        assert len(m.dominant) == m.omega.size and np.all(m.decoupling <= 1 + 1e-12)
    # a machine's frequencies: the same as the generalised problem solved here
    ref = np.sqrt(sla.eigh(machine.stiffness_matrix, machine.mass_matrix, eigvals_only=True)) / (2 * np.pi)
    np.testing.assert_allclose(modes(machine).frequencies_hz, ref, rtol=1e-12)


def test_the_matrix_check_is_shared():
    import mechdyn.drivetrain

    assert mechdyn.drivetrain.check_matrices is check_matrices
