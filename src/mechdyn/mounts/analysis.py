"""One mount, all the way: the estimate with its parts, the FE reference with its mesh convergence,
the calibration, the isolation figures. What ``mechdyn mount`` prints, stores and plots."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.mounts.bolted import BoltedJoint
from mechdyn.mounts.calibration import (
    Calibration,
    SdofFit,
    apply,
    fit_cone_angle,
    fit_frf,
    fit_pad_factor,
    load_calibration,
    read_frf_csv,
)
from mechdyn.mounts.fe import (
    AnchorFE,
    Extrapolation,
    FEResult,
    anchor_members,
    pad_compression,
    richardson,
)
from mechdyn.mounts.pad import ElastomerPad
from mechdyn.mounts.types import DampingPad, isolation
from mechdyn.results import Result, Table

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["MountResult", "analyse"]


@dataclass
class _Draft:
    """What the analysis has found so far (SI)."""

    summary: dict[str, Any]
    mount: Any
    fe_levels: list[FEResult] = field(default_factory=list)
    refinements: list[int] = field(default_factory=list)
    anchor: AnchorFE | None = None
    extrapolation: Extrapolation | None = None
    calibration: Calibration | None = None
    frf: tuple[np.ndarray, np.ndarray, SdofFit] | None = None


@dataclass(frozen=True, repr=False)  # the short repr of Result
class MountResult(Result):
    """Everything one mount analysis found: the estimate and its parts, the FE reference with its
    mesh convergence, the contact pressure, the calibration, the FRF fit, the isolation (SI).

    Attributes
    ----------
    name, kind : str
        The mount's name and type (``"pad"``, ``"anchor"``, ...).
    mount : object
        The estimate (calibrated when a stored calibration was applied).
    data : dict
        The summary (see :meth:`summary`).
    fe_levels : tuple of FEResult
        The FE reference at each refinement.
    anchor : AnchorFE, optional
        The finest anchor FE model (contact pressure).
    calibration : Calibration, optional
    frf : (ndarray, ndarray, SdofFit), optional
        Measured frequencies (Hz), receptance (m/N) and the single-DOF fit.
    preloads : tuple of float
        Preloads of the contact-pressure study, N.
    pressure_threshold : float, optional
        Pa.
    """

    name: str
    kind: str
    mount: Any
    data: dict[str, Any]
    fe_levels: tuple[FEResult, ...] = ()
    anchor: AnchorFE | None = None
    calibration: Calibration | None = None
    frf: tuple[np.ndarray, np.ndarray, SdofFit] | None = None
    preloads: tuple[float, ...] = ()
    pressure_threshold: float | None = None

    def summary(self) -> dict[str, Any]:
        """Stiffness along the main axis (N/m) with its breakdown, and what else the file asked for."""
        return dict(self.data)

    @property
    def warnings(self) -> tuple[str, ...]:
        """An FE reference whose error is not bounded (no two successive admissible Richardson
        extrapolations) or whose bound exceeds its tolerance."""
        d = self.data
        if "fe_error_bound_relative" not in d:
            return ()
        err, tol = d["fe_error_bound_relative"], d["fe_tolerance_relative"]
        finest = d["fe_convergence"][-1]["elements_through_thickness"]
        if not d["fe_error_verified"]:
            return (
                f"the FE reference did not converge to {100 * tol:.2g} %: at {finest} elements through "
                f"the thickness its error is not bounded ({d['fe_note']}; the estimate is "
                f"{100 * err:.2g} %); raise [fe] max_refinement",
            )
        if err > tol:
            return (
                f"the FE reference did not converge to {100 * tol:.2g} %: at {finest} elements through the "
                f"thickness the last two Richardson extrapolations differ by {100 * err:.2g} %; raise "
                "[fe] max_refinement",
            )
        return ()

    def to_frame(self) -> pd.DataFrame:
        """The FE mesh convergence (one row per refinement), or the figures with a unit as one row."""
        import pandas as pd

        if "fe_convergence" in self.data:
            return pd.DataFrame(self.data["fe_convergence"])
        from mechdyn.units import key_unit

        return pd.DataFrame(
            [
                {
                    k: v
                    for k, v in self.data.items()
                    if isinstance(v, (int, float)) and not isinstance(v, bool) and key_unit(k)
                }
            ]
        )

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        return {}

    def tables(self, **display_units: str) -> list[Table]:
        """The estimate, the frusta, the FE convergence, the contact pressure, calibration, FRF fit,
        isolation. ``length_unit`` (default ``"mm"``), ``pressure_unit`` (``"MPa"``) and
        ``stiffness_unit`` (default: the one the mount's stiffness reads best in, kN/mm for most)."""
        from mechdyn.mounts.tables import mount_tables

        return mount_tables(
            self,
            display_units.get("length_unit", "mm"),
            display_units.get("pressure_unit", "MPa"),
            display_units.get("stiffness_unit"),
        )

    def plots(self, **display_units: str) -> dict[str, Any]:
        """The pad's load curve, the FE convergence, the contact pressure, the calibration, the FRF fit
        (each where it applies)."""
        from mechdyn.mounts import plots as mp

        out: dict[str, Any] = {}
        mount = self.mount
        pad = getattr(mount, "pad", mount) if self.kind in ("pad", "damping_pad") else None
        if pad is not None:
            out["pad_curve.png"] = lambda: mp.plot_pad_curve(pad)
        if self.fe_levels:  # an FE reference is made for a bolted joint or a pad
            est = _estimate(mount, pad)
            out["fe_convergence.png"] = lambda: mp.plot_convergence(
                list(self.fe_levels),
                est,
                reference=self.data.get("fe_stiffness_N_per_m"),
                bound=self.data.get("fe_error_bound_relative"),
            )
        if self.anchor is not None:
            out["contact_pressure.png"] = lambda: mp.plot_contact_pressure(
                self.anchor, list(self.preloads), self.pressure_threshold
            )
        if self.calibration is not None and isinstance(mount, BoltedJoint):
            c = self.calibration
            out["calibration.png"] = lambda: mp.plot_calibration(mount, c.target, c.value)
        if self.frf is not None:
            out["frf_fit.png"] = lambda: mp.plot_frf_fit(*self.frf)
        return out


def _pad_of(mount: Any) -> ElastomerPad | None:
    if isinstance(mount, ElastomerPad):
        return mount
    if isinstance(mount, DampingPad):
        return mount.pad
    return None


def _estimate(mount: Any, pad: ElastomerPad | None) -> float:
    """The estimate an FE reference checks: a bolted joint's members, or a pad in compression, N/m."""
    return mount.member_stiffness() if isinstance(mount, BoltedJoint) else _pad(pad).compression_stiffness


def _pad(pad: ElastomerPad | None) -> ElastomerPad:
    """The pad where an FE reference or a calibration needs one (only pads and bolted joints get
    them, and a bolted joint is taken first)."""
    if pad is None:  # pragma: no cover - the schema allows [fe] and [calibration] on these alone
        raise ModelError("an FE reference and a calibration are made for a pad or a bolted joint")
    return pad


def _fe(spec: Any, mount: Any, report: _Draft) -> float | None:
    fe = spec.fe
    if fe is None:
        return None
    pad = _pad_of(mount)
    if pad is not None:
        if pad.diameter is None:
            raise ModelError(
                "the FE reference is axisymmetric: give the pad a diameter", element=spec.name, field="fe"
            )
        m = pad.material
        report.fe_levels, report.refinements, report.extrapolation = _converged(
            lambda n: pad_compression(pad.diameter, pad.thickness, m.youngs_modulus, m.poissons_ratio, n=n),
            fe,
        )
        return report.fe_levels[-1].stiffness
    joint: BoltedJoint = mount
    if len(joint.layers) != 2:
        raise ModelError(
            "the FE reference models a base plate on one concrete layer: give two layers",
            element=spec.name,
            field="fe",
        )
    plate, conc = joint.layers
    kw = dict(
        plate_thickness=plate.thickness,
        plate_radius=fe.plate_radius or 2.5 * joint.head_diameter,
        embedment=conc.thickness,
        concrete_radius=fe.concrete_radius or 6.0 * joint.head_diameter,
        hole_diameter=joint.hole_diameter,
        washer_diameter=joint.head_diameter,
        anchor_head_diameter=joint.lower_bearing_diameter,
        plate_E=plate.material.youngs_modulus,
        plate_nu=plate.material.poissons_ratio,
        concrete_E=conc.material.youngs_modulus,
        concrete_nu=conc.material.poissons_ratio,
    )
    runs, report.refinements, report.extrapolation = _converged(lambda n: anchor_members(**kw, n=n), fe)
    report.fe_levels = [r.result for r in runs]
    report.anchor = runs[-1]
    return runs[-1].stiffness


def _doubling_tail(levels: list[int]) -> int:
    """Where the last run of meshes refined by exactly 2 each time starts."""
    i = len(levels) - 1
    while i > 0 and levels[i] == 2 * levels[i - 1]:
        i -= 1
    return i


def _extrapolate(levels: list[int], stiffness: list[float], element_order: int) -> Extrapolation:
    """Richardson over the meshes refined by 2 each time, against the order of an energy from
    elements of ``element_order`` (2k; :func:`mechdyn.mounts.fe.richardson`)."""
    start = _doubling_tail(levels)
    return richardson(stiffness[start:], 2.0, expected_order=2.0 * element_order)


def _converged(run: Any, fe: Any) -> tuple[list[Any], list[int], Extrapolation]:
    """The FE runs over ``fe.refinements``, refined by 2 from the last until two successive Richardson
    extrapolations, each on an order admitted against the elements' theoretical one, agree within
    ``fe.tolerance`` (or ``fe.max_refinement`` is reached)."""
    levels = list(fe.refinements)
    runs = [run(n) for n in levels]
    while True:
        order = (runs[-1].result if isinstance(runs[-1], AnchorFE) else runs[-1]).order
        ex = _extrapolate(levels, [r.stiffness for r in runs], order)
        if (ex.verified and ex.error <= fe.tolerance) or 2 * levels[-1] > fe.max_refinement:
            return runs, levels, ex
        levels.append(2 * levels[-1])
        runs.append(run(levels[-1]))


def analyse(spec: Any, store: Any = None) -> MountResult:
    """Run everything a mount file asks for; ``store`` keeps (and supplies) calibrations.

    Parameters
    ----------
    spec : MountSpec
        A mount file as read (:func:`mechdyn.io.load_with_source`).
    store : ResultStore, optional
        Where calibrations are kept and read (``use_stored``).

    Returns
    -------
    MountResult
    """
    mount = spec.mount
    s: dict[str, Any] = {"mount_type": spec.kind}
    stored = None
    if spec.calibration.use_stored:
        if store is None:
            raise ModelError("use_stored needs a results database", element=spec.name, field="calibration")
        stored = load_calibration(store, spec.name)
        s["stiffness_as_drawn_N_per_m"] = mount.stiffness
        mount = apply(stored, mount)
        s["applied_calibration"] = stored.as_dict() | {"provenance": stored.provenance}
    report = _Draft(s, mount)
    s["stiffness_N_per_m"] = mount.stiffness
    s["breakdown"] = mount.breakdown()
    s["adjusts_height"] = bool(mount.adjusts_height)
    s["damps"] = bool(mount.damps)
    s["loss_factor"] = float(mount.loss_factor)
    pad = _pad_of(mount)
    if pad is not None:
        s["shape_factor"] = pad.shape_factor
        s["shear_stiffness_N_per_m"] = pad.shear_stiffness
        s["linear_limits_N"] = pad.linear_limits
    if isinstance(mount, BoltedJoint):
        s["bolt_stiffness_N_per_m"] = mount.bolt_stiffness
        s["member_stiffness_N_per_m"] = mount.member_stiffness()
        s["load_factor"] = mount.load_factor
        s["cone_half_angle_deg"] = math.degrees(mount.cone_angle)
    fe_finest = _fe(spec, mount, report)
    fe_k = None
    if fe_finest is not None:
        ex = report.extrapolation
        assert ex is not None  # _fe made it with the levels
        fe_k = ex.value  # the reference: extrapolated to the converged mesh
        s["fe_stiffness_N_per_m"] = fe_k
        s["fe_error_bound_relative"] = ex.error
        s["fe_error_verified"] = ex.verified
        s["fe_finest_mesh_N_per_m"] = fe_finest
        s["fe_discretisation_error_relative"] = ex.finest_error
        s["fe_convergence_order"] = ex.order
        s["fe_theoretical_order"] = 2.0 * report.fe_levels[-1].order
        s["fe_tolerance_relative"] = spec.fe.tolerance
        if ex.note:
            s["fe_note"] = ex.note
        # the observed order (log₂ of the ratio of successive changes: dimensionless) and the
        # extrapolation of each mesh with the two before it (in the last run of meshes refined by 2)
        start = _doubling_tail(report.refinements)
        pad_none = [None] * (start + 2)
        orders = (pad_none + list(ex.orders))[: len(report.fe_levels)]
        extrapolated = (pad_none + list(ex.extrapolations))[: len(report.fe_levels)]
        s["fe_convergence"] = [
            {
                "elements_through_thickness": n,
                "elements": r.elements,
                "dofs": r.dofs,
                "stiffness_N_per_m": r.stiffness,
                "observed_order_ratio": p,
                "extrapolated_N_per_m": e,
            }
            for n, r, p, e in zip(report.refinements, report.fe_levels, orders, extrapolated, strict=True)
        ]
        estimate = _estimate(mount, pad)
        s["estimate_to_fe"] = estimate / fe_k
        if pad is not None:  # the FE solid is the k = 1 law's; the table's k < 1 is the filled rubber's
            s["ideal_solid_estimate_to_fe"] = pad.ideal_compression_stiffness / fe_k
    if report.anchor is not None:
        a = report.anchor
        thr = spec.fe.pressure_threshold
        s["contact"] = [
            {
                "preload_N": F,
                "pressure_max_Pa": float(a.pressure(F).max()),
                "head_pressure_Pa": a.head_pressure * F,
                "radius_above_threshold_m": a.radius_above(thr, F) if thr is not None else None,
            }
            for F in spec.fe.preloads
        ]
        s["contact_lift_off_radius_m"] = a.lift_off_radius
        s["pressure_threshold_Pa"] = thr
    cal = spec.calibration
    provenance = cal.provenance or f"{spec.name}: {cal.reference} reference"
    if cal.reference == "fe":
        if fe_k is None:
            raise ModelError('reference = "fe" needs an [fe] table', element=spec.name, field="calibration")
        report.calibration = (
            fit_cone_angle(mount, fe_k, provenance)
            if isinstance(mount, BoltedJoint)
            else fit_pad_factor(_pad(pad), fe_k, provenance)
        )
    elif cal.reference == "measured":
        target = cal.measured_stiffness
        if isinstance(mount, BoltedJoint):  # the test sees bolt and members in parallel
            report.calibration = fit_cone_angle(mount, target - mount.bolt_stiffness, provenance)
        else:
            report.calibration = fit_pad_factor(_pad(pad), target, provenance)
    elif cal.reference == "frf":
        f, H, kind = read_frf_csv(Path(spec.directory) / cal.frf_csv)
        fit = fit_frf(f, H, kind)
        power = {"receptance": 0, "mobility": 1, "accelerance": 2}[kind]
        report.frf = (f, H / (2j * np.pi * f) ** power, fit)
        s["frf_fit"] = {
            "stiffness_N_per_m": fit.stiffness,
            "damping_N_s_per_m": fit.damping,
            "mass_kg": fit.mass,
            "natural_frequency_hz": fit.natural_frequency,
            "damping_ratio": fit.damping_ratio,
            "residual_relative": fit.residual,
        }
        if store is not None:
            s["frf_fit"]["record_id"] = store.put_record(
                "frf_fit", spec.name, s["frf_fit"], provenance + f" ({cal.frf_csv})"
            )
    if report.calibration is not None:
        c = report.calibration
        calibrated = apply(c, mount)
        # the quantity the parameter governs, as before and target: members, or the pad
        after = calibrated.member_stiffness() if isinstance(calibrated, BoltedJoint) else calibrated.stiffness
        s["calibration"] = c.as_dict() | {
            "provenance": c.provenance,
            "value_deg" if c.parameter == "cone_angle" else "value_factor": (
                math.degrees(c.value) if c.parameter == "cone_angle" else c.value
            ),
            "stiffness_after_N_per_m": after,
            "mount_stiffness_after_N_per_m": calibrated.stiffness,
        }
        if store is not None:
            s["calibration"]["record_id"] = c.save(store)
    if spec.load is not None:
        eta = spec.load.loss_factor if spec.load.loss_factor is not None else s["loss_factor"]
        s["isolation"] = isolation(
            s["stiffness_N_per_m"], spec.load.weight, spec.load.disturbing_frequency, eta
        )
    fe = spec.fe
    return MountResult(
        spec.name,
        spec.kind,
        report.mount,
        s,
        tuple(report.fe_levels),
        report.anchor,
        report.calibration,
        report.frf,
        tuple(fe.preloads) if fe is not None else (),
        fe.pressure_threshold if fe is not None else None,
    )
