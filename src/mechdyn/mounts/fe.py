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

from mechdyn.checks import check_count, check_number
from mechdyn.errors import ModelError
from mechdyn.units import check_poisson_ratio

MAX_ELEMENTS = 2_000_000
"""The most triangles a finite-element model may have (a few minutes of solving); a finer mesh, or a
geometry of extreme proportions (a 1 km block under a 1 µm plate), is refused before it is built."""
MAX_REFINEMENT = 1024
"""The most elements through the thickness (as a mount file's ``fe.refinements``)."""

__all__ = [
    "MAX_ELEMENTS",
    "MAX_REFINEMENT",
    "AnchorFE",
    "Extrapolation",
    "FEResult",
    "anchor_members",
    "pad_compression",
    "richardson",
]


def _lame(E: float, nu: float) -> tuple[float, float]:
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


def _too_many(owner: str, elements: float, n: int) -> None:
    """Refuse a mesh of more than :data:`MAX_ELEMENTS` triangles before it is built."""
    if elements > MAX_ELEMENTS:
        raise ModelError(
            f"n = {n} elements through the thickness gives a mesh of about {elements:.3g} triangles for this "
            f"geometry, more than {MAX_ELEMENTS:.0e}: give a smaller n, or check the dimensions (their "
            "proportions set the mesh)",
            element=owner,
            field="n",
        )


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

    diameter = check_number("fe", "diameter", diameter, "m", positive=True)
    thickness = check_number("fe", "thickness", thickness, "m", positive=True)
    youngs_modulus = check_number("fe", "youngs_modulus", youngs_modulus, "Pa", positive=True)
    poissons_ratio = check_poisson_ratio("fe", "poissons_ratio", poissons_ratio)
    n = check_count("fe", "n", n, high=MAX_REFINEMENT, what="elements through the thickness")
    a, h = diameter / 2, thickness
    _too_many("fe", 2.0 * max(2.0, n * a / h) * n, n)
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
            The bolt's preload, N, from 0 to 1e11 N (the model is linear between contact changes:
            pressures scale).
        """
        return self.contact_pressure * check_number("anchor", "preload", preload, "N", nonnegative=True)

    def radius_above(self, threshold: float, preload: float) -> float:
        """Outermost radius where the contact pressure exceeds ``threshold`` (Pa) under ``preload`` (N), m.

        Parameters
        ----------
        threshold : float
            Contact pressure to compare with, Pa.
        preload : float
            The bolt's preload, N.
        """
        threshold = check_number("anchor", "threshold", threshold, "Pa", nonnegative=True, what="pressure")
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


def _bisected(nodes: np.ndarray, times: int) -> np.ndarray:
    """The nodes with every interval halved ``times`` times."""
    for _ in range(times):
        nodes = np.sort(np.concatenate([nodes, 0.5 * (nodes[1:] + nodes[:-1])]))
    return nodes


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
    plate's thickness set the mesh: graded away from the bolt on the coarsest mesh of its family
    (n / 2^k ≥ 4), whose every element is bisected k times, so that the meshes for n and 2n are
    nested and refined by exactly 2 everywhere, as Richardson extrapolation assumes. Linear
    triangles, so that the interface is a set of node pairs: the stiffness (an energy) converges
    with order 2 at most (:func:`richardson`).

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
    for name, value in dims.items():
        dims[name] = check_number("anchor", name, value, "m", positive=True)
    plate_thickness, plate_radius, embedment, concrete_radius = (
        dims[name] for name in ("plate_thickness", "plate_radius", "embedment", "concrete_radius")
    )
    hole_diameter, washer_diameter, anchor_head_diameter = (
        dims[name] for name in ("hole_diameter", "washer_diameter", "anchor_head_diameter")
    )
    plate_E = check_number("anchor", "plate_E", plate_E, "Pa", positive=True, what="Young's modulus")
    concrete_E = check_number("anchor", "concrete_E", concrete_E, "Pa", positive=True, what="Young's modulus")
    plate_nu = check_poisson_ratio("anchor", "plate_nu", plate_nu)
    concrete_nu = check_poisson_ratio("anchor", "concrete_nu", concrete_nu)
    n = check_count("anchor", "n", n, high=MAX_REFINEMENT, what="elements through the plate")
    max_iterations = check_count("anchor", "max_iterations", max_iterations, high=10_000, what="iterations")
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
    # the meshes of one family are nested: the coarsest (n0 = n / 2^k ≥ 4 elements through the plate)
    # is graded away from the bolt, and each finer one bisects every element of the one before, so that
    # successive meshes refine by exactly 2 everywhere (the self-similar sequence Richardson assumes)
    n0, k = n, 0
    while n0 % 2 == 0 and n0 // 2 >= 4:
        n0, k = n0 // 2, k + 1
    h_base = plate_thickness / n0
    # the mesh before it is built: radial nodes at spacings up to 8 × h_base/2, bisected k times
    radial = ((concrete_radius - rh) / (4 * h_base) + 40) * 2**k
    _too_many("anchor", 2 * radial * (n + max(2.0, embedment / h_base) * 2**k), n)
    grid = _graded(rh, concrete_radius, h_base / 2)
    special = np.array(sorted({rw, ra, plate_radius}))  # loaded edges and the plate's edge fall on nodes
    spacing = np.interp(special, grid[1:], np.diff(grid))
    near = np.any(np.abs(grid[:, None] - special[None]) < 0.5 * spacing[None], axis=1)
    near[[0, -1]] = False
    r_all = _bisected(np.union1d(grid[~near], special), k)
    r_plate = r_all[r_all <= plate_radius + 1e-12]
    h0 = plate_thickness / n
    z_plate = np.linspace(0.0, plate_thickness, n + 1)
    nc = max(2, math.ceil(embedment / h_base)) * 2**k
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
    """A mesh-converged value from a sequence of refinements by a constant ratio, with its error.

    Attributes
    ----------
    value : float
        The extrapolated (converged) value; the finest mesh's value when the last three meshes give
        no admissible order.
    order : float or None
        The observed order p of the last three meshes (None when they do not converge
        monotonically).
    error : float
        Relative error estimate of ``value``. When ``verified``, the change between the last two
        extrapolations, |E_k − E_(k−1)| / |E_k| (a bound in the asymptotic range; see
        :func:`richardson`). Otherwise the finest mesh's own error (one extrapolation) or the last
        change between meshes (no admissible order), which bounds nothing.
    finest_error : float
        Relative error of the finest mesh against ``value``, |f_finest − value| / |value|.
    verified : bool
        Whether the last two extrapolations both rest on an admissible order, so that ``error`` is
        their agreement.
    orders : tuple of float or None
        The observed order of each three successive meshes (from the third mesh on).
    extrapolations : tuple of float or None
        The extrapolated value from each three successive meshes; None where the order is not
        admissible.
    note : str
        Why the estimate is not verified (empty when it is).
    """

    value: float
    order: float | None
    error: float
    finest_error: float = math.inf
    verified: bool = False
    orders: tuple[float | None, ...] = ()
    extrapolations: tuple[float | None, ...] = ()
    note: str = ""


def _observed_order(f1: float, f2: float, f3: float, ratio: float) -> float | None:
    """p = ln((f₁ − f₂)/(f₂ − f₃)) / ln r, or None when the three do not converge monotonically."""
    d1, d2 = f1 - f2, f2 - f3
    if d1 * d2 > 0:
        return math.log(d1 / d2) / math.log(ratio)
    return None


def richardson(
    values: Any,
    ratio: float = 2.0,
    *,
    expected_order: float = 2.0,
    lowest_order: float = 1.0,
) -> Extrapolation:
    """Richardson extrapolation of a refinement sequence, checked against the theoretical order.

    With f_h = f + C h^p and the mesh refined by ``ratio`` between levels, three successive values
    give the observed order p = ln((f₁ − f₂)/(f₂ − f₃)) / ln r and the extrapolated value
    E = f₃ + (f₃ − f₂)/(r^p − 1) (Roache, *Verification and Validation in Computational Science and
    Engineering*, 1998, §5.4; ASME V&V 20-2009, §2-4). The extrapolation holds only in the
    asymptotic range, where p is the method's order for the quantity: an observed order outside
    [``lowest_order``, 1.1 ``expected_order``] is not admitted (a p near zero would extrapolate
    far beyond the data; Eča & Hoekstra, *J. Comput. Phys.* 262, 2014, 104–130, reject such orders
    in the same way). Each three successive values give one extrapolation; when the last two are
    both admitted, the value is the last one and its error the change between them,
    |E_k − E_(k−1)| / |E_k| — an upper bound while the extrapolations' own error falls by at least 2
    per refinement, which the next term of the expansion (a higher power of h) gives in the
    asymptotic range. With one admitted extrapolation the error is that of the finest mesh
    (unverified); with none, the value is the finest mesh's and the error the last change (no bound).

    For a stiffness (an energy) from elements of degree k the theoretical order is 2k on a smooth
    solution; a corner singularity u ~ r^λ lowers it to 2λ on uniformly refined meshes (Strang &
    Fix, *An Analysis of the Finite Element Method*, 1973, §8.2), and λ ≥ 1/2 in a 2-D elastic body
    (the crack, Williams, *J. Appl. Mech.* 19, 1952, 526–528): hence ``lowest_order`` = 1.

    Parameters
    ----------
    values : sequence of float
        The quantity on meshes refined by ``ratio`` each time, coarsest first.
    ratio : float
        Refinement ratio between levels.
    expected_order : float
        The theoretical order of the quantity's convergence (2 for a stiffness from linear
        elements, 4 from quadratic ones).
    lowest_order : float
        The lowest order admitted (what the strongest singularity of the problem allows).

    Returns
    -------
    Extrapolation
    """
    f = [float(v) for v in values]
    if not f:
        raise ModelError("no values to extrapolate", element="fe", field="refinements")
    if len(f) < 2:
        return Extrapolation(f[-1], None, math.inf, math.inf, note="one mesh: no error estimate")
    highest = 1.1 * expected_order
    orders: list[float | None] = []
    ext: list[float | None] = []
    for f1, f2, f3 in zip(f, f[1:], f[2:], strict=False):
        if f1 == f2 == f3:  # converged to round-off
            orders.append(None)
            ext.append(f3)
            continue
        p = _observed_order(f1, f2, f3, ratio)
        orders.append(p)
        admitted = p is not None and lowest_order <= p <= highest
        ext.append(f3 + (f3 - f2) / (ratio**p - 1.0) if admitted and p is not None else None)
    last = f[-1]
    change = abs(f[-1] - f[-2]) / abs(f[-1]) if f[-1] else abs(f[-1] - f[-2])
    order = orders[-1] if orders else None
    if not ext or ext[-1] is None:
        if not ext:
            note = "two meshes: no observed order"
        elif order is None:
            note = "the last three meshes do not converge monotonically"
        else:
            note = (
                f"observed order {order:.3g} outside [{lowest_order:.3g}, {highest:.3g}] (theoretical "
                f"{expected_order:.3g}): not in the asymptotic range"
            )
        return Extrapolation(last, order, change, change, False, tuple(orders), tuple(ext), note)
    value = ext[-1]
    finest = abs(last - value) / abs(value) if value else abs(last - value)
    previous = ext[-2] if len(ext) >= 2 else None
    if previous is None:
        note = "one extrapolation, not checked by a second: refine once more"
        return Extrapolation(value, order, finest, finest, False, tuple(orders), tuple(ext), note)
    error = abs(value - previous) / abs(value) if value else abs(value - previous)
    return Extrapolation(value, order, error, finest, True, tuple(orders), tuple(ext))
