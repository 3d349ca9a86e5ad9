"""The calibration loop: fit the free parameters of the estimates to FE results or measurements,
keep them with their provenance, use them in the next prediction.

- Cone half-angle α of a bolted joint's members, to a reference member stiffness (FE or test).
- Compression coefficient k ("pad factor") of an elastomer pad, to a reference compression stiffness.
- A mount's stiffness and damping from a measured frequency response: a single-degree-of-freedom
  model 1/H = k − m ω² + i c ω fitted first linearly (the dynamic stiffness is linear in k, m, c),
  then by nonlinear least squares on H itself (relative residuals; scipy ``least_squares``).

A :class:`Calibration` is stored in the results database as a named record (kind
``"calibration"``) with where its reference came from; :func:`load_calibration` reads the latest
back, and :func:`apply` makes the calibrated estimate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from scipy.optimize import brentq, least_squares

from mechdyn.checks import check_array, check_number
from mechdyn.errors import ModelError
from mechdyn.mounts.bolted import BoltedJoint
from mechdyn.mounts.pad import ElastomerPad

__all__ = [
    "Calibration",
    "SdofFit",
    "apply",
    "fit_cone_angle",
    "fit_frf",
    "fit_pad_factor",
    "load_calibration",
    "read_frf_csv",
]


@dataclass(frozen=True)
class Calibration:
    """A fitted parameter and where it came from.

    Attributes
    ----------
    name : str
        What it calibrates (e.g. the joint or pad name).
    parameter : str
        ``"cone_angle"`` (rad) or ``"compression_coefficient"``.
    value : float
        The fitted value, in the parameter's unit (rad, or dimensionless).
    target : float
        The reference stiffness it reproduces, N/m.
    before : float
        The estimate before calibration, N/m.
    provenance : str
        Where the reference came from (FE model and mesh, test report, file).
    """

    name: str
    parameter: str
    value: float
    target: float
    before: float
    provenance: str

    def as_dict(self) -> dict[str, Any]:
        """The calibration as a JSON-ready dict (SI values), as it is stored."""
        return {
            "name": self.name,
            "parameter": self.parameter,
            "value": self.value,
            "target_N_per_m": self.target,
            "before_N_per_m": self.before,
        }

    def save(self, store: Any) -> int:
        """Store as a named record with its provenance; returns the record id.

        Parameters
        ----------
        store : mechdyn.store.ResultStore
            The results database.
        """
        return store.put_record("calibration", self.name, self.as_dict(), self.provenance)


def load_calibration(store: Any, name: str) -> Calibration:
    """The latest calibration of ``name`` in a results store.

    Parameters
    ----------
    store : mechdyn.store.ResultStore
        The results database.
    name : str
        The calibrated estimate's name.

    Raises
    ------
    StoreError
        When there is none, saying how to make one.
    """
    from mechdyn.store.store import StoreError

    try:
        rec = store.latest_record("calibration", name)
    except StoreError:
        raise StoreError(
            f"no calibration of mount {name!r} in the results database; calibrate it first: "
            'give its mount file a [calibration] table (reference = "fe", "measured" or "frf") and '
            "run `mechdyn mount FILE` with the same database"
        ) from None
    d = rec.data
    return Calibration(
        d["name"], d["parameter"], d["value"], d["target_N_per_m"], d["before_N_per_m"], rec.provenance
    )


def _fit(f, lo: float, hi: float, what: str, name: str) -> float:
    a, b = f(lo), f(hi)
    if a * b > 0:
        raise ModelError(
            f"no {what} in [{lo:g}, {hi:g}] reproduces the reference (the estimate spans "
            f"{min(a, b):+.3g} to {max(a, b):+.3g} N/m from it); check the reference",
            element=name,
            field=what,
        )
    return float(brentq(f, lo, hi, xtol=1e-12, rtol=1e-12))


def fit_cone_angle(joint: BoltedJoint, target: float, provenance: str) -> Calibration:
    """The cone half-angle α at which the frusta give the reference member stiffness (N/m).

    Parameters
    ----------
    joint : BoltedJoint
        The joint as drawn.
    target : float
        The reference member stiffness, N/m, from 1e-6 to 1e15 N/m.
    provenance : str
        Where the reference comes from.
    """
    target = check_number(joint.name, "target", target, "N/m", positive=True, what="reference stiffness")
    val = _fit(
        lambda a: joint.member_stiffness(a) - target,
        math.radians(1.0),
        math.radians(80.0),
        "cone_angle",
        joint.name,
    )
    return Calibration(joint.name, "cone_angle", val, float(target), joint.member_stiffness(), provenance)


def fit_pad_factor(pad: ElastomerPad, target: float, provenance: str) -> Calibration:
    """The compression coefficient k at which the pad formula gives the reference stiffness (N/m).

    Against an FE model of a linear-elastic solid k comes out near 1 (the solid's own law); the
    k < 1 of a filled rubber shows only in a test of the compound, which is the reference to use.

    Parameters
    ----------
    pad : ElastomerPad
        The pad as drawn.
    target : float
        The reference compression stiffness, N/m, from 1e-6 to 1e15 N/m.
    provenance : str
        Where the reference comes from.
    """
    target = check_number(pad.name, "target", target, "N/m", positive=True, what="reference stiffness")

    def err(k: float) -> float:
        return replace(pad, compression_coefficient=k).compression_stiffness - target

    val = _fit(err, 1e-3, 1.0, "compression_coefficient", pad.name)
    return Calibration(
        pad.name, "compression_coefficient", val, float(target), pad.compression_stiffness, provenance
    )


def apply(calibration: Calibration, estimate: BoltedJoint | ElastomerPad) -> BoltedJoint | ElastomerPad:
    """The estimate with the calibrated parameter in place.

    Parameters
    ----------
    calibration : Calibration
        A fitted parameter.
    estimate : BoltedJoint or ElastomerPad
        The estimate to apply it to (a joint's cone angle, a pad's compression coefficient).
    """
    if calibration.parameter == "cone_angle" and isinstance(estimate, BoltedJoint):
        return replace(estimate, cone_angle=calibration.value)
    if calibration.parameter == "compression_coefficient" and isinstance(estimate, ElastomerPad):
        return replace(estimate, compression_coefficient=calibration.value)
    raise ModelError(
        f"a {calibration.parameter} calibration does not apply to a {type(estimate).__name__}",
        element=calibration.name,
        field="parameter",
    )


@dataclass(frozen=True)
class SdofFit:
    """A mount's stiffness and damping from a measured frequency response.

    Attributes
    ----------
    stiffness : float
        k, N/m.
    damping : float
        c, N·s/m.
    mass : float
        m, kg (the mass the mount carried in the test).
    residual : float
        RMS relative misfit of H.
    """

    stiffness: float
    damping: float
    mass: float
    residual: float

    @property
    def natural_frequency(self) -> float:
        """Hz."""
        return math.sqrt(self.stiffness / self.mass) / (2 * math.pi)

    @property
    def damping_ratio(self) -> float:
        return self.damping / (2 * math.sqrt(self.stiffness * self.mass))

    def receptance(self, frequency: Any) -> np.ndarray:
        """The fitted model's receptance 1/(k − m ω² + i c ω), m/N.

        Parameters
        ----------
        frequency : float or ndarray
            Frequency, Hz, from 0 to 1e7 Hz.
        """
        w = 2 * np.pi * check_array("frf", "frequency", frequency, "Hz", nonnegative=True, what="frequencies")
        return 1.0 / (self.stiffness - self.mass * w**2 + 1j * self.damping * w)


_KINDS = {"receptance": 0, "mobility": 1, "accelerance": 2}
RESPONSE_RANGE = (1e-30, 1e30)
"""The magnitudes (SI) a measured FRF point may have: far beyond any mount's receptance, mobility or
accelerance on both sides, so that a zero or an overflow never reaches the fit."""


def fit_frf(frequency: Any, response: Any, kind: str = "receptance") -> SdofFit:
    """Fit k, c, m of a single-degree-of-freedom model to a measured FRF.

    Parameters
    ----------
    frequency : array_like
        Hz, > 0 (at most 1e7 Hz).
    response : array_like
        Complex H(f): displacement (receptance, m/N), velocity (mobility, m/(N·s)) or
        acceleration (accelerance, m/(N·s²)) per force; finite, of magnitude between 1e-30 and
        1e30 (SI).
    kind : {"receptance", "mobility", "accelerance"}

    Raises
    ------
    mechdyn.errors.ModelError
        For a frequency or a response that is not finite or out of range (naming the first), too few
        points, or data that do not look like one resonance.
    """
    f = check_array("frf", "frequency", frequency, "Hz", positive=True, what="frequencies")
    H = check_array("frf", "response", response, complex_values=True, bounded=False, what="responses")
    small = np.abs(H) < RESPONSE_RANGE[0]
    if (small | (np.abs(H) > RESPONSE_RANGE[1])).any():
        k = int(np.argmax(small | (np.abs(H) > RESPONSE_RANGE[1])))
        raise ModelError(
            f"response[{k}] = {H.flat[k]:g} is {'too small' if small.flat[k] else 'too large'} to be a "
            "measured "
            f"response; give magnitudes between {RESPONSE_RANGE[0]:g} and {RESPONSE_RANGE[1]:g} (SI)",
            element="frf",
            field="response",
        )
    if kind not in _KINDS:
        raise ModelError(f"{kind!r} must be one of {sorted(_KINDS)}", element="frf", field="kind")
    if f.ndim != 1 or f.size != H.size or f.size < 4 or np.any(f <= 0) or not np.all(np.isfinite(H)):
        raise ModelError(
            "need at least 4 finite points with positive frequencies and one response each",
            element="frf",
            field="frequency",
        )
    w = 2 * np.pi * f
    X = H / (1j * w) ** _KINDS[kind]  # receptance
    Z = 1.0 / X  # dynamic stiffness k − m ω² + i c ω
    A = np.column_stack([np.ones_like(w), -(w**2)])
    (k0, m0), *_ = np.linalg.lstsq(A, Z.real, rcond=None)
    c0 = float(np.sum(Z.imag * w) / np.sum(w**2))
    scale = np.array([abs(k0) or 1.0, abs(c0) or 1.0, abs(m0) or 1.0])

    def res(p):
        k, c, m = p * scale
        model = 1.0 / (k - m * w**2 + 1j * c * w)
        r = (model - X) / np.abs(X)
        return np.concatenate([r.real, r.imag])

    sol = least_squares(res, np.array([k0, c0, m0]) / scale, method="lm", xtol=1e-14, ftol=1e-14)
    k, c, m = sol.x * scale
    if not (k > 0 and m > 0 and c >= 0):
        raise ModelError(
            f"the data do not look like one resonance (k {k:.3g} N/m, m {m:.3g} kg, c {c:.3g} N·s/m); "
            "give a frequency range around the mount's resonance",
            element="frf",
            field="response",
        )
    return SdofFit(float(k), float(c), float(m), float(np.sqrt(np.mean(sol.fun**2))))


def read_frf_csv(path: str | Path) -> tuple[np.ndarray, np.ndarray, str]:
    """Read a measured FRF: columns ``frequency_Hz`` and either ``real`` and ``imag`` or
    ``magnitude`` and ``phase_deg``; an optional comment line ``# kind: mobility``.

    Returns frequency (Hz), the complex response and its kind.

    Parameters
    ----------
    path : str or Path
        The CSV file.
    """
    import pandas as pd

    p = Path(path)
    if not p.is_file():
        raise ModelError(f"{p}: no such file", element=str(p), field="frf")
    kind = "receptance"
    for line in p.read_text(encoding="utf-8").splitlines():
        if line.startswith("#") and "kind:" in line:
            kind = line.split("kind:", 1)[1].strip()
    df = pd.read_csv(p, comment="#")
    cols = set(df.columns)
    if "frequency_Hz" not in cols:
        raise ModelError(
            f"{p}: no frequency_Hz column (found {sorted(cols)})", element=str(p), field="frequency_Hz"
        )
    if {"real", "imag"} <= cols:
        H = df["real"].to_numpy() + 1j * df["imag"].to_numpy()
    elif {"magnitude", "phase_deg"} <= cols:
        H = df["magnitude"].to_numpy() * np.exp(1j * np.radians(df["phase_deg"].to_numpy()))
    else:
        raise ModelError(
            f"{p}: give columns real and imag, or magnitude and phase_deg (found {sorted(cols)})",
            element=str(p),
            field="columns",
        )
    return df["frequency_Hz"].to_numpy(dtype=float), H, kind
