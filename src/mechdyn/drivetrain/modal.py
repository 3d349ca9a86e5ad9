"""Natural frequencies, mode shapes and modal energy of a drivetrain."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp

from mechdyn.checks import check_count
from mechdyn.drivetrain.assembly import _DENSE_STIFFNESS, Assembly, _unit_shapes
from mechdyn.drivetrain.model import Drivetrain
from mechdyn.results import Result, Table
from mechdyn.vibration.eigen import Solver, dense_modes, solve_eigen
from mechdyn.vibration.modes import Modes

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["ModalResult", "modal", "stiffness_factor"]


def stiffness_factor(asm: Assembly) -> sp.csr_array | None:
    """F with K = Fᵀ F on the assembly's coordinates: one row per spring, from the element blocks.

    Parameters
    ----------
    asm : Assembly
        The assembled drivetrain (its rigid meshes already reduced out, θ = T q).

    Returns
    -------
    scipy.sparse.csr_array or None
        (n_springs, n_coordinates), in √(N·m/rad): a shaft of stiffness k between disks a and b gives
        the row √k (e_a − e_b); a flexible mesh √k_c (r_a e_a ± r_b e_b) (r_a, r_b base radii in m,
        k_c in N/m); a grounded spring √k e_a; a shaft divided into elements one row per sub-element
        (:attr:`~mechdyn.drivetrain.elements.ElementBlocks.stiffness_rows`); each row is then carried to
        the independent coordinates as F_full T. None when some element's stiffness block is neither of
        rank one nor given as such rows (no element today).

    Notes
    -----
    Each rank-one block S = s sᵀ is factored on its own, s = S[:, j]/√S_jj at its largest diagonal
    entry j, so the entries of F keep the relative accuracy of the element data (no sums, no
    cancellation). :func:`mechdyn.vibration.solve_eigen` uses F to get the natural frequencies to high
    relative accuracy when inertias or stiffnesses spread over many decades.
    """
    dt = asm.drivetrain
    rows: list[np.ndarray] = []
    cols: list[np.ndarray] = []
    vals: list[np.ndarray] = []
    count = 0
    for g in dt.block_groups("stiffness"):
        B, dofs = g.blocks, g.dofs
        m, width = dofs.shape
        j = np.argmax(np.diagonal(B, axis1=1, axis2=2), axis=1)
        pivot = B[np.arange(m), j, j]
        s = B[np.arange(m), :, j] / np.sqrt(np.where(pivot > 0, pivot, 1.0))[:, None]
        scale = np.abs(B).max(axis=(1, 2))
        misfit = np.abs(B - s[:, :, None] * s[:, None, :]).max(axis=(1, 2))
        bad = ((pivot <= 0) & (scale > 0)) | (misfit > 1e-12 * scale)
        for i in np.flatnonzero(bad):  # not of rank one: the element's own springs, if it gives them
            given = dt.element_blocks[g.elements[i]][1].stiffness_rows
            if given is None:
                return None
            r = given.shape[0]
            rows.append(np.repeat(count + np.arange(r), width))
            cols.append(np.tile(dofs[i], r))
            vals.append(np.asarray(given, dtype=float).ravel())
            count += r
        at = np.flatnonzero(~bad)
        rows.append(np.repeat(count + np.arange(at.size), width))
        cols.append(dofs[at].ravel())
        vals.append(s[at].ravel())
        count += at.size
    F = sp.csr_array(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))) if rows else ([], ([], [])),
        shape=(count, len(dt.dof_names)),
    )
    return F if asm.T.shape[0] == asm.T.shape[1] else sp.csr_array(F @ asm.T)


def _small_dense(asm: Assembly, n_rb: int) -> tuple[np.ndarray, np.ndarray, str] | None:
    """All modes of a small model with a diagonal M and a dense stiffness operator by one LAPACK call
    (:func:`mechdyn.vibration.eigen.dense_modes`); None where it does not apply or is in doubt."""
    mass = asm.mass_diagonal
    K = asm.stiffness_operator
    if mass is None or asm.n > _DENSE_STIFFNESS or not isinstance(K, np.ndarray):
        return None
    found = dense_modes(K, mass, n_rb)
    return None if found is None else (*found, "dense")


@dataclass(frozen=True, repr=False)  # the short repr of Result
class ModalResult(Result, Modes):
    """Undamped modes of a drivetrain.

    Attributes
    ----------
    assembly : Assembly
        The assembled model the modes belong to.
    omega : ndarray
        Natural circular frequencies of the flexible modes, rad/s, ascending.
    shapes : ndarray
        (n_dofs, n_modes) mass-normalised mode shapes for *every* disk, including disks removed by
        rigid meshes (recovered as θ = T q), then the nodes inside divided shafts
        (:attr:`Drivetrain.dof_names`), angles in rad for unit modal amplitude.
    rigid_body_shapes : ndarray
        (n_dofs, n_rigid_body) rigid-body motions, rad, largest entry 1.
    solver : str
        The eigen solver that ran.
    reduced_shapes : ndarray
        (n_coordinates, n_modes) the same modes on the independent coordinates, rad (shapes = T @ this).
    rigid_gears : bool
        Whether the gear meshes were taken as rigid constraints.
    """

    assembly: Assembly
    omega: np.ndarray
    shapes: np.ndarray
    rigid_body_shapes: np.ndarray
    solver: str
    reduced_shapes: np.ndarray
    rigid_gears: bool = False

    @property
    def drivetrain(self) -> Drivetrain:
        return self.assembly.drivetrain

    @property
    def rigid_body_modes(self) -> int:
        """Number of rigid-body (zero-frequency) modes."""
        return self.rigid_body_shapes.shape[1]

    @property
    def disk_names(self) -> tuple[str, ...]:
        """The rows of :attr:`shapes`: the disks, then the nodes inside divided shafts."""
        return self.drivetrain.dof_names

    @property
    def coordinate_names(self) -> tuple[str, ...]:
        """The disks (and shaft nodes): :attr:`shapes` has one row per degree of freedom."""
        return self.drivetrain.dof_names

    def coordinate_mass(self) -> Any:
        """The mass matrix over every degree of freedom, kg·m²: (n_dofs,) its diagonal where it is
        diagonal (the disks' inertias, plus lumped shaft inertia), else the sparse (n_dofs, n_dofs) M."""
        if not self.assembly.diagonal_mass:
            return self.assembly.M_full
        dt = self.drivetrain
        if len(dt.dof_names) == len(dt.disks) and not any(getattr(e, "inertia", 0.0) for e in dt.elements):
            return dt.inertias
        return self.assembly.M_full.diagonal()

    @cached_property
    def unit_shapes(self) -> np.ndarray:
        """Mode shapes scaled to a largest disk angle of +1."""
        return _unit_shapes(self.shapes)

    @cached_property
    def strain_energy(self) -> tuple[tuple[str, ...], np.ndarray]:
        """Share of each stiff element in each mode's strain energy.

        Returns
        -------
        names : tuple of str
            Elements with a stiffness (shafts, flexible meshes, grounded springs).
        share : ndarray
            (n_elements, n_modes), columns sum to 1.
        """
        dt = self.drivetrain
        positions, parts = [], []
        for g in dt.block_groups("stiffness"):
            phi = self.shapes[g.dofs]  # (m, k, n_modes)
            parts.append(
                0.5 * np.einsum("eia,eij,eja->ea", phi, g.blocks, phi)
            )  # ½ φᵀ K_e φ per element e, mode a
            positions.append(g.elements)
        order = np.argsort(np.concatenate(positions)) if positions else np.zeros(0, dtype=int)
        energy = np.concatenate(parts)[order] if parts else np.zeros((0, self.shapes.shape[1]))
        names = [dt.element_blocks[p][0].name for p in np.concatenate(positions)[order]] if positions else []
        total = energy.sum(axis=0)
        return tuple(names), energy / np.where(total == 0, 1.0, total)

    def dominant_element(self, mode: int) -> tuple[str, float]:
        """The element holding the largest share of strain energy in flexible mode ``mode`` (0-based).

        Parameters
        ----------
        mode : int
            Index of the flexible mode, 0 for the lowest.

        Returns
        -------
        tuple of (str, float)
            The element's name and its share of the mode's strain energy, a fraction.
        """
        names, share = self.strain_energy
        i = int(np.argmax(share[:, mode]))
        return names[i], float(share[i, mode])

    @property
    def label(self) -> str:
        """``"rigid gears"`` or ``"as modelled"``, for titles."""
        return "rigid gears" if self.rigid_gears else "as modelled"

    def summary(self) -> dict[str, Any]:
        """Frequencies (Hz), rigid-body mode count, solver, and each mode's shape and owner."""
        modes = []
        for m, f in enumerate(self.frequencies_hz):
            el, share = self.dominant_element(m)
            modes.append(
                {
                    "mode": m + 1,
                    "frequency_hz": float(f),
                    "dominant_element": el,
                    "dominant_element_share": share,
                    "shape": dict(zip(self.disk_names, self.unit_shapes[:, m].tolist(), strict=True)),
                }
            )
        return {
            "frequencies_hz": self.frequencies_hz.tolist(),
            "rigid_body_modes": self.rigid_body_modes,
            "rigid_gears": self.rigid_gears,
            "solver": self.solver,
            "modes": modes,
        }

    def tables(self, **display_units: str) -> list[Table]:
        """Frequencies with the owning element and disk; shapes, strain energy, rigid-body modes; the
        model as assembled."""
        title = self.label
        names, share = self.strain_energy
        rows = []
        for m, f in enumerate(self.frequencies_hz):
            el, es = self.dominant_element(m)
            d = int(np.argmax(self.kinetic_energy[:, m]))
            rows.append([m + 1, f, el, 100 * es, self.disk_names[d], 100 * self.kinetic_energy[d, m]])
        tables = [
            Table(
                f"{title}: natural frequencies ({self.rigid_body_modes} rigid-body mode(s) set aside)",
                [
                    "mode",
                    "frequency [Hz]",
                    "most strain energy in",
                    "share [%]",
                    "most kinetic energy in",
                    "share [%]",
                ],
                rows,
            )
        ]
        modes = range(len(self.omega))
        if modes:  # a model that only turns as a rigid body has no shapes or strain energy to show
            tables.append(
                Table(
                    f"{title}: mode shapes (largest disk angle = 1)",
                    ["disk", *[f"mode {m + 1}" for m in modes]],
                    [[d, *self.unit_shapes[i].tolist()] for i, d in enumerate(self.disk_names)],
                )
            )
            tables.append(
                Table(
                    f"{title}: strain energy per element [%]",
                    ["element", *[f"mode {m + 1}" for m in modes]],
                    [[n, *(100 * share[i]).tolist()] for i, n in enumerate(names)],
                )
            )
        if self.rigid_body_modes:
            tables.append(
                Table(
                    f"{title}: rigid-body modes (0 Hz)",
                    ["disk", *[f"rigid {k + 1}" for k in range(self.rigid_body_modes)]],
                    [[d, *self.rigid_body_shapes[i].tolist()] for i, d in enumerate(self.disk_names)],
                )
            )
        from mechdyn.drivetrain.summary import model_table

        return [*tables, model_table(self.drivetrain)]

    def plots(self, **display_units: str) -> dict[str, Any]:
        """``mode_shapes.png``."""
        from mechdyn.drivetrain.plots import plot_mode_shapes

        return {"mode_shapes.png": lambda: plot_mode_shapes(self)}

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        """Natural frequencies (Hz) and mass-normalised shapes of every disk (rad)."""
        return {"frequencies_hz": (self.frequencies_hz, "Hz"), "mode_shapes": (self.shapes, "rad")}

    def to_frame(self) -> pd.DataFrame:
        """One row per flexible mode: frequency, and the element and disk that dominate it."""
        import pandas as pd

        rows = []
        for m, f in enumerate(self.frequencies_hz):
            el, es = self.dominant_element(m)
            d = int(np.argmax(self.kinetic_energy[:, m]))
            rows.append(
                {
                    "mode": m + 1,
                    "frequency_hz": f,
                    "strain_energy_element": el,
                    "strain_energy_share_relative": es,
                    "kinetic_energy_disk": self.disk_names[d],
                    "kinetic_energy_share_relative": float(self.kinetic_energy[d, m]),
                }
            )
        return pd.DataFrame(rows)

    def shapes_frame(self) -> pd.DataFrame:
        """Unit-scaled mode shapes: one row per disk, one column per flexible mode (Hz in the name)."""
        import pandas as pd

        cols = {
            f"mode {m + 1} ({f:.4g} Hz)": self.unit_shapes[:, m] for m, f in enumerate(self.frequencies_hz)
        }
        return pd.DataFrame(cols, index=pd.Index(self.disk_names, name="disk"))

    def energy_frame(self) -> pd.DataFrame:
        """Strain-energy share (%) of every stiff element, one column per flexible mode."""
        import pandas as pd

        names, share = self.strain_energy
        cols = {f"mode {m + 1}": 100 * share[:, m] for m in range(share.shape[1])}
        return pd.DataFrame(cols, index=pd.Index(names, name="element"))

    def plot(self, modes: Any = None, ax: Any = None, **display_units: str) -> Any:
        """Plot unit-scaled mode shapes against disk; returns the matplotlib Figure.

        Parameters
        ----------
        modes : sequence of int, optional
            Flexible modes to draw, 0-based (default: all).
        ax : matplotlib.axes.Axes, optional
            Axes to draw on (default: a new figure).
        **display_units : str
            Display units (unused: the shapes are normalised).
        """
        from mechdyn.drivetrain.plots import plot_mode_shapes

        return plot_mode_shapes(self, modes=modes, ax=ax)


def modal(
    model: Drivetrain | Assembly,
    *,
    n_modes: int | None = None,
    solver: Solver = "auto",
    rigid_gears: bool = False,
) -> ModalResult:
    """Undamped natural frequencies and mode shapes of a drivetrain.

    Parameters
    ----------
    model : Drivetrain or Assembly
    n_modes : int, optional
        Number of lowest flexible modes; all when None.
    solver : {"auto", "dense", "banded", "sparse"}
        Eigen solver, see :func:`mechdyn.vibration.solve_eigen`.
    rigid_gears : bool
        Treat every gear mesh as a rigid constraint (:meth:`Drivetrain.with_rigid_gears`).

    Returns
    -------
    ModalResult

    Notes
    -----
    Solves K q = ω² M q on the coordinates left after the rigid-mesh reduction θ = T q (e.g.
    Friswell et al., *Dynamics of Rotating Machines*, 2010, ch. 9). With a diagonal M (disks, lumped
    shafts) the fast and accurate paths of :func:`mechdyn.vibration.solve_eigen` run on its diagonal;
    a consistent shaft inertia makes M a band matrix, solved as the generalised symmetric problem.
    The rigid-body modes are the exact rigid motions of the free branches; their number is checked
    against K during assembly, so the lowest that many eigenpairs are the zero modes and are set aside.

    With a diagonal M, every flexible frequency is accurate to 1e-6 (relative) however widely the
    inertias and stiffnesses spread: where the fast solvers' error estimate cannot promise that, the
    frequencies are recomputed from the springs' factor (:func:`stiffness_factor`) to high relative
    accuracy (:func:`mechdyn.vibration.solve_eigen`, whose ``used`` then shows as
    :attr:`ModalResult.solver` ``"bidiagonal"`` or ``"jacobi"``), or a
    :class:`~mechdyn.errors.ModelWarning` gives the condition estimate. With a consistent M the
    generalised solve is backward stable and the same error estimate warns where it cannot promise that.

    Examples
    --------
    Two disks on a shaft: one rigid-body mode, and f = √(k (1/J₁ + 1/J₂))/(2π).

    >>> from mechdyn.drivetrain import Disk, Drivetrain, Shaft, modal
    >>> pair = Drivetrain(
    ...     [Disk("a", "1 kg*m^2"), Disk("b", "2 kg*m^2")], [Shaft("s", ("a", "b"), "1000 N*m/rad")]
    ... )
    >>> modes = modal(pair)
    >>> modes.frequencies_hz.round(4), modes.rigid_body_shapes.shape[1]
    (array([6.164]), 1)
    """
    if isinstance(model, Drivetrain):
        asm = (model.with_rigid_gears() if rigid_gears else model).assembly
    else:
        asm = model.drivetrain.with_rigid_gears().assembly if rigid_gears else model
    n_rb = asm.n_rigid_body
    if n_modes is not None:
        n_modes = check_count("modal", "n_modes", n_modes, high=10**9, what="modes")
    want = None if n_modes is None else n_rb + n_modes
    small = None
    if (want is None or want >= asm.n) and solver in ("auto", "dense") and asm.n > n_rb:
        small = _small_dense(asm, n_rb)
    if small is not None:
        lam, Q, used = small
    elif asm.n == n_rb:
        lam, Q, used = np.zeros(0), np.zeros((asm.n, 0)), "none"
    else:
        # the factor is built only if the fast eigen paths' error estimate calls for the accurate ones;
        # the matrices were checked finite where the model entered (its elements), not again here
        mass = asm.mass_diagonal if asm.mass_diagonal is not None else asm.M
        lam, Q, used = solve_eigen(
            asm.stiffness_operator,
            mass,
            n_modes=want,
            solver=solver,
            factor=lambda: stiffness_factor(asm),
            n_rigid=n_rb,
            check_finite=False,
        )
    lam, Q = lam[n_rb:], Q[:, n_rb:]
    omega = np.sqrt(np.clip(lam, 0.0, None))
    shapes = np.asarray(asm.T @ Q) if asm.T.shape[0] != asm.T.shape[1] else Q  # T = I without rigid meshes
    return ModalResult(asm, omega, shapes, asm.rigid_body_unit_shapes, used, Q, rigid_gears)
