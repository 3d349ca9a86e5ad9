"""A single-degree-of-freedom reading of an identified mode: stiffness and damping of a mount.

A mass m on a spring k and a dashpot c has the pole λ = −ζ ω_n + i ω_n √(1 − ζ²) with
ω_n = √(k/m) and ζ = c / (2 √(k m)), and the driving-point receptance
1/(k − m ω² + i c ω) = R/(iω − λ) + R*/(iω − λ*) with R = 1/(2 i m ω_d), ω_d = ω_n √(1 − ζ²)
(Ewins, *Modal Testing*, 2nd ed., 2000, §2.2–2.3). So k = m ω_n² and c = 2 ζ m ω_n for a known
mass, and the residue gives the mass back, m = 1/(2 ω_d abs(R)): the same model as the mount
calibration's fit (:func:`mechdyn.mounts.fit_frf`), read from the modal parameters.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mechdyn.measurement.identify import IdentifiedModes

__all__ = ["SingleDof", "single_dof"]


@dataclass(frozen=True)
class SingleDof:
    """Stiffness and damping of a single-DOF system from one identified mode.

    Attributes
    ----------
    mass : float
        m, kg, as given.
    stiffness, stiffness_std : float
        k = m ω_n² and its standard uncertainty, N/m.
    damping, damping_std : float
        c = 2 ζ m ω_n and its standard uncertainty, N·s/m.
    damping_ratio, damping_ratio_std : float
        ζ and its standard uncertainty, dimensionless.
    natural_frequency_hz, natural_frequency_std_hz : float
        ω_n / 2π and its standard uncertainty, Hz.
    residue_mass : float
        1/(2 ω_d abs(R)) from the driving-point receptance residue, kg (NaN when the mode has no
        driving-point residue or the data are not receptance-form residues).
    """

    mass: float
    stiffness: float
    stiffness_std: float
    damping: float
    damping_std: float
    damping_ratio: float
    damping_ratio_std: float
    natural_frequency_hz: float
    natural_frequency_std_hz: float
    residue_mass: float


def single_dof(modes: IdentifiedModes, mass: float, *, mode: int = 0, mass_std: float = 0.0) -> SingleDof:
    """Read one identified mode as a mass on a spring and a dashpot.

    Parameters
    ----------
    modes : IdentifiedModes
        From :func:`mechdyn.measurement.identify_modes`.
    mass : float
        m, kg: the mass the mount carried in the test (> 0).
    mode : int
        Which mode (0: the first).
    mass_std : float
        Standard uncertainty of ``mass``, kg (≥ 0).

    Returns
    -------
    SingleDof

    Raises
    ------
    ValueError
        For a mass that is not positive, a negative ``mass_std`` or a mode index out of range.

    Notes
    -----
    k = m ω_n², c = 2 ζ m ω_n (module sources); uncertainties by first-order propagation of the
    stated scatter of ω_n and ζ and of ``mass_std``, taken independent.
    """
    if not (math.isfinite(mass) and mass > 0):
        raise ValueError(f"mass {mass!r} kg must be positive: give the mass the mount carried in the test")
    if not (math.isfinite(mass_std) and mass_std >= 0):
        raise ValueError(f"mass_std {mass_std!r} kg must be ≥ 0")
    n = len(modes.omega)
    if not -n <= mode < n:
        raise ValueError(f"mode {mode} is out of range: {n} modes were identified")
    w = float(modes.omega[mode])
    z = float(modes.damping[mode])
    sw = float(modes.omega_scatter[mode])
    sz = float(modes.damping_scatter[mode])
    rm = mass_std / mass
    k = mass * w**2
    c = 2.0 * z * mass * w
    residue_mass = math.nan
    for i, out in enumerate(modes.outputs):
        if out in modes.references and modes.residues.shape[1] > 0:
            R = complex(modes.residues[i, modes.references.index(out), mode])
            if R != 0:
                residue_mass = 1.0 / (2.0 * w * math.sqrt(1.0 - z**2) * abs(R))
            break
    return SingleDof(
        mass=float(mass),
        stiffness=k,
        stiffness_std=k * math.hypot(2.0 * sw / w, rm),
        damping=c,
        damping_std=abs(c) * float(np.sqrt((sz / z) ** 2 + (sw / w) ** 2 + rm**2))
        if z
        else 2 * mass * w * sz,
        damping_ratio=z,
        damping_ratio_std=sz,
        natural_frequency_hz=w / (2.0 * math.pi),
        natural_frequency_std_hz=sw / (2.0 * math.pi),
        residue_mass=residue_mass,
    )
