"""Bad numbers given from Python are refused at the edge, by name (issue: "from Python, a NaN in a
periodic load, or a mount damping of 1e300, runs for ever"; "15 bad Python inputs return NaN or inf
without a word").

Every public constructor and analysis refuses NaN, ±inf and magnitudes no machine has (±1e300) with
a :class:`~mechdyn.errors.MechdynError` whose message names the parameter and shows the value, never
a hang, a traceback from inside numpy or scipy, or a NaN in the result. The two reported hangs run in
a subprocess with a time limit, so that a hang fails the test instead of the suite; the table runs in
process under an alarm (a hang in Python code is interrupted there). The model files bound their
quantities with the Python API's own table (:data:`mechdyn.checks.MAGNITUDE_LIMITS`), checked here
unit by unit.
"""

from __future__ import annotations

import json
import math
import re
import signal
import subprocess
import sys
import textwrap
from dataclasses import replace

import numpy as np
import pytest

from mechdyn import drivetrain as dt
from mechdyn import gears as gr
from mechdyn import mechanism as me
from mechdyn import mounts as mo
from mechdyn import support as su
from mechdyn import vibration as vi
from mechdyn.errors import MechdynError, ModelError

HANG_LIMIT_S = 120  # generous: the machine running the suite may be loaded
CASE_LIMIT_S = 60  # one table case; the refusals take milliseconds


@pytest.fixture(autouse=True)
def _no_hang():
    """Interrupt a test that runs past :data:`CASE_LIMIT_S` (a hang in Python code) with an error."""
    if not hasattr(signal, "setitimer"):
        yield
        return

    def stop(signum, frame):
        raise TimeoutError(f"still running after {CASE_LIMIT_S} s: a hang")

    old = signal.signal(signal.SIGALRM, stop)
    signal.setitimer(signal.ITIMER_REAL, CASE_LIMIT_S)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


# -- the two reported hangs, in a subprocess -------------------------------------------------------

_CHILD = """
import json, sys
import numpy as np
from mechdyn.errors import MechdynError, ModelError
from mechdyn.support import Mount, MountedMachine, PeriodicLoad, RigidBody, startup_response
{body}
try:
    r = run()
except MechdynError as e:
    print(json.dumps({{"refused": True, "type": type(e).__name__, "message": str(e)}}))
except Exception as e:  # a traceback from inside numpy or scipy
    print(json.dumps({{"refused": False, "type": type(e).__name__, "message": str(e)}}))
else:
    summary = r.summary()
    finite = all(np.isfinite(v).all() for v in summary.values() if isinstance(v, float))
    print(json.dumps({{"refused": False, "type": "result", "message": f"finite={{finite}}"}}))
"""


def _run_child(body: str) -> dict:
    code = _CHILD.format(body=textwrap.dedent(body))
    try:
        run = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, timeout=HANG_LIMIT_S
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"still running after {HANG_LIMIT_S} s: the bad input was not refused (a hang)")
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize(
    "make_load",
    [
        "PeriodicLoad.from_harmonics(0.1, {1: float('nan')})",
        "PeriodicLoad.from_harmonics(0.1, {1: 100.0}, mean=float('nan'))",
        "PeriodicLoad(0.1, [[0, 0, 0, 0, 0, 0], [0, 0, float('nan'), 0, 0, 0]])",
    ],
)
def test_nan_in_a_periodic_load_is_refused_not_integrated_for_ever(make_load):
    out = _run_child(
        f"""
        def run():
            machine = MountedMachine.single_dof(100.0, 1e5, 0.05)
            return startup_response(machine, {make_load}, cycles=2)
        """
    )
    assert out["refused"], out
    assert "nan" in out["message"] and "element 'load'" in out["message"]
    assert re.search(r"field '(harmonics\[1\]|mean|coefficients)'", out["message"]), out["message"]


def test_a_mount_damping_of_1e300_is_refused_not_integrated_for_ever():
    out = _run_child(
        """
        def run():
            mount = Mount("pad", (0.0, 0.0, 0.0), (0.0, 0.0, 1e5), (0.0, 0.0, 1e300))
            machine = MountedMachine(RigidBody(100.0), (mount,), ("z",))
            return startup_response(machine, PeriodicLoad.from_harmonics(0.1, {1: 100.0}), cycles=2)
        """
    )
    assert out["refused"], out
    assert "field 'damping'" in out["message"] and "1e+300" in out["message"], out["message"]
    assert "1e+13 N*s/m" in out["message"]  # what is accepted


def test_a_damping_too_stiff_for_an_explicit_method_is_refused_not_integrated_for_ever():
    """1e13 N·s/m is a damping the mounts accept; under 100 kg its mode decays at 1e11 1/s, which
    DOP853 would follow with billions of steps: refused before the integration, naming the method.
    The exact start-up (the default) takes it in its stride."""
    machine = """
            mount = Mount("pad", (0.0, 0.0, 0.0), (0.0, 0.0, 1e5), (0.0, 0.0, 1e13))
            machine = MountedMachine(RigidBody(100.0), (mount,), ("z",))
            load = PeriodicLoad.from_harmonics(0.1, {1: 100.0})"""
    out = _run_child(
        f"""
        def run():{machine}
            return startup_response(machine, load, cycles=2, method="DOP853")
        """
    )
    assert out["refused"], out
    assert "field 'method'" in out["message"] and "DOP853" in out["message"], out["message"]
    exact = _run_child(
        f"""
        def run():{machine}
            return startup_response(machine, load, cycles=2)
        """
    )
    assert not exact["refused"] and exact["message"] == "finite=True", exact


# -- the table: every public API, each numeric argument ----------------------------------------

NAN, INF = float("nan"), float("inf")
BAD = (NAN, INF, -INF, 1e300, -1e300)
NONFINITE = (NAN, INF, -INF)
POSITIVE_BAD = (NAN, INF, -INF, 1e300)  # -1e300: also refused, but as negative (no value check)


def _two_disks() -> dt.Drivetrain:
    return dt.Drivetrain((dt.Disk("a", 1.0), dt.Disk("b", 2.0)), (dt.Shaft("s", ("a", "b"), 1e4),))


def _gear(**kw) -> gr.SpurGear:
    return gr.SpurGear(**{"teeth": 20, "module": 0.002, "face_width": 0.02, **kw})


def _pair() -> gr.GearPair:
    return gr.GearPair(_gear(name="pinion"), _gear(teeth=40))


TOOTH = dict(
    tip_height=0.0046,
    root_height=0.0006,
    tip_thickness=0.003146,
    root_thickness=0.006144,
    face_width=0.05,
    youngs_modulus=206e9,
)


def _fourbar(**kw) -> me.Mechanism:
    """Crank 50 mm about O2, coupler 200 mm, rocker 150 mm about O4 = (200 mm, 0), drawn at 60°."""
    b = (0.05 * math.cos(math.pi / 3), 0.05 * math.sin(math.pi / 3))
    q, r_b, r_c = np.array([0.2, 0.0]), 0.2, 0.15
    d = float(np.linalg.norm(q - b))
    x = (d**2 + r_b**2 - r_c**2) / (2 * d)
    e = (q - b) / d
    c = np.array(b) + x * e + math.sqrt(r_b**2 - x**2) * np.array([-e[1], e[0]])
    base = dict(
        points={"O2": (0.0, 0.0), "B": b, "C": tuple(c), "O4": (0.2, 0.0)},
        bodies=(
            me.Body("crank", ("O2", "B"), 1.0, 1e-3),
            me.Body("coupler", ("B", "C"), 2.0, 1e-2),
            me.Body("rocker", ("C", "O4"), 1.5, 3e-3),
        ),
        joints=(
            me.Revolute("O2", ("ground", "crank"), "O2"),
            me.Revolute("B", ("crank", "coupler"), "B"),
            me.Revolute("C", ("coupler", "rocker"), "C"),
            me.Revolute("O4", ("rocker", "ground"), "O4"),
        ),
        driver=me.Driver("crank", "O2", "B", 10.0),
        gravity=(0.0, -9.81),
    )
    return me.Mechanism(**{**base, **kw})


def _with_force(v: float) -> me.Mechanism:
    force = me.ProcessForce("rocker", "C", lambda th, s: (np.full_like(th, v), 0.0 * th))
    return replace(_fourbar(), process_forces=(force,))


def _profile(v: float) -> me.Driver:
    return me.Driver("crank", "O2", "B", 10.0, lambda psi: np.full_like(psi, v))


DB = mo.default_materials()
STEEL, RUBBER = DB["steel"], DB["rubber shore 50"]


def _joint(**kw) -> mo.BoltedJoint:
    layers = kw.pop("layers", [mo.Layer(0.02, STEEL), mo.Layer(0.04, DB["concrete (published anchor case)"])])
    base = dict(diameter=0.012, head_diameter=0.024, hole_diameter=0.013, nut="anchor")
    return mo.BoltedJoint("joint", layers=layers, bolt_material=DB["bolt steel"], **{**base, **kw})


def _pad() -> mo.ElastomerPad:
    return mo.ElastomerPad("pad", RUBBER, 0.01, diameter=0.1)


ANCHOR = dict(
    plate_thickness=0.02,
    plate_radius=0.06,
    embedment=0.04,
    concrete_radius=0.15,
    hole_diameter=0.013,
    washer_diameter=0.024,
    anchor_head_diameter=0.024,
    plate_E=2.1e11,
    plate_nu=0.3,
    concrete_E=1.8e10,
    concrete_nu=0.2,
    n=4,
)
F_HZ = np.linspace(2.0, 40.0, 20)
H_FRF = 1 / (2.5e6 - 180 * (2 * np.pi * F_HZ) ** 2 + 1j * 2000 * 2 * np.pi * F_HZ)


def _anchor_result() -> mo.AnchorFE:
    from mechdyn.mounts.fe import FEResult

    result = FEResult(1e9, 10, 20, 0.005, 1)
    return mo.AnchorFE(1e9, np.array([0.01, 0.02]), np.array([2.0, 0.0]), 1.0, 0.02, result)


def _single_dof(mass=100.0, stiffness=1e5, zeta=0.05) -> su.MountedMachine:
    return su.MountedMachine.single_dof(mass, stiffness, zeta)


def _load(**kw) -> su.PeriodicLoad:
    return su.PeriodicLoad.from_harmonics(kw.get("period", 0.1), {1: kw.get("amplitude", 100.0)})


def _four_mounts(**kw) -> su.MountedMachine:
    k, c = kw.get("stiffness", (1e5, 1e5, 2e5)), kw.get("damping", (100.0, 100.0, 100.0))
    mounts = tuple(
        su.Mount(f"m{i}", (0.3 * sx, 0.3 * sy, 0.0), k, c)
        for i, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1)))
    )
    return su.MountedMachine(su.RigidBody(100.0, (0.0, 0.0, 0.2), (10.0, 10.0, 10.0)), mounts)


K2 = np.array([[2.0, -1.0], [-1.0, 2.0]])

# (case, field named in the message, call with the bad value, values tried)
TABLE = [
    # drivetrain
    ("Disk", "inertia", lambda v: dt.Disk("a", v), BAD),
    (
        "Disk.from_geometry",
        "thickness",
        lambda v: dt.Disk.from_geometry("a", thickness=v, outer_diameter=0.1, density=7800.0),
        BAD,
    ),
    ("Shaft", "stiffness", lambda v: dt.Shaft("s", ("a", "b"), v), BAD),
    ("Shaft", "damping", lambda v: dt.Shaft("s", ("a", "b"), 1e4, v), BAD),
    (
        "Shaft.from_geometry",
        "shear_modulus",
        lambda v: dt.Shaft.from_geometry("s", ("a", "b"), length=0.5, diameter=0.02, shear_modulus=v),
        BAD,
    ),
    ("GearMesh", "ratio", lambda v: dt.GearMesh("m", ("a", "b"), ratio=v), BAD),
    ("GearMesh", "teeth", lambda v: dt.GearMesh("m", ("a", "b"), teeth=(20, v)), BAD),
    ("GearMesh", "base_radii", lambda v: dt.GearMesh("m", ("a", "b"), base_radii=(0.02, v)), BAD),
    (
        "GearMesh",
        "stiffness",
        lambda v: dt.GearMesh("m", ("a", "b"), base_radii=(0.02, 0.04), stiffness=v),
        BAD,
    ),
    (
        "GearMesh",
        "damping",
        lambda v: dt.GearMesh("m", ("a", "b"), base_radii=(0.02, 0.04), stiffness=1e8, damping=v),
        BAD,
    ),
    (
        "GearMesh.from_gear_pair",
        "points",
        lambda v: dt.GearMesh.from_gear_pair("m", ("a", "b"), _pair(), points=v),
        BAD,
    ),
    ("GroundSpring", "stiffness", lambda v: dt.GroundSpring("g", "a", v), BAD),
    ("GroundDamper", "damping", lambda v: dt.GroundDamper("g", "a", v), BAD),
    ("ModalDamping", "ratio", lambda v: dt.ModalDamping(v), BAD),
    ("ModalDamping", "ratio", lambda v: dt.ModalDamping((0.02, v)), BAD),
    ("RayleighDamping", "alpha", lambda v: dt.RayleighDamping(v, 0.0), BAD),
    ("RayleighDamping", "beta", lambda v: dt.RayleighDamping(0.0, v), BAD),
    ("RayleighDamping.from_ratios", "f1_hz", lambda v: dt.RayleighDamping.from_ratios(v, 100.0, 0.02), BAD),
    ("RayleighDamping.from_ratios", "zeta", lambda v: dt.RayleighDamping.from_ratios(10.0, 100.0, v), BAD),
    ("frf", "frequencies_hz", lambda v: dt.frf(_two_disks(), [1.0, v], {"a": 1.0}), BAD),
    ("frf", "excitation", lambda v: dt.frf(_two_disks(), [1.0, 2.0], {"a": v}), BAD),
    ("frf", "excitation", lambda v: dt.frf(_two_disks(), [1.0, 2.0], {"a": complex(v, 1.0)}), BAD),
    ("campbell", "speed_range", lambda v: dt.campbell(_two_disks(), (0.0, v)), BAD),
    (
        "campbell",
        "shaft_orders",
        lambda v: dt.campbell(_two_disks(), (0.0, 100.0), shaft_orders=(1.0, v)),
        BAD,
    ),
    ("campbell", "mesh_orders", lambda v: dt.campbell(_two_disks(), (0.0, 100.0), mesh_orders=(v,)), BAD),
    ("compare_rigid", "threshold", lambda v: dt.compare_rigid(_two_disks(), threshold=v), BAD),
    ("mac", "a", lambda v: dt.mac(np.array([[1.0, v], [0.0, 1.0]]), np.eye(2)), NONFINITE),
    # gears
    ("SpurGear", "teeth", lambda v: _gear(teeth=v), BAD),
    ("SpurGear", "module", lambda v: _gear(module=v), BAD),
    ("SpurGear", "face_width", lambda v: _gear(face_width=v), BAD),
    ("SpurGear", "pressure_angle", lambda v: _gear(pressure_angle=v), BAD),
    ("SpurGear", "profile_shift", lambda v: _gear(profile_shift=v), BAD),
    ("SpurGear", "addendum", lambda v: _gear(addendum=v), BAD),
    ("SpurGear", "dedendum", lambda v: _gear(dedendum=v), BAD),
    ("SpurGear", "youngs_modulus", lambda v: _gear(youngs_modulus=v), BAD),
    ("SpurGear", "poisson_ratio", lambda v: _gear(poisson_ratio=v), BAD),
    ("SpurGear", "bore_diameter", lambda v: _gear(bore_diameter=v), BAD),
    ("SpurGear.thickness", "radius", lambda v: _gear().thickness(v), BAD),
    (
        "GearPair",
        "center_distance",
        lambda v: gr.GearPair(_gear(name="pinion"), _gear(teeth=40), center_distance=v),
        BAD,
    ),
    ("GearPair.mesh_cycle", "points", lambda v: _pair().mesh_cycle(v), BAD),
    ("GearPair.pair_stiffness", "s", lambda v: _pair().pair_stiffness(v), BAD),
    ("iso_stiffness", "specific_load", lambda v: gr.iso_stiffness(_pair(), specific_load=v), BAD),
    ("iso_stiffness", "rim_thickness_ratio", lambda v: gr.iso_stiffness(_pair(), rim_thickness_ratio=v), BAD),
    ("iso_stiffness", "web_width_ratio", lambda v: gr.iso_stiffness(_pair(), web_width_ratio=v), BAD),
    ("IsoStiffness.mesh_stiffness", "face_width", lambda v: gr.iso_stiffness(_pair()).mesh_stiffness(v), BAD),
    ("TruncatedTooth", "face_width", lambda v: gr.TruncatedTooth(**{**TOOTH, "face_width": v}), BAD),
    ("TruncatedTooth", "youngs_modulus", lambda v: gr.TruncatedTooth(**{**TOOTH, "youngs_modulus": v}), BAD),
    ("TruncatedTooth", "poisson_ratio", lambda v: gr.TruncatedTooth(**TOOTH, poisson_ratio=v), BAD),
    ("TruncatedTooth.thickness", "height", lambda v: gr.TruncatedTooth(**TOOTH).thickness(v), BAD),
    (
        "TruncatedTooth.compliance",
        "load_angle",
        lambda v: gr.TruncatedTooth(**TOOTH).compliance(0.0026, v),
        BAD,
    ),
    ("hertz_compliance", "face_width", lambda v: gr.hertz_compliance(v, 206e9, 0.3), BAD),
    ("hertz_compliance", "e1", lambda v: gr.hertz_compliance(0.05, v, 0.3), BAD),
    ("hertz_compliance", "nu1", lambda v: gr.hertz_compliance(0.05, 206e9, v), BAD),
    ("hertz_compliance", "nu2", lambda v: gr.hertz_compliance(0.05, 206e9, 0.3, 110e9, v), BAD),
    # mechanism
    ("Body", "mass", lambda v: me.Body("b", ("A",), v, 0.0), BAD),
    ("Body", "inertia", lambda v: me.Body("b", ("A",), 1.0, v), BAD),
    ("Body", "center_of_mass", lambda v: me.Body("b", ("A",), 1.0, 0.1, (v, 0.0)), BAD),
    ("Driver", "speed", lambda v: me.Driver("crank", "O2", "B", v), BAD),
    ("Driver", "profile", _profile, BAD),
    ("Mechanism", "position", lambda v: _fourbar(points={**_fourbar().points, "O4": (v, 0.0)}), BAD),
    ("Mechanism", "gravity", lambda v: _fourbar(gravity=(0.0, v)), BAD),
    ("Mechanism", "angle_datum", lambda v: _fourbar(angle_datum=v), BAD),
    ("Prismatic", "axis", lambda v: me.Prismatic("p", ("a", "b"), "A", v), BAD),
    ("kinematics", "n_angles", lambda v: me.kinematics(_fourbar(), v), BAD),
    ("inverse_dynamics", "n_angles", lambda v: me.inverse_dynamics(_fourbar(), v), BAD),
    ("dyad_motion", "n_angles", lambda v: me.dyad_motion(_fourbar(), v), BAD),
    ("newton_motion", "n_angles", lambda v: me.newton_motion(_fourbar(), v), BAD),
    ("cycle", "n_angles", lambda v: me.cycle(_fourbar(), v), BAD),
    ("variants", "n_angles", lambda v: me.variants([_fourbar(), _fourbar()], v), BAD),
    ("DesignBatch.run", "n_angles", lambda v: me.DesignBatch.run([_fourbar(), _fourbar()], v), BAD),
    ("cycle", "masses", lambda v: me.cycle(_fourbar(), 36, masses={"crank": [1.0, v]}), BAD),
    ("cycle", "inertias", lambda v: me.cycle(_fourbar(), 36, inertias={"crank": [1e-3, v]}), BAD),
    ("cycle", "points", lambda v: me.cycle(_fourbar(), 36, points={"O4": [(0.2, 0.0), (v, 0.0)]}), BAD),
    ("ProcessForce", "force", lambda v: me.inverse_dynamics(_with_force(v), 36), BAD),
    ("ProcessForce", "force", lambda v: me.cycle(_with_force(v), 36), BAD),
    (
        "DynamicsResult.shaking_moment",
        "about",
        lambda v: me.inverse_dynamics(_fourbar(), 36).shaking_moment((v, 0.0)),
        BAD,
    ),
    ("CycleBatch.shaking_moment", "about", lambda v: me.cycle(_fourbar(), 36).shaking_moment((0.0, v)), BAD),
    ("PlanterDesign", "eccentricity_ratio", lambda v: me.PlanterDesign(eccentricity_ratio=v), BAD),
    ("PlanterDesign", "arm_radius", lambda v: me.PlanterDesign(arm_radius=v), BAD),
    ("PlanterDesign", "fork_angle", lambda v: me.PlanterDesign(fork_angle=v), BAD),
    ("PlanterDesign", "com_offset", lambda v: me.PlanterDesign(com_offset=v), BAD),
    ("PlanterDesign", "planet_mass", lambda v: me.PlanterDesign(planet_mass=v), BAD),
    ("PlanterDesign", "planet_inertia", lambda v: me.PlanterDesign(planet_inertia=v), BAD),
    ("PlanterDesign", "speed", lambda v: me.PlanterDesign(speed=v), BAD),
    ("PlanterDesign", "gravity", lambda v: me.PlanterDesign(gravity=v), BAD),
    # mounts
    ("Material", "youngs_modulus", lambda v: mo.Material("x", "steel", v, 0.3), BAD),
    ("Material", "shear_modulus", lambda v: mo.Material("x", "steel", 2e11, 0.3, shear_modulus=v), BAD),
    ("Material", "bulk_modulus", lambda v: mo.Material("x", "steel", 2e11, 0.3, bulk_modulus=v), BAD),
    ("Material", "shore_a", lambda v: mo.Material("r", "rubber", 2e6, 0.4999, shore_a=v), BAD),
    ("MaterialDatabase.rubber", "shore_a", lambda v: DB.rubber(v), BAD),
    ("ElastomerPad", "thickness", lambda v: mo.ElastomerPad("p", RUBBER, v, diameter=0.1), BAD),
    (
        "ElastomerPad",
        "compression_coefficient",
        lambda v: mo.ElastomerPad("p", RUBBER, 0.01, diameter=0.1, compression_coefficient=v),
        BAD,
    ),
    ("ElastomerPad.compression_force", "deflection", lambda v: _pad().compression_force(v), BAD),
    ("ElastomerPad.tangent_stiffness", "deflection", lambda v: _pad().tangent_stiffness([0.0, v]), BAD),
    ("Layer", "thickness", lambda v: mo.Layer(v, STEEL), BAD),
    ("BoltedJoint", "diameter", lambda v: _joint(diameter=v), BAD),
    ("BoltedJoint", "cone_angle", lambda v: _joint(cone_angle=v), BAD),
    ("BoltedJoint", "pitch", lambda v: _joint(pitch=v), BAD),
    ("BoltedJoint", "stress_area", lambda v: _joint(stress_area=v), BAD),
    ("BoltedJoint.member_stiffness", "alpha", lambda v: _joint().member_stiffness(v), BAD),
    ("BoltedJoint.bolt_stiffness_vdi2230", "shank_length", lambda v: _joint().bolt_stiffness_vdi2230(v), BAD),
    ("SpringIsolator", "active_coils", lambda v: mo.SpringIsolator("s", 0.008, 0.06, v, STEEL), BAD),
    ("SpringIsolator", "springs", lambda v: mo.SpringIsolator("s", 0.008, 0.06, 6, STEEL, springs=v), BAD),
    (
        "SpringIsolator",
        "loss_factor",
        lambda v: mo.SpringIsolator("s", 0.008, 0.06, 6, STEEL, loss_factor=v),
        BAD,
    ),
    ("ScrewFoot", "pitch", lambda v: mo.ScrewFoot("f", 0.02, 0.05, STEEL, pitch=v), BAD),
    (
        "LevellingWedge",
        "loss_factor",
        lambda v: mo.LevellingWedge("w", 0.01, 0.05, STEEL, loss_factor=v),
        BAD,
    ),
    ("DampingPad", "loss_factor", lambda v: mo.DampingPad("d", _pad(), loss_factor=v), BAD),
    ("isolation", "stiffness", lambda v: mo.isolation(v, 1000.0, 30.0), BAD),
    ("isolation", "load", lambda v: mo.isolation(1e6, v, 30.0), BAD),
    ("isolation", "disturbing_frequency", lambda v: mo.isolation(1e6, 1000.0, v), BAD),
    ("isolation", "loss_factor", lambda v: mo.isolation(1e6, 1000.0, 30.0, v), BAD),
    ("frustum_stiffness", "E", lambda v: mo.frustum_stiffness(v, 0.01, 0.015, 0.02, 0.5), BAD),
    ("frustum_stiffness", "d", lambda v: mo.frustum_stiffness(207e9, v, 0.015, 0.02, 0.5), BAD),
    ("frustum_stiffness", "t", lambda v: mo.frustum_stiffness(207e9, 0.01, 0.015, v, 0.5), BAD),
    ("frustum_stiffness", "alpha", lambda v: mo.frustum_stiffness(207e9, 0.01, 0.015, 0.02, v), BAD),
    ("vdi2230_cone_angle", "grip", lambda v: mo.vdi2230_cone_angle(v, 0.02, 0.06), BAD),
    ("vdi2230_cone_angle", "bearing_diameter", lambda v: mo.vdi2230_cone_angle(0.03, v, 0.06), BAD),
    ("vdi2230_cone_angle", "outer_diameter", lambda v: mo.vdi2230_cone_angle(0.03, 0.02, v), BAD),
    (
        "anchor_members",
        "plate_thickness",
        lambda v: mo.anchor_members(**{**ANCHOR, "plate_thickness": v}),
        BAD,
    ),
    (
        "anchor_members",
        "concrete_radius",
        lambda v: mo.anchor_members(**{**ANCHOR, "concrete_radius": v}),
        BAD,
    ),
    ("anchor_members", "plate_E", lambda v: mo.anchor_members(**{**ANCHOR, "plate_E": v}), BAD),
    ("anchor_members", "concrete_nu", lambda v: mo.anchor_members(**{**ANCHOR, "concrete_nu": v}), BAD),
    ("anchor_members", "n", lambda v: mo.anchor_members(**{**ANCHOR, "n": v}), BAD),
    ("anchor_members", "max_iterations", lambda v: mo.anchor_members(**ANCHOR, max_iterations=v), BAD),
    ("pad_compression", "diameter", lambda v: mo.pad_compression(v, 0.05, 2e6, 0.45, n=3), BAD),
    ("pad_compression", "thickness", lambda v: mo.pad_compression(0.08, v, 2e6, 0.45, n=3), BAD),
    ("pad_compression", "youngs_modulus", lambda v: mo.pad_compression(0.08, 0.05, v, 0.45, n=3), BAD),
    ("pad_compression", "n", lambda v: mo.pad_compression(0.08, 0.05, 2e6, 0.45, n=v), BAD),
    ("fit_frf", "frequency", lambda v: mo.fit_frf(np.r_[F_HZ[:-1], v], H_FRF), BAD),
    ("fit_frf", "response", lambda v: mo.fit_frf(F_HZ, np.r_[H_FRF[:-1], v]), BAD),
    ("fit_cone_angle", "target", lambda v: mo.fit_cone_angle(_joint(), v, "test"), BAD),
    ("fit_pad_factor", "target", lambda v: mo.fit_pad_factor(_pad(), v, "test"), BAD),
    ("SdofFit.receptance", "frequency", lambda v: mo.fit_frf(F_HZ, H_FRF).receptance(v), BAD),
    ("AnchorFE.pressure", "preload", lambda v: _anchor_result().pressure(v), BAD),
    ("AnchorFE.radius_above", "threshold", lambda v: _anchor_result().radius_above(v, 1000.0), BAD),
    # support
    ("RigidBody", "mass", lambda v: su.RigidBody(v), BAD),
    ("RigidBody", "center_of_mass", lambda v: su.RigidBody(1.0, (0.0, 0.0, v)), BAD),
    ("RigidBody", "inertia", lambda v: su.RigidBody(1.0, (0.0, 0.0, 0.0), (1.0, 1.0, v)), BAD),
    ("Mount", "position", lambda v: su.Mount("a", (0.0, 0.0, v), (1e5, 1e5, 1e5)), BAD),
    ("Mount", "stiffness", lambda v: su.Mount("a", (0.0, 0.0, 0.0), (1e5, 1e5, v)), BAD),
    ("Mount", "damping", lambda v: su.Mount("a", (0.0, 0.0, 0.0), (1e5, 1e5, 1e5), (0.0, 0.0, v)), BAD),
    (
        "Mount",
        "axes",
        lambda v: su.Mount("a", (0.0, 0.0, 0.0), (1e5, 1e5, 1e5), axes=[[1, 0, 0], [0, 1, 0], [0, 0, v]]),
        BAD,
    ),
    (
        "Mount.with_orientation",
        "orientation",
        lambda v: su.Mount.with_orientation("a", (0, 0, 0), (1e5, 1e5, 1e5), (0.0, v, 0.0)),
        BAD,
    ),
    ("MountedMachine", "gravity", lambda v: replace(_four_mounts(), gravity=v), BAD),
    ("MountedMachine.single_dof", "mass", lambda v: _single_dof(mass=v), BAD),
    ("MountedMachine.single_dof", "stiffness", lambda v: _single_dof(stiffness=v), BAD),
    ("MountedMachine.single_dof", "damping_ratio", lambda v: _single_dof(zeta=v), BAD),
    ("MountedMachine.scaled", "stiffness", lambda v: _four_mounts().scaled(stiffness=v), BAD),
    ("MountedMachine.scaled", "damping", lambda v: _four_mounts().scaled(damping=v), BAD),
    ("PeriodicLoad", "period", lambda v: su.PeriodicLoad(v, np.ones((2, 6))), BAD),
    (
        "PeriodicLoad",
        "coefficients",
        lambda v: su.PeriodicLoad(0.1, [[0, 0, 1, 0, 0, 0], [0, 0, v, 0, 0, 0]]),
        BAD,
    ),
    ("PeriodicLoad", "n_samples", lambda v: su.PeriodicLoad(0.1, np.ones((2, 6)), n_samples=v), BAD),
    ("PeriodicLoad.from_samples", "samples", lambda v: su.PeriodicLoad.from_samples(0.1, [1.0, v, 3.0]), BAD),
    (
        "PeriodicLoad.from_samples",
        "angle",
        lambda v: su.PeriodicLoad.from_samples(0.1, [1.0, 2.0, 3.0], angle=[0.0, 1.0, v]),
        BAD,
    ),
    (
        "PeriodicLoad.from_times",
        "time",
        lambda v: su.PeriodicLoad.from_times(0.1, [0.0, 0.03, v], [1.0, 2.0, 3.0]),
        BAD,
    ),
    (
        "PeriodicLoad.from_times",
        "n",
        lambda v: su.PeriodicLoad.from_times(0.1, [0.0, 0.03, 0.06], [1.0, 2.0, 3.0], n=v),
        BAD,
    ),
    ("PeriodicLoad.from_harmonics", "period", lambda v: _load(period=v), BAD),
    ("PeriodicLoad.from_harmonics", "harmonics", lambda v: _load(amplitude=v), BAD),
    (
        "PeriodicLoad.from_harmonics",
        "harmonics",
        lambda v: su.PeriodicLoad.from_harmonics(0.1, {v: 1.0}),
        BAD,
    ),
    (
        "PeriodicLoad.from_harmonics",
        "mean",
        lambda v: su.PeriodicLoad.from_harmonics(0.1, {1: 1.0}, mean=v),
        BAD,
    ),
    ("PeriodicLoad.value", "t", lambda v: _load().value(v), BAD),
    ("PeriodicLoad.time", "n", lambda v: _load().time(v), BAD),
    ("PeriodicLoad.scaled", "factor", lambda v: _load().scaled(v), BAD),
    ("Placement", "origin", lambda v: su.Placement((v, 0.0, 0.0)), BAD),
    (
        "periodic_response",
        "n_samples",
        lambda v: su.periodic_response(_single_dof(), _load(), n_samples=v),
        BAD,
    ),
    ("periodic_response", "time", lambda v: su.periodic_response(_single_dof(), _load(), time=[0.0, v]), BAD),
    ("startup_response", "cycles", lambda v: su.startup_response(_single_dof(), _load(), cycles=v), BAD),
    (
        "startup_response",
        "steps_per_period",
        lambda v: su.startup_response(_single_dof(), _load(), cycles=1, steps_per_period=v),
        BAD,
    ),
    (
        "startup_response",
        "rtol",
        lambda v: su.startup_response(_single_dof(), _load(), cycles=1, rtol=v),
        BAD,
    ),
    (
        "SupportResponse.displacement_at",
        "position",
        lambda v: su.periodic_response(_four_mounts(), _load()).displacement_at((v, 0.0, 0.0)),
        BAD,
    ),
    # vibration
    (
        "harmonic_solve",
        "omega",
        lambda v: vi.harmonic_solve(K2, 0 * K2, np.eye(2), [1.0, 0.0], [0.5, v]),
        BAD,
    ),
    ("harmonic_solve", "F", lambda v: vi.harmonic_solve(K2, 0 * K2, np.eye(2), [1.0, v], [0.5]), NONFINITE),
    (
        "harmonic_solve",
        "K",
        lambda v: vi.harmonic_solve(np.array([[2.0, -1.0], [-1.0, v]]), 0 * K2, np.eye(2), [1.0, 0.0], [0.5]),
        NONFINITE,
    ),
    ("dynamic_stiffness", "omega", lambda v: vi.dynamic_stiffness(K2, 0 * K2, np.eye(2), v), BAD),
    (
        "check_matrices",
        "K",
        lambda v: vi.check_matrices(
            np.eye(2), np.array([[2.0, -1.0], [-1.0, v]]), expected_rigid_body_modes=0
        ),
        NONFINITE,
    ),
    (
        "check_matrices",
        "rtol",
        lambda v: vi.check_matrices(np.eye(2), K2, expected_rigid_body_modes=0, rtol=v),
        BAD,
    ),
]


def _shown(v: float) -> str:
    """The value as the messages print it (``format(v, "g")``)."""
    return f"{v:g}"


def _cases():
    seen: dict[str, int] = {}
    for case, field, call, values in TABLE:
        key = f"{case}-{field}"
        seen[key] = seen.get(key, 0) + 1
        name = key if seen[key] == 1 else f"{key}#{seen[key]}"
        for v in values:
            yield pytest.param(field, call, v, id=f"{name}={_shown(v)}")


@pytest.mark.filterwarnings("ignore:.*range of the Sainsot fit:mechdyn.errors.ModelWarning")
@pytest.mark.parametrize(("field", "call", "value"), list(_cases()))
def test_a_bad_number_is_refused_naming_the_field_and_the_value(field, call, value):
    with pytest.raises(MechdynError) as info:
        call(value)
    message = str(info.value)
    assert re.search(rf"\b{re.escape(field)}\b", message), message
    shown = _shown(value)
    # the value as printed, not a longer number that contains it ("-inf" is not "inf")
    assert re.search(rf"(?<![\w.+-]){re.escape(shown)}(?![\w.])", message), message


# -- good values at the edges still work -------------------------------------------------------


def _finite(x) -> bool:
    if isinstance(x, tuple):
        return all(_finite(part) for part in x)
    a = np.asarray(x, dtype=complex)
    return a.size > 0 and bool(np.isfinite(a).all())


EDGES = [
    (
        "inertias from 1e-18 to 1e10 kg·m²",
        lambda: (
            dt.modal(
                dt.Drivetrain((dt.Disk("a", 1e-18), dt.Disk("b", 1e10)), (dt.Shaft("s", ("a", "b"), 1.0),))
            ).omega
        ),
    ),
    ("stiffness 1e14 N·m/rad, damping 0", lambda: dt.Shaft("s", ("a", "b"), 1e14, 0.0).stiffness),
    (
        "gear ratios 1e-4 and 1e4",
        lambda: (
            dt.GearMesh("m", ("a", "b"), ratio=1e-4).ratio,
            dt.GearMesh("n", ("a", "b"), ratio=1e4).ratio,
        ),
    ),
    (
        "frf at 0 Hz on a grounded drivetrain and at 1e7 Hz",
        lambda: (
            dt.frf(
                dt.Drivetrain((dt.Disk("a", 1.0),), (dt.GroundSpring("g", "a", 1e4),)), [0.0, 1e7], {"a": 1.0}
            ).angles
        ),
    ),
    ("mode shapes of any scale", lambda: dt.mac(np.array([[1e300], [2e300]]), np.array([[1.0], [2.0]]))),
    ("a gear of 10 000 teeth", lambda: _gear(teeth=10_000).pitch_radius),
    ("Poisson's ratio near both ends", lambda: gr.hertz_compliance(0.05, 206e9, -0.99, 206e9, 0.499)),
    ("4 and 1000 crank angles", lambda: (me.kinematics(_fourbar(), 4).q, me.kinematics(_fourbar(), 1000).q)),
    (
        "massless links",
        lambda: (
            me.inverse_dynamics(
                _fourbar(bodies=tuple(replace(b, mass=0.0, inertia=0.0) for b in _fourbar().bodies)), 36
            ).multipliers
        ),
    ),
    (
        "a slow crank, 1e-6 rad/s",
        lambda: me.inverse_dynamics(_fourbar(driver=me.Driver("crank", "O2", "B", 1e-6)), 36).multipliers,
    ),
    ("a 1e8 kg machine on 1e15 N/m, ζ = 10", lambda: su.modes(_single_dof(1e8, 1e15, 10.0)).omega),
    (
        "a damping of 1e13 N·s/m by the convolution integral",
        lambda: (
            su.startup_response(
                su.MountedMachine(
                    su.RigidBody(100.0), (su.Mount("a", (0, 0, 0), (0, 0, 1e5), (0, 0, 1e13)),), ("z",)
                ),
                _load(),
                cycles=2,
                method="duhamel",
            ).displacement
        ),
    ),
    (
        "a zero load",
        lambda: (
            su.periodic_response(_single_dof(), su.PeriodicLoad.from_harmonics(0.1, {1: 0.0})).displacement
        ),
    ),
    ("a loss factor of 1.99", lambda: mo.isolation(1e6, 1000.0, 30.0, 1.99)["transmissibility"]),
    ("a cone angle of 1°", lambda: _joint(cone_angle="1 deg").member_stiffness()),
    ("a pad deflected to 0.99 of its thickness", lambda: _pad().compression_force([0.0, 0.0099])),
]


@pytest.mark.parametrize("compute", [pytest.param(f, id=name) for name, f in EDGES])
def test_good_values_at_the_edges_still_work(compute):
    assert _finite(compute())


# -- one table of magnitude limits for the Python API and the model files ------------------------


def test_the_model_files_take_their_magnitude_limits_from_the_python_api():
    from mechdyn import checks
    from mechdyn.io import fields

    assert fields.MAGNITUDE_LIMITS is checks.MAGNITUDE_LIMITS
    assert fields.DEFAULT_LIMIT == checks.DEFAULT_LIMIT


def _limits():
    from mechdyn.io.fields import MAGNITUDE_LIMITS  # the model files' table (the Python API's own)

    return [pytest.param(u, lim, id=u or "dimensionless") for u, lim in sorted(MAGNITUDE_LIMITS.items())]


@pytest.mark.parametrize(("unit", "limit"), _limits())
def test_a_model_file_and_a_constructor_accept_and_refuse_the_same_magnitudes(unit, limit):
    from pydantic import TypeAdapter, ValidationError

    from mechdyn.errors import ModelError
    from mechdyn.io.fields import quantity
    from mechdyn.units import si_field

    read = TypeAdapter(quantity(unit)).validate_python
    text = (lambda x: f"{x!r} {unit}") if unit else repr
    assert read(text(limit)) == pytest.approx(limit)
    assert si_field("element", "field", limit, unit) == limit
    over = limit * 1.01
    with pytest.raises(ValidationError, match="beyond any machine"):
        read(text(over))
    with pytest.raises(ModelError, match="beyond any machine"):
        si_field("element", "field", over, unit)


@pytest.mark.parametrize("n_modes", [float("nan"), float("inf"), 0, -1, 1.5])
def test_a_number_of_modes_that_is_no_count_is_refused(n_modes):
    from mechdyn.drivetrain import Disk, Drivetrain, Shaft, modal

    pair = Drivetrain(
        [Disk("a", "1 kg*m^2"), Disk("b", "2 kg*m^2")], [Shaft("s", ("a", "b"), "1000 N*m/rad")]
    )
    with pytest.raises(ModelError, match=r"field 'n_modes': .* between 1 and"):
        modal(pair, n_modes=n_modes)


@pytest.mark.parametrize(
    ("mass", "match"),
    [([1.0, float("nan")], "not finite"), ([1.0, 0.0], "positive mass"), ([1.0, -2.0], "positive")],
)
def test_the_eigen_solver_refuses_a_mass_that_is_not_positive_and_finite(mass, match):
    import scipy.sparse as sp

    from mechdyn.vibration.eigen import solve_eigen

    with pytest.raises(ModelError, match=match):
        solve_eigen(sp.csr_array(np.array([[1.0, -1.0], [-1.0, 1.0]])), np.array(mass))
