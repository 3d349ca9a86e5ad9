"""mechdyn's spur mesh stiffness against ROSS's time-varying mesh stiffness (issue 30).

ROSS (petrobras/ross, ``pip install ross-rotordynamics``) models a spur pair's time-varying mesh
stiffness (TVMS) in ``GearElementTVMS`` and ``Mesh``: the potential-energy tooth of Ma et al. (2014)
(bending, shear and axial compression integrated over the rack-generated trochoid fillet and the
involute), the body of Sainsot et al. (2004) under it, and a constant Hertz stiffness
π E b / (4 (1 − ν²)). Its own example, asserted in ``ross/tests/test_gear_element.py``
(``gear_tvms`` fixture and ``test_mesh_params``; ROSS v2.3.0, commit
a26a66fe40e8b86aa5e5c203d18cca801e68ff8e; the same numbers at main
631a249adbae414d5f5f986479b58f1a4c47935e, where the classes moved to ``ross/multi_rotor/``),
is a 62:62 pair: m 2 mm, α 20°, b 20 mm, bore 35 mm, E 206 GPa, ν 0.3, addendum 1, tip clearance
0.25, its rack's tip rounded fully, ρ = 0.25 m / (1 − sin α) = 0.37995 m (given to mechdyn as
``fillet_radius``; its default, ISO 53's 0.38, moves the involute's start by 1e-5). mechdyn's
``GearPair(..., tooth_model="involute")`` is the same kind of model, so the two are compared number by
number: geometry and contact ratio to rounding; mesh stiffness to the agreement measured, which the
modelling differences below explain.

Where the models differ (the mesh stiffness differences all come from these):

- Kinematics. ROSS advances the contact linearly in the driving tooth's pressure angle, from the
  start of its involute (α_c = 14.77°) to its tip (24.45°), a span of (α_a − α_c)/ε_α per mesh
  period; mechdyn moves it uniformly along the line of action from the start of the active profile
  that the mating tip sets (15.28°) to the tip. Both give double contact over the first ε_α − 1 of
  the period (0.79), with the same phase origin (a pair entering at the driving tooth's root).
- The foundation's tooth angle θ_f: ROSS's closed form (0.04566 rad) against the chord of the
  generated tooth at the root circle in mechdyn (0.04858 rad), and the load point's height above the
  root circle: projected on the tooth's centre line in ROSS, radial in mechdyn.
- Integration: ROSS's adaptive quadrature over the parametric trochoid and involute, mechdyn's
  Gauss–Legendre over the chordal thickness against the radius.

Measured (mechdyn / ROSS − 1, same phases): one tooth +1.1 % at the start of the involute, +2.9 % at
the pitch point, +4.3 % at the tip; mesh stiffness pointwise −1.45 % to +0.30 % (rms 0.70 %); mean
−0.33 %; double-contact mean −0.17 %; single-contact mean −1.44 %; the four first harmonics' relative
amplitudes within 0.004. The tolerances below are those measured differences with a small margin, not
a goal.

ROSS's ``Mesh.stiffness`` (4.096607e8 N/m in its test) is not the mean of its TVMS: it is the rule
ε_α b E₁E₂ / (9 (E₁ + E₂)), which ROSS's own TVMS mean (3.7365e8) lies 8.8 % below and mechdyn's
(3.7242e8) 9.1 % below; it is reproduced here from mechdyn's ε_α only, as a check of the ratio.

ROSS's only asserted time response with a gear mesh (``test_mesh_with_backlash`` in
``ross/tests/test_multi_rotor.py`` at main 631a249a, a 20:20 pair with backlash on lateral bearings)
runs its square-wave stiffness built on that rule, not the TVMS; of it, the contact ratio and working
pressure angle at its mean centre distance are compared here.

``test_against_ross_installed`` recomputes ROSS where it imports (ROSS 2.3.0 needs plotly < 6; with
plotly 7 its import fails on the removed ``scattermapbox`` and the test is skipped). The ROSS values
not asserted by ROSS itself (GOLDEN_ROSS) were computed with ROSS 2.3.0 by :func:`ross_values`, the
same computation as the live test's; to regenerate them::

    pip install ross-rotordynamics==2.3.0 "plotly<6"
    python tests/test_ross_gear_mesh.py
"""

from __future__ import annotations

import importlib
import math
import warnings
from copy import deepcopy

import numpy as np
import pytest

from mechdyn.gears import GearPair, MeshCycle, SpurGear

E, NU, B = 206e9, 0.3, 0.020  # ROSS's gear_tvms fixture: Pa, -, m
RHO_F = 0.25 / (1.0 - math.sin(math.radians(20.0)))  # ROSS's cutter tip radius, in modules
POINTS = 999  # ROSS samples 1000 angles over one mesh period, the last repeating the first phase

# Asserted by ROSS: ross/tests/test_gear_element.py, v2.3.0 (a26a66fe40e8b86aa5e5c203d18cca801e68ff8e)
ROSS_RADII = {"base": 0.05826094248872632, "pitch": 0.062, "addendum": 0.064, "root": 0.0595}  # m
ROSS_INVOLUTE_START_ANGLE = 0.2577380345253824  # rad, pr_angles_dict["start_point"]
ROSS_CONTACT_RATIO = 1.7897798668330458
ROSS_HERTZ = 3555868607.9093266  # N/m
ROSS_RULE_STIFFNESS = 4.096607e08  # N/m, Mesh.stiffness = ε_α b E₁E₂ / (9 (E₁ + E₂)), asserted rtol 1e-6
ROSS_FIRST_FIVE = [
    396622921.3581085,
    396738680.0375346,
    396854147.2919756,
    396969323.136738,
    397084207.5865779,
]

# Computed with ROSS 2.3.0 (command in the module docstring), N/m; phases i/999 of the mesh period
GOLDEN_ROSS = {
    "mean": 373654756.68981355,
    "double_mean": 411906389.26251036,  # phases < ε_α − 1
    "single_mean": 229937908.5952527,
    "max": 419569438.98401976,
    "min": 229323644.97141242,
    "harmonics": [0.20687, 0.14096, 0.0857, 0.03222],  # |X_n| 2/X_0, n = 1…4
    "samples": {
        0: 396622921.3581085,
        111: 407693724.622993,
        222: 415164774.3836515,
        333: 419009078.1645833,
        444: 419206282.6771962,
        555: 415755237.98715967,
        666: 408674584.71793866,
        777: 397991680.24129075,
        888: 230242263.6690596,
        998: 229340929.2382538,
    },
    # one tooth, no Hertz (GearElementTVMS._compute_stiffness), at these pressure angles
    "tooth": {ROSS_INVOLUTE_START_ANGLE: 732098711.8353938, math.radians(20.0): 470982092.2419473},
    "tooth_tip": 230939164.97598696,
}

# Asserted by ROSS: test_mesh_with_backlash, ross/tests/test_multi_rotor.py at main
# (631a249adbae414d5f5f986479b58f1a4c47935e): means over its time response
ROSS_BACKLASH_CENTER_DISTANCE = 0.20004375431223567  # m
ROSS_BACKLASH_PRESSURE_ANGLE = 0.34966621486324245  # rad
ROSS_BACKLASH_CONTACT_RATIO = 1.5525088765723407

# measured agreement (module docstring) with a small margin, mechdyn / ROSS − 1
TOL_POINTWISE = 0.02  # measured −1.45 % … +0.30 %
TOL_MEAN = 0.005  # measured −0.33 %
TOL_DOUBLE = 0.005  # double-contact mean and its end values, measured −0.17 %, first samples +0.30 %
TOL_SINGLE = 0.02  # single-contact mean, measured −1.44 %
TOL_TOOTH = 0.06  # one tooth, measured +1.1 %, +2.9 %, +4.3 % (θ_f and load-height definitions)
TOL_HARMONICS = 0.006  # absolute, relative amplitudes, measured ≤ 0.0037


def _gear(name: str) -> SpurGear:
    return SpurGear(
        teeth=62,
        module="2 mm",
        face_width=B,
        pressure_angle="20 deg",
        youngs_modulus=E,
        poisson_ratio=NU,
        bore_diameter="35 mm",
        fillet_radius=RHO_F,
        name=name,
    )


@pytest.fixture(scope="module")
def pair() -> GearPair:
    return GearPair(_gear("pinion"), _gear("gear"), tooth_model="involute")


@pytest.fixture(scope="module")
def cycle(pair: GearPair) -> MeshCycle:
    """Sampled at ROSS's phases i/999, i = 0 … 998 (mechdyn's cycle omits the end point)."""
    return pair.mesh_cycle(POINTS)


def _tooth_stiffness(pair: GearPair, pressure_angle: float) -> float:
    """One pinion tooth, without Hertz, loaded on its involute where the pressure angle is this, N/m."""
    p = pair.pinion
    r = p.base_radius / math.cos(pressure_angle)
    return 1.0 / pair.teeth[0].compliance(p.load_height(r), p.load_angle(r))


def _double(cycle: MeshCycle) -> np.ndarray:
    return np.arange(len(cycle.stiffness)) / len(cycle.stiffness) < cycle.pair.contact_ratio - 1


def test_geometry_and_contact_ratio_as_ross_asserts(pair, cycle):
    p = pair.pinion
    for got, want in (
        (p.base_radius, ROSS_RADII["base"]),
        (p.pitch_radius, ROSS_RADII["pitch"]),
        (p.tip_radius, ROSS_RADII["addendum"]),
        (p.root_radius, ROSS_RADII["root"]),
        (math.acos(p.base_radius / p.involute_start_radius), ROSS_INVOLUTE_START_ANGLE),
        (pair.contact_ratio, ROSS_CONTACT_RATIO),
        (1.0 / pair.pair_compliances(pair.pitch_point)["hertz"], ROSS_HERTZ),
    ):
        assert got == pytest.approx(want, rel=1e-12)
    # ROSS's Mesh.stiffness is a rule in ε_α, not its TVMS mean: mechdyn's ε_α reproduces it
    assert pair.contact_ratio * B * E * E / (9 * (E + E)) == pytest.approx(ROSS_RULE_STIFFNESS, rel=1e-6)
    # double contact over the first ε_α − 1 of the period in both (ROSS: d_α ≤ d_meshing (ε_α − 1))
    assert cycle.double_contact_share == pytest.approx(ROSS_CONTACT_RATIO - 1, abs=1.0 / POINTS)


def test_mesh_stiffness_against_ross_published_and_golden(cycle):
    k = cycle.stiffness
    # the five stiffness values ROSS asserts, at the start of the period (double contact)
    np.testing.assert_allclose(k[:5], ROSS_FIRST_FIVE, rtol=TOL_DOUBLE)
    g = GOLDEN_ROSS
    samples = np.array(list(g["samples"].values()))
    np.testing.assert_allclose(k[list(g["samples"])], samples, rtol=TOL_POINTWISE)
    double = _double(cycle)
    assert cycle.mean == pytest.approx(g["mean"], rel=TOL_MEAN)
    assert k[double].mean() == pytest.approx(g["double_mean"], rel=TOL_DOUBLE)
    assert k[~double].mean() == pytest.approx(g["single_mean"], rel=TOL_SINGLE)
    assert k.max() == pytest.approx(g["max"], rel=TOL_DOUBLE)
    assert k.min() == pytest.approx(g["min"], rel=TOL_SINGLE)
    amplitude, _ = cycle.harmonics(4)
    np.testing.assert_allclose(amplitude, g["harmonics"], atol=TOL_HARMONICS)


def test_one_tooth_against_ross_golden(pair):
    for angle, want in GOLDEN_ROSS["tooth"].items():
        assert _tooth_stiffness(pair, angle) == pytest.approx(want, rel=TOL_TOOTH)
    tip = math.acos(pair.pinion.base_radius / pair.pinion.tip_radius)
    assert _tooth_stiffness(pair, tip) == pytest.approx(GOLDEN_ROSS["tooth_tip"], rel=TOL_TOOTH)


def test_contact_ratio_at_ross_backlash_center_distance():
    def gear(name: str) -> SpurGear:
        return SpurGear(teeth=20, module=0.01, face_width=0.030, youngs_modulus=2e11, name=name)

    pair = GearPair(gear("pinion"), gear("gear"), center_distance=ROSS_BACKLASH_CENTER_DISTANCE)
    # ROSS's numbers are means over a response whose centre distance varies slightly: 1e-5, not rounding
    assert pair.working_pressure_angle == pytest.approx(ROSS_BACKLASH_PRESSURE_ANGLE, rel=1e-5)
    assert pair.contact_ratio == pytest.approx(ROSS_BACKLASH_CONTACT_RATIO, rel=1e-5)


def _import_ross():
    """ROSS's gear classes (2.3.0 layout, or main's ross.multi_rotor), or skip where ROSS is absent or
    does not import (ROSS 2.3.0 under plotly 7.1 raises ValueError on import)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            importlib.import_module("ross")
        except ImportError:
            pytest.skip("ross is not installed")
        except Exception as exc:  # ROSS fails inside its own import: nothing to compare
            first = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
            pytest.skip(f"ross is installed but does not import: {type(exc).__name__}: {first}")
        try:
            units = importlib.import_module("ross.units")
            materials = importlib.import_module("ross.materials")
            try:
                gears = importlib.import_module("ross.gear_element")
                mesh_module = gears
            except ImportError:
                gears = importlib.import_module("ross.multi_rotor.gear_element")
                mesh_module = importlib.import_module("ross.multi_rotor.mesh")
        except ImportError as exc:
            pytest.skip(f"ross has no GearElementTVMS and Mesh here: {exc}")
    return units.Q_, materials.Material, gears.GearElementTVMS, mesh_module.Mesh


def ross_values() -> dict:
    """ROSS's TVMS of its example pair, N/m: the mesh over one period at phases i/999 (ROSS's 1000
    angles less the last, which repeats the first phase), its summary, and one tooth (no Hertz) at the
    pressure angles of GOLDEN_ROSS; with its contact ratio and Hertz stiffness."""
    Q_, Material, GearElementTVMS, Mesh = _import_ross()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        material = Material("Gear_steel", rho=Q_(7.81, "g/cm**3"), E=Q_(206, "GPa"), Poisson=NU)
        gear = GearElementTVMS(
            n=0,
            material=material,
            module=Q_(2, "mm"),
            width=Q_(20, "mm"),
            n_teeth=62,
            bore_diameter=Q_(35, "mm"),
            pr_angle=Q_(20, "deg"),
        )
        mesh = Mesh(gear, deepcopy(gear))
        k = np.asarray(mesh.stiffness_range, dtype=float)[:-1]
        tooth = {a: float(gear._compute_stiffness(a)) for a in GOLDEN_ROSS["tooth"]}
        tooth_tip = float(gear._compute_stiffness(gear.pr_angles_dict["addendum"]))
    double = np.arange(len(k)) / len(k) < mesh.contact_ratio - 1
    spectrum = np.fft.rfft(k)
    return {
        "contact_ratio": float(mesh.contact_ratio),
        "hertz": float(mesh.hertzian_stiffness),
        "stiffness": k,
        "mean": float(k.mean()),
        "double_mean": float(k[double].mean()),
        "single_mean": float(k[~double].mean()),
        "max": float(k.max()),
        "min": float(k.min()),
        "harmonics": [round(float(a), 5) for a in 2.0 * np.abs(spectrum[1:5]) / spectrum[0].real],
        "samples": {i: float(k[i]) for i in [*range(0, POINTS, 111), POINTS - 1]},
        "tooth": tooth,
        "tooth_tip": tooth_tip,
    }


def test_against_ross_installed(pair, cycle):
    ross = ross_values()
    k_ross = ross["stiffness"]
    assert len(k_ross) == POINTS
    assert pair.contact_ratio == pytest.approx(ross["contact_ratio"], rel=1e-12)
    assert 1.0 / pair.pair_compliances(pair.pitch_point)["hertz"] == pytest.approx(ross["hertz"], rel=1e-12)
    k = cycle.stiffness
    np.testing.assert_allclose(k, k_ross, rtol=TOL_POINTWISE)
    assert cycle.mean == pytest.approx(ross["mean"], rel=TOL_MEAN)
    double = _double(cycle)
    assert k[double].mean() == pytest.approx(ross["double_mean"], rel=TOL_DOUBLE)
    assert k[~double].mean() == pytest.approx(ross["single_mean"], rel=TOL_SINGLE)
    amplitude, _ = cycle.harmonics(4)
    np.testing.assert_allclose(amplitude, ross["harmonics"], atol=TOL_HARMONICS)
    for angle, want in ross["tooth"].items():
        assert _tooth_stiffness(pair, angle) == pytest.approx(want, rel=TOL_TOOTH)
    tip = math.acos(pair.pinion.base_radius / pair.pinion.tip_radius)
    assert _tooth_stiffness(pair, tip) == pytest.approx(ross["tooth_tip"], rel=TOL_TOOTH)


if __name__ == "__main__":  # regenerates GOLDEN_ROSS (module docstring)
    from pprint import pprint

    pprint({key: value for key, value in ross_values().items() if key != "stiffness"}, sort_dicts=False)
