"""Plots of mount estimates: pad load–deflection, FE mesh convergence, anchor contact pressure,
calibration curve, measured against fitted FRF."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mechdyn.plotting import legend, new_axes
from mechdyn.units import convert, show

__all__ = ["plot_calibration", "plot_contact_pressure", "plot_convergence", "plot_frf_fit", "plot_pad_curve"]


# the display units of these plots, converted by the package's one unit registry
def mm(v: Any) -> Any:
    return convert(v, "m", "mm")


def kN(v: Any) -> Any:
    return convert(v, "N", "kN")


def kN_per_mm(v: Any) -> Any:
    return convert(v, "N/m", "kN/mm")


def MPa(v: Any) -> Any:
    return convert(v, "Pa", "MPa")


def um_per_N(v: Any) -> Any:
    return convert(v, "m/N", "µm/N")


def plot_pad_curve(pad: Any, ax: Any = None) -> Any:
    """Compressive force against deflection: linear and load-dependent, with the linear limit."""
    ax = new_axes(ax)
    d = np.linspace(0.0, 0.3 * pad.thickness, 100)
    ax.plot(mm(d), kN(pad.compression_stiffness * d), label="linear K_c")
    ax.plot(mm(d), kN(pad.compression_force(d)), label="load-dependent (neo-Hookean, E_c)")
    lim = 0.10 * pad.thickness
    ax.axvline(mm(lim), color="0.5", ls=":", lw=1)
    ax.annotate(
        "linear estimate holds to here (10 % strain)",
        (mm(lim), 0.95),
        xycoords=("data", "axes fraction"),
        fontsize="small",
        ha="right",
    )
    ax.set_xlabel("deflection (mm)")
    ax.set_ylabel("compressive force (kN)")
    kc = show(pad.compression_stiffness, "N/m", "kN/mm", ".4g")
    ax.set_title(f"{pad.name}: S = {pad.shape_factor:.2f}, K_c = {kc}")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax


def plot_convergence(
    levels: list[Any],
    estimate: float | None = None,
    ax: Any = None,
    reference: float | None = None,
    bound: float | None = None,
) -> Any:
    """FE stiffness against the number of unknowns (mesh refinement), with the extrapolated
    reference (N/m) and its relative error bound where given."""
    ax = new_axes(ax, figsize=(6.0, 4.0))
    n = [r.dofs for r in levels]
    k = [kN_per_mm(r.stiffness) for r in levels]
    ax.semilogx(n, k, "o-", label="finite elements")
    if reference is not None:
        ax.axhline(kN_per_mm(reference), color="C2", lw=1, label="extrapolated (Richardson)")
        if bound is not None and math.isfinite(bound):
            lo, hi = kN_per_mm(reference * (1 - bound)), kN_per_mm(reference * (1 + bound))
            ax.axhspan(lo, hi, color="C2", alpha=0.2, lw=0, label=f"error bound ±{100 * bound:.2g} %")
    if estimate is not None:
        ax.axhline(kN_per_mm(estimate), color="C3", ls="--", label="estimate from the drawing")
    ax.set_xlabel("unknowns")
    ax.set_ylabel("stiffness (kN/mm)")
    ax.set_title("mesh convergence")
    ax.grid(alpha=0.3, which="both")
    legend(ax, fontsize="small")
    return ax


def plot_contact_pressure(anchor: Any, preloads: list[float], threshold: float | None, ax: Any = None) -> Any:
    """Contact pressure between base plate and concrete against radius, per preload."""
    ax = new_axes(ax)
    r = mm(anchor.contact_radius)
    for F in preloads:
        ax.plot(r, MPa(anchor.pressure(F)), label=f"preload {show(F, 'N', 'kN')}")
    if threshold is not None:
        label = f"threshold {show(threshold, 'Pa', 'MPa')}"
        ax.axhline(MPa(threshold), color="k", ls="--", lw=1, label=label)
    ax.axvline(mm(anchor.lift_off_radius), color="0.5", ls=":", lw=1)
    ax.annotate(
        "plate lifts off",
        (mm(anchor.lift_off_radius), 0.9),
        xycoords=("data", "axes fraction"),
        fontsize="small",
    )
    ax.set_xlabel("radius from the bolt axis (mm)")
    ax.set_ylabel("contact pressure (MPa)")
    ax.set_title("base plate on concrete: contact pressure under preload (FE)")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax


def plot_calibration(joint: Any, target: float, fitted: float, ax: Any = None) -> Any:
    """Member stiffness of the pressure-cone model against the cone half-angle, and the fit."""
    ax = new_axes(ax, figsize=(6.0, 4.0))
    a = np.radians(np.linspace(10, 60, 101))
    ax.plot(np.degrees(a), [kN_per_mm(joint.member_stiffness(x)) for x in a], label="pressure cones")
    ax.axhline(kN_per_mm(target), color="k", ls="--", lw=1, label="reference")
    ax.axvline(math.degrees(fitted), color="C3", ls=":", label=f"fitted α = {math.degrees(fitted):.1f}°")
    ax.set_xlabel("cone half-angle α (deg)")
    ax.set_ylabel("member stiffness (kN/mm)")
    ax.set_title(f"{joint.name}: calibration of the cone angle")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax


def plot_frf_fit(frequency: np.ndarray, measured: np.ndarray, fit: Any, ax: Any = None) -> Any:
    """Measured receptance (m/N) magnitude against the fitted single-degree-of-freedom model."""
    ax = new_axes(ax)
    ax.semilogy(frequency, um_per_N(np.abs(measured)), ".", label="measured")
    f = np.linspace(frequency.min(), frequency.max(), 400)
    ax.semilogy(
        f,
        um_per_N(np.abs(fit.receptance(f))),
        label=f"fit: k {show(fit.stiffness, 'N/m', 'kN/mm', '.3g')}, ζ {fit.damping_ratio:.3f}",
    )
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("receptance |x/F| (µm/N)")
    ax.set_title("mount from its measured frequency response")
    ax.grid(alpha=0.3, which="both")
    legend(ax, fontsize="small")
    return ax
