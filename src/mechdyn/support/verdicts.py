"""The standards a machine on its supports is judged by: their tables as public data, and the functions
that apply them.

- **ISO 20816-3:2022** (*Mechanical vibration — Measurement and evaluation of machine vibration — Part
  3: Industrial machinery with a power rating above 15 kW and operating speeds between 120 r/min and
  30 000 r/min*), Annex A, Table A.1 (group 1: large machines, 300 kW to 50 MW) and Table A.2 (group 2:
  medium machines, 15 kW to 300 kW): the zone boundaries A/B, B/C and C/D of the broad-band RMS
  vibration velocity on a rigid or a flexible foundation (the values of ISO 10816-3:2009, Table A.1 and
  A.2, kept by the 2022 edition). The band is 10 Hz to 1 kHz, from 2 Hz for a machine running at
  600 r/min or less.
- **VDI 2062 Blatt 1** (2011, *Schwingungsisolierung — Begriffe und Methoden*): the isolation efficiency
  (Isolierwirkungsgrad) η = 1 − V of a transmissibility V (force on the floor over the exciting force);
  for one spring and damper V = √((1 + (2ζr)²)/((1 − r²)² + (2ζr)²)), r = Ω/ω_n (also Rao, *Mechanical
  Vibrations*, §9.10).
- **Vibration criteria of floors** (the VC curves of Ungar & Gordon, 1983, and Gordon, *Generic
  vibration criteria for vibration-sensitive equipment*, SPIE 3786, 1999; as IEST-RP-CC012.3): RMS
  velocity in one-third-octave bands from 1 Hz to 80 Hz, each curve flat over the band range; and the
  human-comfort curves of ISO 2631-2:1989 (vertical base curve, Annex A's multiplying factors: 1
  operating theatre, 2 residential by day, 4 office, 8 workshop), as the ASHRAE Handbook (HVAC
  Applications, ch. "Noise and vibration control") tabulates them beside the VC curves. One-third-octave
  bands are the base-10 bands of IEC 61260-1:2014 (centres 10^(n/10) Hz, edges a twentieth of a decade
  either side).

The numbers are public data (they are quoted in the standards' summaries, vendors' guides and
handbooks); they are kept here in SI (m/s RMS) and shown in mm/s or µm/s.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from mechdyn.errors import ModelError

__all__ = [
    "FOUNDATIONS",
    "GROUPS",
    "ISO_20816_3_SPEEDS_RPM",
    "SEPARATION_MARGIN",
    "VIBRATION_CRITERIA",
    "ZONE_BOUNDARIES",
    "ZONE_MEANINGS",
    "band_rms",
    "criterion_velocity",
    "floor_criteria",
    "foundation_class",
    "harmonic_band_rms",
    "iso_band",
    "iso_zone",
    "isolation_efficiency",
    "mode_separation",
    "third_octave_bands",
    "third_octave_spectrum",
    "transmissibility",
    "zone_boundaries",
]

GROUPS = (1, 2)
"""ISO 20816-3 machine groups: 1, large machines (300 kW to 50 MW); 2, medium machines (15 kW to 300 kW)."""
FOUNDATIONS = ("rigid", "flexible")
"""ISO 20816-3 foundation classes (§ 5.4: rigid when the lowest natural frequency of machine and
support lies at least 25 % above the main exciting frequency, else flexible)."""

ZONE_BOUNDARIES: dict[tuple[int, str], tuple[float, float, float]] = {
    # ISO 20816-3:2022, Table A.1, group 1, RMS velocity (2.3, 4.5, 7.1 mm/s; 3.5, 7.1, 11 mm/s)
    (1, "rigid"): (2.3e-3, 4.5e-3, 7.1e-3),
    (1, "flexible"): (3.5e-3, 7.1e-3, 11.0e-3),
    # ISO 20816-3:2022, Table A.2, group 2 (1.4, 2.8, 4.5 mm/s; 2.3, 4.5, 7.1 mm/s)
    (2, "rigid"): (1.4e-3, 2.8e-3, 4.5e-3),
    (2, "flexible"): (2.3e-3, 4.5e-3, 7.1e-3),
}
"""Zone boundaries A/B, B/C, C/D of the broad-band RMS vibration velocity, m/s, by (group, foundation)."""

ZONE_MEANINGS = {
    "A": "the vibration of newly commissioned machines normally falls in this zone",
    "B": "acceptable for unrestricted long-term operation",
    "C": "unsatisfactory for long-term continuous operation (a limited period until a remedy)",
    "D": "severe enough to cause damage to the machine",
}
"""What each zone of ISO 20816-3 (§ 6.2.2) says of a machine."""

ISO_20816_3_SPEEDS_RPM = (120.0, 30_000.0)
"""The operating speeds ISO 20816-3 covers, r/min."""
_LOW_SPEED_RPM = 600.0  # at or below it the band starts at 2 Hz (ISO 20816-3, § 4.2)
_BAND_HZ = {True: (2.0, 1000.0), False: (10.0, 1000.0)}

SEPARATION_MARGIN = 0.2
"""A natural frequency closer than ±20 % to an exciting harmonic is flagged (the separation margin
machinery specifications ask, e.g. API 610's ±10 % doubled for a support whose stiffness is only
estimated)."""

EXCITING_SHARE = 0.01
"""A harmonic of the load counts as exciting when its amplitude is at least 1 % of the largest one."""

VIBRATION_CRITERIA: dict[str, float] = {
    # ISO 2631-2:1989 vertical base curve times Annex A's factors (ASHRAE): flat above 8 Hz
    "workshop (ISO)": 800e-6,
    "office (ISO)": 400e-6,
    "residential day (ISO)": 200e-6,
    "operating theatre (ISO)": 100e-6,
    # Gordon (1999), IEST-RP-CC012.3: flat from 1 Hz to 80 Hz
    "VC-A": 50e-6,
    "VC-B": 25e-6,
    "VC-C": 12.5e-6,
    "VC-D": 6.25e-6,
    "VC-E": 3.12e-6,
}
"""One-third-octave RMS velocity of each floor vibration criterion over its flat part, m/s, least
strict first."""

_ISO_FLAT_FROM_HZ = 8.0
_CRITERIA_HZ = (1.0, 80.0)


# -- ISO 20816-3 ------------------------------------------------------------------------------------


def zone_boundaries(group: int, foundation: str) -> tuple[float, float, float]:
    """The A/B, B/C and C/D boundaries of ISO 20816-3:2022 (Table A.1 or A.2), RMS velocity.

    Parameters
    ----------
    group : {1, 2}
        Machine group: 1, large machines (300 kW to 50 MW); 2, medium machines (15 kW to 300 kW).
    foundation : {"rigid", "flexible"}
        The foundation class.

    Returns
    -------
    (float, float, float)
        m/s RMS.
    """
    key = (int(group), str(foundation))
    if key not in ZONE_BOUNDARIES:
        raise ModelError(
            f"(group {group!r}, foundation {foundation!r}): ISO 20816-3 has groups 1 and 2 and rigid or "
            "flexible foundations",
            element="vibration verdict",
            field="machine_group" if int(group) not in GROUPS else "foundation",
        )
    return ZONE_BOUNDARIES[key]


def iso_zone(velocity_rms: float, group: int, foundation: str) -> str:
    """The zone (A, B, C or D) of a broad-band RMS vibration velocity by ISO 20816-3:2022.

    A value on a boundary belongs to the lower zone (the boundaries are the largest values of zones
    A, B and C).

    Parameters
    ----------
    velocity_rms : float
        RMS vibration velocity, m/s.
    group : {1, 2}
        Machine group (Table A.1: 1; Table A.2: 2).
    foundation : {"rigid", "flexible"}
        The foundation class.

    Returns
    -------
    str
        ``"A"``, ``"B"``, ``"C"`` or ``"D"``.
    """
    bounds = zone_boundaries(group, foundation)
    return "ABCD"[int(np.searchsorted(bounds, float(velocity_rms), side="left"))]


def iso_band(running_speed: float) -> tuple[float, float]:
    """The frequency band of ISO 20816-3's broad-band measurement, Hz: 10 Hz to 1 kHz, or 2 Hz to
    1 kHz for a machine running at 600 r/min or less (ISO 20816-3:2022, § 4.2).

    Parameters
    ----------
    running_speed : float
        rad/s.
    """
    from mechdyn.units import convert

    return _BAND_HZ[bool(convert(abs(float(running_speed)), "rad/s", "rpm") <= _LOW_SPEED_RPM)]


def foundation_class(lowest_natural_frequency: float, running_frequency: float) -> str:
    """Rigid or flexible by ISO 20816-3:2022, § 5.4: rigid when the lowest natural frequency of the
    machine on its support is at least 25 % above the main exciting (running) frequency.

    Parameters
    ----------
    lowest_natural_frequency : float
        Hz.
    running_frequency : float
        Hz.
    """
    return "rigid" if lowest_natural_frequency >= 1.25 * running_frequency else "flexible"


# -- band RMS -------------------------------------------------------------------------------------


def harmonic_band_rms(coefficients: Any, fundamental: float, band: Sequence[float]) -> np.ndarray:
    """RMS of the harmonics of a periodic signal whose frequencies lie in a band.

    For x(t) = c₀ + 2 Re Σ c_h e^{i h 2π f₀ t} (the convention of :func:`mechdyn.support.excitation.series`)
    each harmonic h ≥ 1 has amplitude 2|c_h| and mean square 2|c_h|² (Parseval); c₀ counts |c₀|² when
    0 Hz is in the band. Band edges are inclusive.

    Parameters
    ----------
    coefficients : array_like
        (H + 1, ...) complex coefficients c_h, in the signal's unit.
    fundamental : float
        f₀, Hz.
    band : (float, float)
        Lowest and highest frequency, Hz.

    Returns
    -------
    ndarray
        (...) RMS, in the signal's unit.
    """
    c = np.asarray(coefficients)
    f = float(fundamental) * np.arange(c.shape[0])
    lo, hi = float(band[0]), float(band[1])
    inside = (f >= lo * (1 - 1e-12)) & (f <= hi * (1 + 1e-12))
    weight = np.where(np.arange(c.shape[0]) == 0, 1.0, 2.0) * inside
    power = np.tensordot(weight, np.abs(c) ** 2, axes=(0, 0))
    return np.sqrt(power)


def band_rms(samples: Any, sample_rate: float, band: Sequence[float]) -> float:
    """RMS of a periodic signal within a frequency band, from equally spaced samples of whole periods.

    The samples' discrete Fourier transform gives the harmonics (:func:`harmonic_band_rms`); a pure
    sine of amplitude A in the band gives A/√2, out of it 0.

    Parameters
    ----------
    samples : array_like
        (N,) the signal over a whole number of periods, any unit.
    sample_rate : float
        Samples per second, Hz.
    band : (float, float)
        Lowest and highest frequency, Hz.

    Returns
    -------
    float
        RMS, in the signal's unit.
    """
    x = np.asarray(samples, dtype=float)
    n = x.size
    c = np.fft.rfft(x) / n
    if n % 2 == 0:
        c[-1] *= 0.5  # the Nyquist bin stands for itself only
    return float(harmonic_band_rms(c, float(sample_rate) / n, band))


# -- VDI 2062 ---------------------------------------------------------------------------------------


def transmissibility(frequency_ratio: Any, damping_ratio: float) -> Any:
    """Force transmissibility of one spring and viscous damper, V = √((1 + (2ζr)²)/((1 − r²)² + (2ζr)²)).

    VDI 2062 Blatt 1 (2011), § 4; Rao, *Mechanical Vibrations*, 6th ed., § 9.10.

    Parameters
    ----------
    frequency_ratio : float or array_like
        r = Ω/ω_n, dimensionless.
    damping_ratio : float
        ζ, dimensionless.
    """
    r = np.asarray(frequency_ratio, dtype=float)
    d = (2 * damping_ratio * r) ** 2
    out = np.sqrt((1 + d) / ((1 - r**2) ** 2 + d))
    return float(out) if out.ndim == 0 else out


def isolation_efficiency(transmissibility: Any) -> Any:
    """VDI 2062 Blatt 1's isolation efficiency η = 1 − V (negative: the mounts amplify).

    Parameters
    ----------
    transmissibility : float or array_like
        V, the force on the floor over the exciting force, dimensionless.
    """
    if np.ndim(transmissibility):
        return 1.0 - np.asarray(transmissibility, dtype=float)
    return 1.0 - float(transmissibility)


# -- modes against the running speed ------------------------------------------------------------------


def mode_separation(
    natural_frequencies: Sequence[float] | np.ndarray,
    fundamental: float,
    orders: Sequence[int] | np.ndarray,
    margin: float = SEPARATION_MARGIN,
) -> list[dict[str, Any]]:
    """Each natural frequency against the nearest exciting harmonic of the running speed.

    The separation margin is (f_n − h f₀)/(h f₀), signed (positive: the mode lies above the harmonic),
    as API 610 and API 684 state it; the nearest harmonic is the one with the smallest |margin|.

    Parameters
    ----------
    natural_frequencies : sequence of float
        Hz.
    fundamental : float
        f₀, the running speed's frequency, Hz.
    orders : sequence of int
        The harmonic orders that excite (≥ 1).
    margin : float
        Flag a mode closer than this, a ratio (0.2: ±20 %).

    Returns
    -------
    list of dict
        Per mode: ``frequency_hz``, ``order`` (None without exciting harmonics), ``harmonic_hz``,
        ``margin_percent``, ``close`` (|margin| < ``margin``).
    """
    h = np.array(sorted({int(o) for o in orders if int(o) >= 1}), dtype=float)
    out = []
    for f in natural_frequencies:
        if h.size == 0 or fundamental <= 0:
            none = {"order": None, "harmonic_hz": None, "margin_percent": None, "close": False}
            out.append({"frequency_hz": float(f), **none})
            continue
        rel = (float(f) - h * fundamental) / (h * fundamental)
        k = int(np.argmin(np.abs(rel)))
        out.append(
            {
                "frequency_hz": float(f),
                "order": int(h[k]),
                "harmonic_hz": float(h[k] * fundamental),
                "margin_percent": float(100 * rel[k]),
                "close": bool(abs(rel[k]) < margin),
            }
        )
    return out


# -- floor vibration criteria ------------------------------------------------------------------------


def third_octave_bands(low: float = 1.0, high: float = 80.0) -> np.ndarray:
    """Base-10 one-third-octave bands (IEC 61260-1:2014): centres 10^(n/10) Hz, edges 10^(±1/20) times.

    Parameters
    ----------
    low, high : float
        Hz; the bands whose centres lie between them (the nominal 80 Hz band's exact centre is 79.4 Hz).

    Returns
    -------
    ndarray
        (B, 3) lower edge, centre, upper edge, Hz.
    """
    n = np.arange(math.floor(10 * math.log10(low) - 0.5), math.ceil(10 * math.log10(high) + 0.5) + 1)
    centre = 10.0 ** (n / 10)
    keep = (centre >= low / 10 ** (1 / 20)) & (centre <= high * 10 ** (1 / 20))
    centre = centre[keep]
    return np.column_stack([centre / 10 ** (1 / 20), centre, centre * 10 ** (1 / 20)])


def third_octave_spectrum(frequencies: Any, rms: Any, bands: Any = None) -> np.ndarray:
    """The RMS in each one-third-octave band of a line spectrum: the root of the summed mean squares of
    the lines in the band (lines on an edge go to the lower band).

    Parameters
    ----------
    frequencies : array_like
        (L,) the lines' frequencies, Hz.
    rms : array_like
        (L,) each line's RMS, any unit.
    bands : array_like, optional
        (B, 3) from :func:`third_octave_bands` (default: 1 Hz to 80 Hz).

    Returns
    -------
    ndarray
        (B,) band RMS, in the unit of ``rms``.
    """
    b = third_octave_bands() if bands is None else np.asarray(bands, dtype=float)
    f, r = np.asarray(frequencies, dtype=float), np.asarray(rms, dtype=float)
    inside = (f[None, :] > b[:, :1]) & (f[None, :] <= b[:, 2:])
    return np.sqrt(inside.astype(float) @ r**2)


def criterion_velocity(name: str, frequency: Any) -> Any:
    """A floor vibration criterion's one-third-octave RMS velocity at a band centre, m/s.

    The VC curves are flat from 1 Hz to 80 Hz (Gordon 1999; IEST-RP-CC012.3). The ISO curves are the
    ISO 2631-2:1989 vertical base curve times their factor: flat above 8 Hz; below, the base curve's
    acceleration, 5 mm/s² from 4 Hz to 8 Hz and 10 f^(−1/2) mm/s² from 1 Hz to 4 Hz, as velocity
    a/(2πf).

    Parameters
    ----------
    name : str
        A key of :data:`VIBRATION_CRITERIA`.
    frequency : float or array_like
        Band centre, Hz, 1 Hz to 80 Hz.
    """
    if name not in VIBRATION_CRITERIA:
        raise ModelError(f"{name!r} must be one of {', '.join(VIBRATION_CRITERIA)}", element="floor criteria")
    flat = VIBRATION_CRITERIA[name]
    f = np.asarray(frequency, dtype=float)
    if not name.endswith("(ISO)"):
        return flat + 0.0 * f
    factor = flat / VIBRATION_CRITERIA["operating theatre (ISO)"]
    # the base curve's acceleration below 8 Hz, m/s² (its flat velocity part is 100 µm/s)
    base_acc = np.where(f >= 4.0, 5e-3 * factor, 1e-2 * factor / np.sqrt(np.maximum(f, 1e-12)))
    return np.where(f >= _ISO_FLAT_FROM_HZ, flat, base_acc / (2 * math.pi * np.maximum(f, 1e-12)))


def floor_criteria(frequencies: Any, rms: Any) -> dict[str, Any]:
    """A floor's line spectrum of RMS velocity in one-third-octave bands against the criteria curves.

    Parameters
    ----------
    frequencies : array_like
        (L,) the lines' frequencies, Hz.
    rms : array_like
        (L,) RMS velocity of each line, m/s.

    Returns
    -------
    dict
        ``band_centre_hz`` and ``band_velocity_m_per_s`` (1 Hz to 80 Hz), ``met`` (the criteria every
        band stays within), ``strictest_met`` (None: not even the workshop curve), ``band_ratio``
        (criterion name → largest band over the curve).
    """
    bands = third_octave_bands(*_CRITERIA_HZ)
    v = third_octave_spectrum(frequencies, rms, bands)
    ratio = {n: float(np.max(v / criterion_velocity(n, bands[:, 1]))) for n in VIBRATION_CRITERIA}
    met = [n for n, r in ratio.items() if r <= 1.0]
    return {
        "band_centre_hz": [float(c) for c in bands[:, 1]],
        "band_velocity_m_per_s": [float(x) for x in v],
        "met": met,
        "strictest_met": met[-1] if met else None,
        "band_ratio": ratio,
    }
