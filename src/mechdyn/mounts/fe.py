"""Axisymmetric linear-elastic finite elements (scikit-fem) as the reference for mount estimates.

Displacements (u_r, u_z) on the (r, z) half-plane; strains ε_rr = ∂u_r/∂r, ε_zz = ∂u_z/∂z,
ε_θθ = u_r/r, γ_rz = ∂u_r/∂z + ∂u_z/∂r; the energy ∫ (λ (tr ε)² + 2μ ε:ε) 2πr dr dz (e.g. Zienkiewicz
& Taylor, *The Finite Element Method*, vol. 1, ch. 5 "axisymmetric stress analysis"). Quadratic
triangles (P2) by default, which a nearly incompressible rubber needs.

Two models:

- :func:`pad_compression`: a disc pad between rigid plates, bonded (the faces cannot slide) or
  lubricated (a free bar: k = EA/h, which the elements reproduce to round-off).
- :func:`anchor_members`: the members clamped by an anchor bolt — a steel base plate on concrete,
  squeezed between the bolt head's washer on top and the anchor's embedded head below — with
  unilateral, frictionless contact between plate and concrete (active set: a node pair is tied where
  it presses and released where it would pull). Gives the members' stiffness (work-conjugate
  approach of the two bearing faces) and the contact pressure at the interface.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from mechdyn.errors import ModelError

__all__ = [
    "AnchorFE",
    "Extrapolation",
    "FEResult",
    "anchor_members",
    "pad_compression",
    "richardson",
]


def _lame(E: float, nu: float) -> tuple[float, float]:
    if not -1 < nu < 0.5:
        raise ModelError(f"ν = {nu:g} must lie between −1 and 0.5", element="fe", field="poissons_ratio")
    if not E > 0:
        raise ModelError(f"E = {E:g} Pa must be positive", element="fe", field="youngs_modulus")
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


def _stiffness(basis: Any, E: float, nu: float) -> sp.csr_matrix:
    from skfem import BilinearForm, asm

    lam, mu = _lame(E, nu)

    @BilinearForm
    def form(u, v, w):
        r = w.x[0]
        eu = (u.grad[0][0], u.grad[1][1], u[0] / r, u.grad[0][1] + u.grad[1][0])
        ev = (v.grad[0][0], v.grad[1][1], v[0] / r, v.grad[0][1] + v.grad[1][0])
        tr = (eu[0] + eu[1] + eu[2]) * (ev[0] + ev[1] + ev[2])
        dev = eu[0] * ev[0] + eu[1] * ev[1] + eu[2] * ev[2] + 0.5 * eu[3] * ev[3]
        return 2 * np.pi * r * (lam * tr + 2 * mu * dev)

    return asm(form, basis).tocsr()


def _element(order: int) -> Any:
    from skfem import ElementTriP1, ElementTriP2, ElementVector

    if order not in (1, 2):
        raise ModelError(f"order {order} must be 1 or 2", element="fe", field="order")
    return ElementVector(ElementTriP2() if order == 2 else ElementTriP1())


def _solve(K: sp.csr_matrix, f: np.ndarray, fixed: np.ndarray, values: np.ndarray) -> np.ndarray:
    """K u = f with u[fixed] = values (the rest free)."""
    n = K.shape[0]
    u = np.zeros(n)
    u[fixed] = values
    free = np.setdiff1d(np.arange(n), fixed)
    rhs = f[free] - K[free][:, fixed] @ values
    u[free] = spla.spsolve(K[free][:, free].tocsc(), rhs)
    return u


@dataclass(frozen=True)
class FEResult:
    """A stiffness from the finite elements, with the mesh it came from.

    Attributes
    ----------
    stiffness : float
        N/m.
    elements, dofs : int
    element_size : float
        The characteristic element size, m.
    order : int
        1 (linear) or 2 (quadratic) triangles.
    extra : dict
        Further figures of the model (e.g. the contact state), SI, keyed with their units.
    """

    stiffness: float
    elements: int
    dofs: int
    element_size: float
    order: int
    extra: dict[str, Any] = field(default_factory=dict)


def pad_compression(
    diameter: float,
    thickness: float,
    youngs_modulus: float,
    poissons_ratio: float,
    *,
    bonded: bool = True,
    n: int = 8,
    order: int = 2,
) -> FEResult:
    """Compression stiffness of a disc pad between rigid plates, by axisymmetric FE.

    Parameters
    ----------
    diameter, thickness : float
        m.
    youngs_modulus : float
        Pa.
    poissons_ratio : float
        ν < 0.5 (rubber: ν = 0.5 − E/(6B) from its bulk modulus).
    bonded : bool
        Faces bonded to the plates (no radial slip) or free to slide (a bar in uniaxial stress).
    n : int
        Elements through the thickness (square elements; more near the free edge where the bulge
        concentrates the strain).
    order : int
        Polynomial order of the triangles.
    """
    from skfem import Basis, MeshTri

    if not (diameter > 0 and thickness > 0):
        raise ModelError("diameter and thickness must be positive", element="fe", field="thickness")
    a, h = diameter / 2, thickness
    nr = max(2, math.ceil(n * a / h))
    # finer towards the free edge r = a, where a bonded pad bulges
    s = np.linspace(0.0, 1.0, nr + 1)
    r = a * (1 - (1 - s) ** 1.5) if bonded else a * s
    z = h * np.linspace(0.0, 1.0, n + 1)
    mesh = MeshTri.init_tensor(r, z)
    basis = Basis(mesh, _element(order))
    K = _stiffness(basis, youngs_modulus, poissons_ratio)
    bottom = basis.get_dofs(lambda x: np.isclose(x[1], 0.0))
    top = basis.get_dofs(lambda x: np.isclose(x[1], h))
    axis = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all("u^1")
    delta = 1e-3 * h
    fixed_z = np.concatenate([bottom.all("u^2"), top.all("u^2")])
    vals = np.concatenate([np.zeros(bottom.all("u^2").size), -delta * np.ones(top.all("u^2").size)])
    if bonded:
        fixed_r = np.unique(np.concatenate([bottom.all("u^1"), top.all("u^1"), axis]))
    else:
        fixed_r = axis
    fixed = np.concatenate([fixed_z, fixed_r])
    values = np.concatenate([vals, np.zeros(fixed_r.size)])
    fixed, idx = np.unique(fixed, return_index=True)
    u = _solve(K, np.zeros(basis.N), fixed, values[idx])
    force = -(K @ u)[top.all("u^2")].sum()
    return FEResult(float(force / delta), mesh.nelements, basis.N, float(h / n), order)


@dataclass(frozen=True)
class AnchorFE:
    """The members of an anchor-bolt joint by FE: stiffness and the plate–concrete contact pressure.

    Attributes
    ----------
    stiffness : float
        Members' stiffness F/δ, N/m (δ: the work-conjugate approach of the two bearing faces).
    contact_radius : ndarray
        (m,) radii of the interface nodes, m.
    contact_pressure : ndarray
        (m,) contact pressure at the interface per newton of preload, Pa/N (zero where the plate
        lifts); scale by the preload.
    head_pressure : float
        Mean pressure under the washer per newton of preload, Pa/N.
    lift_off_radius : float
        Where the plate leaves the concrete, m (the outer edge when it does not).
    result : FEResult
    """

    stiffness: float
    contact_radius: np.ndarray
    contact_pressure: np.ndarray
    head_pressure: float
    lift_off_radius: float
    result: FEResult

    def pressure(self, preload: float) -> np.ndarray:
        """Contact pressure under a preload (N), Pa.

        Parameters
        ----------
        preload : float
            The bolt's preload, N (the model is linear between contact changes: pressures scale).
        """
        return self.contact_pressure * preload

    def radius_above(self, threshold: float, preload: float) -> float:
        """Outermost radius where the contact pressure exceeds ``threshold`` (Pa) under ``preload`` (N), m.

        Parameters
        ----------
        threshold : float
            Contact pressure to compare with, Pa.
        preload : float
            The bolt's preload, N.
        """
        p = self.pressure(preload)
        above = np.nonzero(p > threshold)[0]
        return float(self.contact_radius[above.max()]) if above.size else 0.0


def _graded(r0: float, r1: float, h0: float, growth: float = 1.12) -> np.ndarray:
    """Nodes from r0 to r1 starting at spacing h0 and growing geometrically (capped at 8 h0)."""
    nodes = [r0]
    step = h0
    while nodes[-1] + step < r1 - 0.5 * step:
        nodes.append(nodes[-1] + step)
        step = min(step * growth, 8 * h0)
    nodes.append(r1)
    return np.array(nodes)


def anchor_members(
    *,
    plate_thickness: float,
    plate_radius: float,
    embedment: float,
    concrete_radius: float,
    hole_diameter: float,
    washer_diameter: float,
    anchor_head_diameter: float,
    plate_E: float,
    plate_nu: float,
    concrete_E: float,
    concrete_nu: float,
    n: int = 8,
    max_iterations: int = 50,
) -> AnchorFE:
    """Members of an anchor-bolt joint under preload, with unilateral plate–concrete contact.

    The base plate (r from the hole to ``plate_radius``, thickness ``plate_thickness``) lies on the
    concrete (r from the hole to ``concrete_radius``, down to the anchor's embedded head at depth
    ``embedment``). The preload presses the plate down under the washer and pulls the concrete up
    over the anchor head's bearing annulus. All lengths m, moduli Pa. ``n`` elements through the
    plate's thickness set the mesh (graded away from the bolt); linear triangles, so that the
    interface is a set of node pairs.

    Parameters
    ----------
    plate_thickness, plate_radius : float
        The base plate's thickness and outer radius, m.
    embedment : float
        Depth of the anchor's head below the concrete's surface, m.
    concrete_radius : float
        Outer radius of the modelled concrete block, m.
    hole_diameter : float
        Diameter of the bolt's hole through plate and concrete, m.
    washer_diameter : float
        Bearing diameter of the washer on the plate, m.
    anchor_head_diameter : float
        Bearing diameter of the anchor's head in the concrete, m.
    plate_E, concrete_E : float
        Young's moduli, Pa.
    plate_nu, concrete_nu : float
        Poisson's ratios, dimensionless.
    n : int
        Elements through the plate's thickness.
    max_iterations : int
        Most active-set iterations for the contact.
    """
    from skfem import Basis, FacetBasis, LinearForm, MeshTri, asm

    dims = dict(
        plate_thickness=plate_thickness,
        plate_radius=plate_radius,
        embedment=embedment,
        concrete_radius=concrete_radius,
        hole_diameter=hole_diameter,
        washer_diameter=washer_diameter,
        anchor_head_diameter=anchor_head_diameter,
    )
    for k, v in dims.items():
        if not v > 0:
            raise ModelError(f"{v:g} m must be positive", element="anchor", field=k)
    rh = hole_diameter / 2
    rw, ra = washer_diameter / 2, anchor_head_diameter / 2
    if rw <= rh or ra <= rh:
        raise ModelError(
            "the washer and the anchor head must be wider than the hole",
            element="anchor",
            field="washer_diameter",
        )
    if not rw < plate_radius <= concrete_radius:
        raise ModelError(
            "need washer radius < plate radius ≤ concrete radius", element="anchor", field="plate_radius"
        )
    h0 = plate_thickness / n
    grid = _graded(rh, concrete_radius, h0 / 2)
    special = np.array(sorted({rw, ra, plate_radius}))  # loaded edges and the plate's edge fall on nodes
    spacing = np.interp(special, grid[1:], np.diff(grid))
    near = np.any(np.abs(grid[:, None] - special[None]) < 0.5 * spacing[None], axis=1)
    near[[0, -1]] = False
    r_all = np.union1d(grid[~near], special)
    r_plate = r_all[r_all <= plate_radius + 1e-12]
    z_plate = np.linspace(0.0, plate_thickness, n + 1)
    nc = max(2, math.ceil(embedment / h0))
    z_conc = np.linspace(-embedment, 0.0, nc + 1)
    order = 1
    elem = _element(order)
    plate = Basis(MeshTri.init_tensor(r_plate, z_plate), elem)
    conc = Basis(MeshTri.init_tensor(r_all, z_conc), elem)
    Kp = _stiffness(plate, plate_E, plate_nu)
    Kc = _stiffness(conc, concrete_E, concrete_nu)
    Np = plate.N
    K = sp.block_diag([Kp, Kc]).tocsr()

    def pressure_load(basis: Any, z0: float, r0: float, r1: float, sign: float) -> np.ndarray:
        mesh = basis.mesh
        facets = mesh.facets_satisfying(
            lambda x: np.isclose(x[1], z0) & (x[0] >= r0 - 1e-12) & (x[0] <= r1 + 1e-12), boundaries_only=True
        )
        fb = FacetBasis(mesh, elem, facets=facets)
        p = sign / (math.pi * (r1**2 - r0**2))  # unit total force

        @LinearForm
        def load(v, w):
            return p * v[1] * 2 * np.pi * w.x[0]

        return asm(load, fb)

    f = np.zeros(K.shape[0])
    f_head = pressure_load(plate, plate_thickness, rh, rw, -1.0)  # down on the plate
    f_anchor = pressure_load(conc, -embedment, rh, ra, +1.0)  # up on the concrete
    f[:Np] += f_head
    f[Np:] += f_anchor
    # the interface node pairs, plate (z = 0) over concrete (z = 0), by radius
    pdofs = plate.get_dofs(lambda x: np.isclose(x[1], 0.0)).nodal["u^2"]
    cdofs_all = conc.get_dofs(lambda x: np.isclose(x[1], 0.0)).nodal["u^2"]
    pr = plate.doflocs[0, pdofs]
    cr = conc.doflocs[0, cdofs_all]
    order_p, order_c = np.argsort(pr), np.argsort(cr)
    pdofs, pr = pdofs[order_p], pr[order_p]
    cdofs_all, cr = cdofs_all[order_c], cr[order_c]
    match = np.searchsorted(cr, pr)
    if not np.allclose(cr[match], pr, atol=1e-9 * plate_radius):
        raise ModelError("interface nodes do not match", element="anchor", field="mesh")
    cdofs = cdofs_all[match] + Np
    # one vertical rigid motion of the concrete is held at its outer bottom corner (the loads balance)
    corner = conc.get_dofs(lambda x: np.isclose(x[0], concrete_radius) & np.isclose(x[1], -embedment)).nodal[
        "u^2"
    ]
    fixed = corner + Np
    active = np.ones(pdofs.size, dtype=bool)
    for _ in range(max_iterations):
        # tie the active pairs: the concrete dof follows the plate's
        n_all = K.shape[0]
        keep = np.ones(n_all, dtype=bool)
        keep[cdofs[active]] = False
        cols = np.cumsum(keep) - 1
        rows = np.arange(n_all)
        target = np.where(keep, cols, 0)
        target[cdofs[active]] = cols[pdofs[active]]
        T = sp.csr_matrix((np.ones(n_all), (rows, target)), shape=(n_all, int(keep.sum())))
        Kr = (T.T @ K @ T).tocsr()
        fr = T.T @ f
        fixed_r = cols[fixed]
        ur = _solve(Kr, fr, fixed_r, np.zeros(fixed_r.size))
        u = T @ ur
        # the force the concrete puts on the plate at each tied node: K u − f on the plate's side
        reaction = (K @ u - f)[pdofs]
        contact = np.where(active, reaction, 0.0)  # > 0: the concrete pushes the plate up
        gap = u[pdofs] - u[cdofs]
        new = np.where(active, contact > 0, gap < 0)
        if np.array_equal(new, active):
            break
        active = new
    else:
        raise ModelError("the contact iterations did not settle", element="anchor", field="mesh")
    # tributary annulus of each interface node: half-way to its neighbours
    edges = np.concatenate([[pr[0]], 0.5 * (pr[1:] + pr[:-1]), [pr[-1]]])
    area = np.pi * (edges[1:] ** 2 - edges[:-1] ** 2)
    pressure = np.where(active, contact / area, 0.0)
    compliance = float(f @ u)  # unit force: the work-conjugate approach of the two faces
    lifted = np.nonzero(~active)[0]
    lift = float(pr[lifted.min()]) if lifted.size else float(plate_radius)
    res = FEResult(
        1.0 / compliance,
        plate.mesh.nelements + conc.mesh.nelements,
        K.shape[0],
        h0,
        order,
        {"contact_iterations": _ + 1},
    )
    head = 1.0 / (math.pi * (rw**2 - rh**2))
    return AnchorFE(1.0 / compliance, pr, pressure, head, lift, res)


@dataclass(frozen=True)
class Extrapolation:
    """A mesh-converged value from a sequence of refinements by a constant ratio.

    Attributes
    ----------
    value : float
        The extrapolated (converged) value.
    order : float or None
        The observed order of convergence p (None when the last three levels do not converge
        monotonically).
    error : float
        Estimated relative discretisation error of the finest mesh, |finest − value| / |value|.
    """

    value: float
    order: float | None
    error: float


def richardson(values: Any, ratio: float = 2.0) -> Extrapolation:
    """Richardson extrapolation of the last three values of a refinement sequence.

    With f_h = f + C h^p and the mesh refined by ``ratio`` between levels, the observed order is
    p = ln((f₁ − f₂)/(f₂ − f₃)) / ln r and the converged value f = f₃ + (f₃ − f₂)/(r^p − 1)
    (Roache, *Verification and Validation in Computational Science and Engineering*, 1998, §5.4;
    the grid convergence index of ASME V&V 20). With fewer than three levels, or a sequence that
    does not converge monotonically, the value is the finest one and the error the last change.

    Parameters
    ----------
    values : sequence of float
        The quantity on meshes refined by ``ratio`` each time, coarsest first.
    ratio : float
        Refinement ratio between levels.
    """
    f = [float(v) for v in values]
    if len(f) < 2:
        return Extrapolation(f[-1], None, math.inf)
    if len(f) >= 3:
        d1, d2 = f[-3] - f[-2], f[-2] - f[-1]
        if d1 * d2 > 0 and abs(d2) < abs(d1):
            p = math.log(d1 / d2) / math.log(ratio)
            value = f[-1] + (f[-1] - f[-2]) / (ratio**p - 1.0)
            return Extrapolation(value, p, abs(f[-1] - value) / abs(value))
    return Extrapolation(f[-1], None, abs(f[-1] - f[-2]) / abs(f[-1]))
