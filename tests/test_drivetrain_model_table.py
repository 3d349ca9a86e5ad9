"""The drivetrain as assembled: every value the analyses rest on, and where it came from."""

from __future__ import annotations

import math

import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.drivetrain import Disk, Drivetrain, Shaft, model_table
from mechdyn.registry import get

GEOMETRY = """
[model]
type = "drivetrain"
name = "geometry"

[material]
density = "7850 kg/m^3"
shear_modulus = "80 GPa"

[[disks]]
name = "flywheel"
thickness = "40 mm"
outer_diameter = "300 mm"
inner_diameter = "50 mm"

[[disks]]
name = "hub"
inertia = "0.01 kg*m^2"

[[shafts]]
name = "quill"
disks = ["flywheel", "hub"]
length = "250 mm"
diameter = "30 mm"
damping = "2 N*m*s/rad"
"""


def test_values_from_geometry_say_so_and_equal_their_formulas(tmp_path):
    path = tmp_path / "geometry.toml"
    path.write_text(GEOMETRY)
    model = mechdyn.load(path).model
    frame = model.to_frame().set_index("name")
    J = 7850 * 0.040 * math.pi * (0.3**4 - 0.05**4) / 32  # ρ h π (D⁴ − d⁴)/32
    k = 80e9 * math.pi * 0.03**4 / 32 / 0.25  # G π d⁴ /(32 l)
    assert frame.loc["flywheel", "value"] == pytest.approx(J, rel=1e-12)
    assert frame.loc["flywheel", "unit"] == "kg*m^2"
    assert frame.loc["flywheel", "from"] == "from geometry: h = 40 mm, D = 300 mm, d = 50 mm, ρ = 7850 kg/m³"
    assert frame.loc["hub", "from"] == "given"
    assert frame.loc["quill", "value"] == pytest.approx(k, rel=1e-12)
    assert frame.loc["quill", "from"] == "from geometry: l = 250 mm, d = 30 mm, G = 80 GPa"
    assert frame.loc["quill (damping)", "value"] == 2.0
    # the table a designer reads: the same values in readable units
    table = model_table(model)
    rows = {r[0]: r for r in table.rows}
    assert rows["quill"][1:3] == [pytest.approx(k / 1e3, rel=1e-12), "kN·m/rad"]
    # equality is the model's, not its history
    assert model == Drivetrain(model.disks, model.elements, name="geometry")


@pytest.mark.filterwarnings("ignore::mechdyn.errors.ModelWarning")
@pytest.mark.parametrize("analysis", ["modal", "campbell", "frf"])
def test_every_drivetrain_analysis_shows_the_model_as_assembled(analysis):
    loaded = mechdyn.load(EXAMPLES / "turret_milling_gear_data.toml")
    options = {"points": 50} if analysis == "frf" else {}
    result = get(analysis).run(loaded, **options)
    table = result.tables()[-1]
    assert table.title.endswith("the model as assembled")
    rows = {r[0]: r for r in table.rows}
    assert rows["mesh 1"][3] == "external mesh" and rows["mesh 1"][2] == "kN/mm"
    assert rows["mesh 1"][-1] == "gear pair '19/19 spur pair': mean over a mesh cycle, involute teeth"
    mesh = loaded.model.element("mesh 1")
    assert rows["mesh 1"][1] == pytest.approx(mesh.stiffness / 1e6, rel=1e-12)  # N/m → kN/mm
    assert len(table.rows) == len(loaded.model.disks) + len(loaded.model.elements)


def test_a_model_built_in_python_is_given_and_a_rigid_mesh_has_no_stiffness():
    from mechdyn.drivetrain import GearMesh

    dt = Drivetrain(
        [Disk("a", 1e-3), Disk("b", 2e-3), Disk("c", 5e-3)],
        [Shaft("s", ("a", "b"), 1e4), GearMesh("g", ("b", "c"), base_radii=(0.02, 0.05))],
    )
    rows = {r[0]: r for r in model_table(dt).rows}
    assert rows["s"][-1] == "given"
    assert rows["g"][3] == "external mesh, rigid" and rows["g"][1] is None
    assert rows["g"][5] == pytest.approx(2.5) and rows["g"][6] == "20 / 50"


@pytest.mark.parametrize("example", ["turret_milling.toml", "press_link_drive.toml", "press_on_mounts.toml"])
def test_plot_returns_the_whole_figure_with_its_texts_as_written(example):
    """.plot() gave the first axes of a six-panel figure; it gives the figure, which a notebook shows."""
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure

    loaded = mechdyn.load(EXAMPLES / example)
    analysis = {"turret_milling.toml": "modal", "press_link_drive.toml": "mechanism"}.get(example, "support")
    options = {"store": None, "cycles": 1} if analysis == "support" else {}
    fig = get(analysis).run(loaded, **options).plot()
    assert isinstance(fig, Figure) and fig.axes
    assert not fig.axes[0].title.get_parse_math()
    plt.close(fig)
