"""The example models of ``mechdyn new``'s templates: for each file type a small sound model (its
values, written as given), example values for the fields and tables it leaves out (written commented
out), notes on tables, and the command that runs it.

The values are what a file holds: quantities as strings with their units. Each example is loaded and
run by the tests (``tests/test_model_templates.py``), so a change to a schema that breaks one shows
at once. A new file type adds its :class:`TemplateExample` to :data:`EXAMPLES`
(:func:`register_template_example`); without one its template has placeholders to fill in.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

__all__ = ["EXAMPLES", "TemplateExample", "register_template_example"]


@dataclass(frozen=True)
class TemplateExample:
    """The example model of one file type's template.

    Attributes
    ----------
    model : mapping
        The file's data as written (tables, arrays of tables, values with their units): a small model
        that loads and whose analysis runs.
    hints : mapping of str to mapping
        By table path (``"meshes"``, ``"gear_pairs.pinion"``): example values of fields the model
        leaves out, written commented out (for a field without a default, or a table not given).
    notes : mapping of str to str
        By table path: a comment written above the table (alternatives, what the example chose).
    run : str
        The command that runs the file (``FILE`` stands for its path).
    intro : str
        What the example model is, for the template's first comment.
    """

    model: Mapping[str, Any]
    hints: Mapping[str, Any] = field(default_factory=dict)
    notes: Mapping[str, str] = field(default_factory=dict)
    run: str = ""
    intro: str = ""


def register_template_example(file_type: str, example: TemplateExample) -> None:
    """Give a file type's template its example model.

    Parameters
    ----------
    file_type : str
        The ``[model] type`` (or ``"study"``).
    example : TemplateExample
        The example model, hints and notes.
    """
    EXAMPLES[file_type] = example


_GEAR_EXTRAS = {
    "helix_angle": "0 deg",
    "bore_diameter": "30 mm",
    "rim_thickness": "6 mm",
    "web_width": "6 mm",
    "rim_supports": 6,
    "youngs_modulus": "206 GPa",
    "poisson_ratio": 0.3,
}

_DRIVETRAIN = TemplateExample(
    intro="The example: a motor driving a load disk through a shaft (two disks, one shaft), with the "
    "tables of the Campbell diagram and the forced response. A gear mesh, gear data, grounded springs "
    "and dampers are shown commented out.",
    run="mechdyn modal FILE   (also: mechdyn campbell FILE, mechdyn frf FILE)",
    model={
        "model": {
            "type": "drivetrain",
            "name": "two-disk drivetrain",
            "description": "a motor driving a load disk through a shaft (template of mechdyn new)",
        },
        "disks": [
            {"name": "motor", "inertia": "0.02 kg*m^2"},
            {"name": "load", "inertia": "0.5 kg*m^2"},
        ],
        "shafts": [{"name": "shaft", "disks": ["motor", "load"], "stiffness": "2e4 N*m/rad"}],
        "campbell": {"speed_range": ["0 rpm", "3000 rpm"], "reference_disk": "motor", "shaft_orders": [1, 2]},
        "response": {
            "excitation": [{"disk": "motor", "amplitude": "10 N*m"}],
            "frequency_range": ["1 Hz", "500 Hz"],
            "points": 500,
            "outputs": ["motor", "load"],
            "modal_damping": 0.02,
        },
    },
    hints={
        "model": {"source": "the drawing, a publication or a measurement"},
        "material": {"density": "7850 kg/m^3", "shear_modulus": "80 GPa"},
        "disks": {"thickness": "20 mm", "outer_diameter": "200 mm", "density": "7850 kg/m^3"},
        "shafts": {
            "length": "500 mm",
            "diameter": "30 mm",
            "shear_modulus": "80 GPa",
            "damping": "0 N*m*s/rad",
            "density": "7850 kg/m^3",
            "inertia": "3.1e-4 kg*m^2",
            "mass_model": "consistent",
            "elements": 4,
        },
        "meshes": {
            "name": "mesh",
            "disks": ["load", "output"],
            "kind": "external",
            "teeth": [20, 60],
            "ratio": 3.0,
            "base_radii": ["18.79 mm", "56.38 mm"],
            "stiffness": "3e8 N/m",
            "gear_pair": "pair",
            "backlash": "60 um",
            "transmission_error": "5 um",
        },
        "meshes.stiffness_variation": {"fluctuation": 0.3, "contact_ratio": 1.6},
        "motor": {
            "disk": "motor",
            "type": "induction",
            "power": "4 kW",
            "synchronous_speed": "1500 rpm",
            "rated_speed": "1440 rpm",
            "pullout_ratio": 2.8,
            "curve": [["0 rpm", "60 N*m"], ["1440 rpm", "26.5 N*m"], ["1500 rpm", "0 N*m"]],
            "ratio": 1.0,
            "direction": 1,
        },
        "loads": {
            "kind": "ramp",
            "disk": "load",
            "torque": "-20 N*m",
            "initial_torque": "0 N*m",
            "time": "1 s",
            "start": "0.5 s",
            "end": "0.8 s",
            "rows": [["0 s", "0 N*m"], ["0.5 s", "-20 N*m"]],
            "amplitude": "2 N*m",
            "frequency": "50 Hz",
            "phase": "0 deg",
            "brake": "40 N*m",
            "hold_speed": "0.01 rad/s",
        },
        "simulation": {
            "duration": "2 s",
            "initial_speed": "0 rpm",
            "reference": "motor",
            "start": "rest",
            "output_step": "1 ms",
            "method": "LSODA",
            "rtol": 1e-7,
            "cycle_steps": 8,
        },
        "speed_sweep": {
            "speed_range": ["500 rpm", "3000 rpm"],
            "points": 60,
            "reference": "motor",
            "harmonics": 16,
            "backlash": True,
            "direction": "up",
        },
        "gear_pairs": {"name": "pair", "center_distance": "80 mm"},
        "gear_pairs.pinion": {"teeth": 20, "module": "2 mm", "face_width": "20 mm", **_GEAR_EXTRAS},
        "gear_pairs.gear": {"teeth": 60, "module": "2 mm", "face_width": "20 mm", **_GEAR_EXTRAS},
        "ground_springs": {"name": "coupling", "disk": "motor", "stiffness": "1e3 N*m/rad"},
        "ground_dampers": {"name": "drag", "disk": "load", "damping": "0.5 N*m*s/rad"},
        "response.rayleigh": {"alpha": "0.5 1/s", "beta": "1e-5 s"},
    },
    notes={
        "disks": "Each disk by its inertia, or by its geometry (thickness and outer_diameter, with a "
        "density here or in [material]).",
        "meshes": "A mesh by its teeth or ratio (rigid), with base_radii and stiffness (flexible), or by "
        "gear_pair = the name of a [[gear_pairs]] row. A mesh needs both its disks: add a [[disks]] "
        'row "output" before uncommenting this one. backlash, transmission_error and '
        "stiffness_variation are read by mechdyn simulate only.",
        "motor": "mechdyn simulate: a motor on a disk, by its rating (Kloss's formula) or, with type = "
        '"curve", its torque-speed curve; with [simulation] this template runs mechdyn simulate FILE.',
        "loads": "mechdyn simulate: a torque on a disk; kind says which fields it reads (a ramp: torque, "
        "start, end, initial_torque).",
        "speed_sweep": "mechdyn speed-sweep: the periodic steady state over the speed of the reference "
        "disk; the [[loads]] rows' final torques load the train.",
    },
)

_FOURBAR_POINTS = {
    "O2": ["0 mm", "0 mm"],
    "A": ["25.000000 mm", "43.301270 mm"],
    "B": ["194.608480 mm", "149.286946 mm"],
    "O4": ["180 mm", "0 mm"],
}

_MECHANISM = TemplateExample(
    intro="The example: a crank-rocker four-bar (crank 50 mm, coupler 200 mm, rocker 150 mm, frame "
    "180 mm), the crank drawn at 60° on the open branch, turning at 12 rad/s, with gravity along -y.",
    run="mechdyn mechanism FILE",
    model={
        "model": {"type": "mechanism", "name": "crank-rocker four-bar"},
        "points": _FOURBAR_POINTS,
        "bodies": [
            {"name": "crank", "points": ["O2", "A"], "mass": "0.3 kg", "inertia": "6.25e-5 kg*m^2"},
            {"name": "coupler", "points": ["A", "B"], "mass": "1.2 kg", "inertia": "4.0e-3 kg*m^2"},
            {"name": "rocker", "points": ["B", "O4"], "mass": "0.9 kg", "inertia": "1.6875e-3 kg*m^2"},
        ],
        "joints": [
            {"name": "O2", "type": "revolute", "bodies": ["ground", "crank"], "point": "O2"},
            {"name": "A", "type": "revolute", "bodies": ["crank", "coupler"], "point": "A"},
            {"name": "B", "type": "revolute", "bodies": ["coupler", "rocker"], "point": "B"},
            {"name": "O4", "type": "revolute", "bodies": ["rocker", "ground"], "point": "O4"},
        ],
        "driver": {"body": "crank", "pivot": "O2", "tip": "A", "speed": "12 rad/s"},
        "settings": {"gravity": ["0 m/s^2", "-9.81 m/s^2"], "trace": ["B"]},
    },
    hints={
        "model": {"source": "the drawing"},
        "bodies": {"center_of_mass": ["12.5 mm", "21.65 mm"]},
        "joints": {"axis": "90 deg", "points": ["P1", "P2"]},
        "joints.pitch": {
            "kind": "circle",
            "radius": "closing",
            "eccentricity_ratio": 0.13,
            "semi_major": "closing",
            "radii": ["20 mm", "22 mm", "24 mm", "22 mm"],
        },
        "driver": {"speed_profile": [["0 deg", "12 rad/s"], ["180 deg", "14 rad/s"]]},
        "settings": {
            "output": ["rocker", "B"],
            "field_velocity": ["0.5 m/s", "0 m/s"],
            "rated_torque": "1600 kN*m",
            "rated_force": "10 MN",
        },
        "process_forces": {
            "body": "rocker",
            "point": "B",
            "direction": "-90 deg",
            "versus": "angle",
            "table": [["0 deg", "0 N"], ["180 deg", "100 N"], ["359 deg", "0 N"]],
        },
        "counterweights": {
            "body": "crank",
            "mass": "0.2 kg",
            "position": ["-20 mm", "0 mm"],
            "inertia": "1e-5 kg*m^2",
            "name": "crank counterweight",
        },
    },
    notes={
        "joints": "point and axis belong to revolute and prismatic joints; points, carrier, pitch, "
        "orientation, pressure_angle, internal and flank to a gear joint.",
    },
)

_PLANTER = TemplateExample(
    intro="The example: the published rotary planting mechanism RP-1 as it is (every design variable "
    "at its default); change a variable to study a variant.",
    run="mechdyn mechanism FILE",
    model={"model": {"type": "planting_mechanism", "name": "rotary planting mechanism"}},
    hints={"settings": {"field_velocity": ["0.6 m/s", "0 m/s"]}},
)

_SUPPORT = TemplateExample(
    intro="The example: a 2 t machine on four mounts, loaded by a vertical force given by its "
    "harmonics, so that the file stands alone.",
    run="mechdyn support FILE",
    model={
        "model": {"type": "support", "name": "machine on four mounts"},
        "machine": {
            "mass": "2000 kg",
            "center_of_mass": ["0 m", "0 m", "0.6 m"],
            "inertia": ["400 kg*m^2", "600 kg*m^2", "500 kg*m^2"],
        },
        "mounts": [
            {
                "name": name,
                "position": [x, y, "0 m"],
                "stiffness": ["1e6 N/m", "1e6 N/m", "4e6 N/m"],
                "damping": ["2e3 N*s/m", "2e3 N*s/m", "4e3 N*s/m"],
            }
            for name, x, y in (
                ("front left", "-0.8 m", "-0.5 m"),
                ("front right", "0.8 m", "-0.5 m"),
                ("rear left", "-0.8 m", "0.5 m"),
                ("rear right", "0.8 m", "0.5 m"),
            )
        ],
        "excitation": {"period": "0.04 s", "harmonics": [[1, "5 kN", "0 deg"], [2, "1 kN", "90 deg"]]},
    },
    hints={
        "model": {"source": "the drawing"},
        "support": {"stiffness": "1.6e7 N/m", "damping_ratio": 0.05},
        "foundation": {"size": ["3 m", "2 m", "1 m"], "density": "2400 kg/m^3"},
        "foundation.soil": {"shear_modulus": "60 MPa", "poisson_ratio": 0.33, "density": "1900 kg/m^3"},
        "mounts": {
            "mount": "pad.toml",
            "estimate": {"pad": {"shore_a": 60, "diameter": "100 mm", "thickness": "12.5 mm"}},
            "lateral_stiffness": "1e6 N/m",
        },
        "excitation": {
            "mechanism": "mechanism.toml",
            "angles": 360,
            "x_axis": [0, 0, -1],
            "y_axis": [1, 0, 0],
            "force_z": ["0 kN", "5 kN", "0 kN", "-5 kN"],
            "speed_range": ["0 rpm", "3000 rpm"],
        },
        "excitation.rotors": {
            "name": "fan",
            "unbalance": "0.02 kg*m",
            "speed": "1480 rpm",
            "axis": "y",
            "position": ["0 m", "0 m", "0.6 m"],
        },
    },
    notes={
        "support": "The machine stands on [support] (one degree of freedom: stiffness and damping ratio) "
        "or on [[mounts]], one of the two: this template gives mounts.",
        "mounts": "A mount's stiffness as numbers (stiffness), from its drawing in a mount file (mount = "
        "a mount file, relative to this one) or inline (estimate = {pad = {...}}): exactly one.",
        "excitation": "The load: exactly one of mechanism (a mechanism model file, relative to this one: "
        "its shaking force and moment, placed by origin, x_axis and y_axis), force_z (samples over one "
        "period), harmonics ([order, amplitude, phase] rows) or [[excitation.rotors]] (unbalanced "
        "rotors). This template gives harmonics so that it stands alone; for a mechanism's load write "
        'mechanism = "press.toml" instead (mechdyn new mechanism press.toml writes one).',
    },
)

_MOUNT = TemplateExample(
    intro="The example: a bonded Shore-60 rubber disc pad (100 mm across, 12.5 mm thick) under a "
    "10 kN load disturbed at 50 Hz.",
    run="mechdyn mount FILE",
    model={
        "model": {"type": "mount", "name": "Shore 60 pad"},
        "pad": {"shore_a": 60, "diameter": "100 mm", "thickness": "12.5 mm"},
        "load": {"weight": "10 kN", "disturbing_frequency": "50 Hz"},
    },
    hints={
        "model": {"source": "the drawing"},
        "materials": {"files": ["my_materials.toml"]},
        "pad": {
            "material": "rubber shore 60",
            "length": "150 mm",
            "width": "100 mm",
            "compression_coefficient": 0.6,
        },
        "bolted": {
            "diameter": "20 mm",
            "head_diameter": "30 mm",
            "lower_bearing_diameter": "30 mm",
            "hole_diameter": "22 mm",
            "stress_area": "245 mm^2",
            "outer_diameter": "60 mm",
            "pitch": "2.5 mm",
            "thread_length": "10 mm",
        },
        "bolted.layers": {"thickness": "25 mm", "material": "steel"},
        "wedge": {"bearing_area": "0.01 m^2", "height": "60 mm", "catalogue_stiffness": "2e9 N/m"},
        "screw_foot": {
            "diameter": "24 mm",
            "free_length": "80 mm",
            "base_stiffness": "5e8 N/m",
            "pitch": "3 mm",
        },
        "damping_pad": {
            "material": "rubber shore 50",
            "shore_a": 50,
            "thickness": "10 mm",
            "length": "120 mm",
            "width": "80 mm",
            "diameter": "80 mm",
            "compression_coefficient": 0.6,
        },
        "spring": {"wire_diameter": "8 mm", "coil_diameter": "50 mm", "active_coils": 6},
        "fe": {
            "preloads": ["20 kN"],
            "pressure_threshold": "1.7 MPa",
            "plate_radius": "75 mm",
            "concrete_radius": "180 mm",
        },
        "load": {"loss_factor": 0.1},
        "calibration": {
            "reference": "measured",
            "measured_stiffness": "5e6 N/m",
            "frf_csv": "mount_frf.csv",
            "provenance": "bench test",
        },
    },
    notes={
        "pad": "The mount is one of [pad], [bolted], [wedge], [screw_foot], [damping_pad] or [spring]: "
        "this template gives a pad; to describe another, comment the pad out and uncomment that one.",
        "fe": "The finite-element reference of a pad or an anchor (it takes a while): uncomment [fe] to "
        "compute it.",
    },
)

_GEAR_PAIR = TemplateExample(
    intro="The example: a standard 20° steel spur pair, module 2 mm, 20/40 teeth, face width 20 mm.",
    run="mechdyn gear FILE",
    model={
        "model": {"type": "gear_pair", "name": "spur pair m 2, z 20/40"},
        "pinion": {"teeth": 20, "module": "2 mm", "face_width": "20 mm", "bore_diameter": "20 mm"},
        "gear": {"teeth": 40, "module": "2 mm", "face_width": "20 mm", "bore_diameter": "40 mm"},
        "mesh": {"points": 100},
    },
    hints={
        "model": {"source": "the gear drawing"},
        "pinion": {
            "rim_thickness": "8 mm",
            "web_width": "8 mm",
            "rim_supports": 6,
            "youngs_modulus": "206 GPa",
            "poisson_ratio": 0.3,
            "helix_angle": "0 deg",
        },
        "gear": {
            "rim_thickness": "8 mm",
            "web_width": "8 mm",
            "rim_supports": 6,
            "youngs_modulus": "206 GPa",
            "poisson_ratio": 0.3,
            "helix_angle": "0 deg",
        },
        "mesh": {"center_distance": "60 mm", "kind": "external"},
    },
)

_TOOTH = {
    "tip_height": "4.025 mm",
    "root_height": "0.525 mm",
    "load_height": "2.275 mm",
    "tip_thickness": "2.749 mm",
    "root_thickness": "3.073 mm",
}

_TOOTH_PAIR = TemplateExample(
    intro="The example: two equal truncated-triangle steel teeth, loaded at mid-height at 20°, "
    "face width 50 mm.",
    run="mechdyn gear FILE",
    model={
        "model": {"type": "tooth_pair", "name": "tooth pair"},
        "load": {"load_angle": "20 deg", "face_width": "50 mm"},
        "pinion": dict(_TOOTH),
        "gear": dict(_TOOTH),
    },
    hints={
        "model": {"source": "the publication"},
        "pinion": {"root_radius": "30 mm", "bore_radius": "10 mm"},
        "gear": {"root_radius": "60 mm", "bore_radius": "20 mm"},
        "published": {"mesh_stiffness": "2.7e9 N/m", "note": "printed in table 2"},
    },
)

_STUDY = TemplateExample(
    intro="The example: the two-disk drivetrain of `mechdyn new drivetrain`, its shaft 20 % softer and "
    "stiffer and its load disk 20 % lighter and heavier, one at a time, watching its natural "
    "frequencies.",
    run="mechdyn study FILE, with its model next to it (mechdyn new drivetrain drivetrain.toml writes it)",
    model={
        "study": {
            "name": "two-disk drivetrain, one at a time",
            "kind": "oat",
            "model": "drivetrain.toml",
            "analysis": "modal",
        },
        "parameters": [
            {"path": "shafts.shaft.stiffness", "levels": ["-20 %", "+20 %"]},
            {"path": "disks.load.inertia", "name": "load inertia", "levels": ["-20 %", "+20 %"]},
        ],
        "outputs": [{"output": "frequencies_hz.1", "unit": "Hz"}],
    },
    hints={
        "study": {
            "samples": 64,
            "population": 20,
            "boxes": ["±10 %", "±20 %"],
            "options": {"modes": 3},
            "scatter_samples": 128,
        },
        "parameters": {
            "name": "shaft stiffness",
            "range": "±10 %",
            "tie": ["disks.motor.inertia"],
            "scatter": {"distribution": "lognormal", "cov": 0.15},
        },
        "outputs": {"limit": "150 Hz", "side": "below", "statistic": "p_exceed"},
        "correlations": {"between": ["shaft stiffness", "load inertia"], "coefficient": 0.5},
        "objectives": {"output": "frequencies_hz.1", "unit": "Hz", "goal": "maximize", "statistic": "q5"},
        "constraints": {
            "statistic": "q95",
            "output": "frequencies_hz.1",
            "unit": "Hz",
            "max": 300,
            "min": 100,
            "equals": 150,
            "tolerance": 1,
        },
        "targets": {
            "output": "frequencies_hz.1",
            "unit": "Hz",
            "max": 300,
            "min": 100,
            "equals": 150,
            "tolerance": 1,
        },
    },
    notes={
        "study": "model is the base model file, relative to this study file: `mechdyn new drivetrain "
        "drivetrain.toml` writes the one this template studies. `mechdyn study --paths MODEL` lists "
        "the values a parameter's path may name.",
    },
)

_DRIVE = TemplateExample(
    intro="The example: the four-bar of `mechdyn new mechanism mechanism.toml` driven by a 0.18 kW "
    "four-pole induction motor through a 12:1 reduction, with a small flywheel on the motor shaft.",
    run="mechdyn drive FILE",
    model={
        "model": {"type": "drive", "name": "four-bar driven by a motor"},
        "mechanism": {"file": "mechanism.toml"},
        "motor": {
            "type": "induction",
            "power": "0.18 kW",
            "synchronous_speed": "1500 rpm",
            "rated_speed": "1380 rpm",
            "pullout_ratio": 2.2,
            "rotor_inertia": "4e-4 kg*m^2",
        },
        "transmission": {"ratio": 12, "efficiency": 0.95},
        "flywheel": {"inertia": "2e-3 kg*m^2", "shaft": "motor"},
    },
    hints={
        "model": {"source": "the motor's catalogue"},
        "motor": {"curve": [["0 rpm", "2.5 N*m"], ["1380 rpm", "1.25 N*m"], ["1500 rpm", "0 N*m"]]},
        "flywheel": {"target_fluctuation": 0.05},
        "transmission": {"efficiency": 0.9},
        "transmission.stages": {"name": "belt", "ratio": 3.0, "efficiency": 0.96, "inertia": "0.5 kg*m^2"},
        "process": {"force": "200 N", "before_bdc": "20 mm", "rise": "2 mm"},
    },
    notes={
        "mechanism": "The mechanism the motor drives: a mechanism model file, relative to this one "
        "(`mechdyn new mechanism mechanism.toml` writes the one this template drives).",
        "motor": 'An induction motor from its rating (Kloss\'s formula), or type = "curve" with its '
        "torque-speed curve as [speed, torque] rows.",
        "process": "A forming force over the last part of the slide's stroke before bottom dead centre "
        "(a mechanism whose output is a slide).",
    },
)

_MEASUREMENT = TemplateExample(
    intro="The example: a hammer test of a machine on four mounts (the accelerometers on the mounts' "
    "tops), compared with the machine's model and its mounts' stiffness updated; it needs the data and "
    "model files beside it (copy examples/measured/tap_test.uff and machine.toml).",
    run="mechdyn modes-from-test FILE --plots plots",
    model={
        "model": {"type": "measurement", "name": "tap test"},
        "measurement": {"data": "tap_test.uff", "model": "machine.toml", "f_min": "3 Hz", "f_max": "28 Hz"},
        "points": [{"point": str(k), "mount": str(k)} for k in range(1, 5)],
        "update": [{"path": f"mounts.*.stiffness.{a}", "prior_scatter": 0.3} for a in "xyz"],
    },
    hints={
        "model": {"source": "hammer test of the machine as built"},
        "measurement": {"units": "m/s^2/N"},
        "points": {"location": ["1.2 m", "0.8 m", "0 m"], "disk": "motor"},
        "updating": {"damping_error": 0.05},
        "predict": {
            "analysis": "support",
            "outputs": ["transmitted_force_max_N", {"output": "natural_frequencies_hz.1", "unit": "Hz"}],
        },
    },
    notes={
        "points": "Each point of the data file mapped to a model point: a mount of a support by name, a "
        "location (x, y, z) in the machine's coordinates, or a drivetrain disk by name (one of the three).",
        "update": "The model values to update, named as a design study names them, with the scatter of "
        "their logarithm before the test; without [[update]] rows the test is only compared.",
    },
)

EXAMPLES: dict[str, TemplateExample] = {
    "drive": _DRIVE,
    "drivetrain": _DRIVETRAIN,
    "mechanism": _MECHANISM,
    "planting_mechanism": _PLANTER,
    "support": _SUPPORT,
    "mount": _MOUNT,
    "gear_pair": _GEAR_PAIR,
    "tooth_pair": _TOOTH_PAIR,
    "measurement": _MEASUREMENT,
    "study": _STUDY,
}
"""The example of each file type's template, by type."""
