"""Plots read right the first time: one panel per mode with a break at every gear mesh, titles that
tell rigid from flexible meshes and fit in the figure, units chosen by size, dead-centre labels
clear of the title, no plot that shows a single full bar."""

from __future__ import annotations

import warnings

import matplotlib
import numpy as np
import pytest

from conftest import EXAMPLES
from mechdyn.errors import ModelWarning
from mechdyn.io import load_model
from mechdyn.registry import get

matplotlib.use("Agg")
import matplotlib.pyplot as plt


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


def _run(name, example, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        return get(name).run(load_model(EXAMPLES / example), **options)


def _inside(fig, text) -> bool:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)  # a saved figure is closed: give it a canvas again to measure it
    fig.canvas.draw()
    box = text.get_window_extent(fig.canvas.get_renderer())
    return box.x0 >= -1 and box.x1 <= fig.bbox.width + 1 and box.y1 <= fig.bbox.height + 1


def test_mode_shapes_have_one_panel_per_mode_and_break_at_each_mesh():
    result = _run("modal", "turret_indexing.toml", compare_rigid=True)
    ax = result.plots()["mode_shapes.png"]()
    fig = ax.figure
    panels = [a for a in fig.axes if a.get_title(loc="left")]
    assert len(panels) == len(result.flexible.frequencies_hz)  # five flexible modes, five panels
    # disks 1-2, 3-4 and 5-6 are three shaft lines joined by two meshes: three lines per panel
    for panel in panels:
        assert len([ln for ln in panel.get_lines() if ln.get_marker() == "o"]) == 3
    titles = " ".join(p.get_title(loc="left") for p in panels)
    assert "e+" not in titles and "16022 Hz" in titles  # plain numbers
    assert "mesh 1 (ratio" in " ".join(t.get_text() for t in panels[0].texts)
    flexible = fig._suptitle.get_text()
    rigid = result.plots()["mode_shapes_rigid.png"]().figure._suptitle.get_text()
    assert "flexible meshes" in flexible and "rigid gears" in rigid and flexible != rigid


def test_large_torques_and_forces_are_shown_in_kilo_or_mega_units():
    result = _run("mechanism", "press_link_drive.toml", angles=72)
    plots = result.plots()
    assert "kN·m" in plots["driving_torque.png"]().get_ylabel()
    forces = plots["joint_forces.png"]()
    # 1.8 MN peaks read 1800 kN, as the summary table shows them (MN from 10 MN)
    assert forces.get_ylabel().endswith("(kN)") and forces.get_title().endswith(": joint forces")
    small = _run("mechanism", "slider_crank.toml", angles=36).plots()["driving_torque.png"]()
    assert small.get_ylabel() == "driving torque (N·m)"


def test_tooth_forces_are_named_only_with_gears():
    result = _run("mechanism", "transplanter_rp1_design.toml", angles=36)
    assert result.plots()["joint_forces.png"]().get_title().endswith("joint and tooth forces")


def test_dead_centre_labels_stay_clear_of_the_title():
    result = _run("mechanism", "press_link_drive.toml", angles=72)
    ax = result.plots()["output_motion.png"]()
    fig = ax.figure
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    title = ax.title.get_window_extent(renderer)
    labels = [t for t in ax.texts if t.get_text() in ("BDC", "TDC")]
    assert len(labels) == 2
    for t in labels:
        assert not t.get_window_extent(renderer).overlaps(title), t.get_text()
        assert t.get_window_extent(renderer).y1 <= ax.get_window_extent(renderer).y1 + 1


def test_the_frame_sheet_has_axes_in_mm_a_legend_of_the_links_and_the_gears():
    press = _run("mechanism", "press_link_drive.toml", angles=72)
    ax = press.plots()["frames.png"]()
    fig = ax.figure
    assert any(a.get_xlabel() == "x (mm)" for a in fig.axes)
    legend = fig.legends[0]
    assert {t.get_text() for t in legend.get_texts()} >= {b.name for b in press.mechanism.bodies}
    rp1 = _run("mechanism", "transplanter_rp1_design.toml", angles=36)
    sheet = rp1.plots()["frames.png"]().figure
    assert "pitch circle (mean)" in {t.get_text() for t in sheet.legends[0].get_texts()}
    dotted = [ln for ln in sheet.axes[0].get_lines() if ln.get_linestyle() == ":"]
    assert len(dotted) == 2 * len(rp1.mechanism.gear_laws)  # both gears of every pair


def test_a_one_degree_of_freedom_support_has_no_single_bar_plot():
    one = _run("support", "press_on_support.toml", cycles=1)
    assert "modes.png" not in one.plots()
    six = _run("support", "press_on_mounts.toml", cycles=1)
    assert "modes.png" in six.plots()
    label = six.plots()["mount_forces.png"]().get_ylabel()
    assert "dynamic part" in label


@pytest.mark.parametrize(
    ("analysis", "example", "options"),
    [
        ("support", "press_on_mounts.toml", {"cycles": 1}),
        ("mechanism", "press_link_drive.toml", {"angles": 36}),
        ("modal", "turret_milling.toml", {"compare_rigid": True}),
    ],
)
def test_no_title_is_clipped_when_the_figure_is_saved(analysis, example, options, tmp_path):
    from mechdyn.plotting import save_figure

    for name, make in _run(analysis, example, **options).plots().items():
        ax = make()
        fig = ax.figure
        save_figure(ax, tmp_path / name)
        titles = [a.title for a in fig.axes] + ([fig._suptitle] if fig._suptitle is not None else [])
        for t in titles:
            if t.get_text():
                assert _inside(fig, t), f"{name}: {t.get_text()!r} is clipped"


def test_a_plot_picks_the_unit_its_table_shows():
    """A plot's unit comes from the tables' rule (units.readable_unit): 1.8 MN of force reads 1800 kN
    in the summary, and its plot's axis says kN too (it said MN: the table and the plot disagreed)."""
    from mechdyn.plotting import display_unit
    from mechdyn.units import readable

    assert display_unit(np.array([2e5, -3.5e5]), "N*m") == ("kN·m", 1e-3)
    assert display_unit(np.array([50.0]), "N*m") == ("N·m", 1.0)
    assert display_unit(np.array([1.8e6]), "N") == ("kN", 1e-3) and readable(1.8e6, "N") == (1800.0, "kN")
    assert display_unit(np.array([2.4e7]), "N") == ("MN", 1e-6)
    assert display_unit(np.array([]), "N") == ("N", 1.0)


def test_the_support_mode_shape_side_view_draws_the_machine_s_side_face():
    """The side view (x–z) is the face y = lo of the outline box, drawn as a rectangle as wide as the
    box in x and as tall in z (it once joined corners of the face x = lo: the machine drew as a
    vertical line beside its mounts); the top view is the face z = lo."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        r = get("support").run(load_model(EXAMPLES / "press_on_mounts.toml"), cycles=1)
    ax = r.plots()["mode_shapes.png"]()
    side, top = ax, ax.figure.axes[len(r.modes.frequencies_hz)]
    pos = np.array([mt.position for mt in r.machine.mounts])
    for view, (i, j) in ((side, (0, 2)), (top, (0, 1))):
        outline = view.lines[0]  # the box at rest, dotted
        x, y = np.asarray(outline.get_xdata()), np.asarray(outline.get_ydata())
        assert outline.get_linestyle() == ":" and len(x) == 5
        # a rectangle around the mounts, with an area (not a line)
        assert x.min() < pos[:, i].min() and x.max() > pos[:, i].max() and y.min() < pos[:, j].min()
        assert np.ptp(y) > 0.5 and len(set(np.round(x, 9))) == 2 and len(set(np.round(y, 9))) == 2
    plt.close("all")


def test_curves_that_would_hide_one_another_are_drawn_once_and_named_together():
    """Symmetric mounts carry one force and the crank's two pins nearly one: each such group is one
    line, its label naming all ("=" to round-off, "≈" within OVERLAP of the largest value); curves
    apart stay apart."""
    from mechdyn.plotting import OVERLAP, overlaid

    x = np.linspace(0.0, 1.0, 50)
    assert [k for k, _ in overlaid({"a": np.sin(x), "b": np.sin(x), "d": np.cos(x)})] == ["a = b", "d"]
    got = dict(overlaid({"a": np.sin(x), "b": np.sin(x), "c": np.sin(x) + 0.5 * OVERLAP, "d": np.cos(x)}))
    assert list(got) == ["a ≈ b ≈ c", "d"]
    np.testing.assert_array_equal(got["d"], np.cos(x))
    assert len(overlaid({"a": np.sin(x), "c": np.sin(x) + 2 * OVERLAP})) == 2
    support = _run("support", "press_on_mounts.toml", cycles=1)
    legend = support.plots()["mount_forces.png"]().get_legend()
    assert [t.get_text() for t in legend.get_texts()] == [
        "front left = rear left",
        "front right = rear right",
    ]
    plt.close("all")


def test_the_shaking_polar_plot_labels_crank_angles_without_overprinting():
    """Where the press's shaking force lingers near zero (180–300°) the twelve angle labels printed over
    one another; a label now keeps 8 % of the largest force from every other."""
    r = _run("mechanism", "press_link_drive.toml", angles=72)
    ax = r.plots()["shaking_force_polar.png"]()
    anchors = np.array([t.xy for t in ax.texts if t.get_text().endswith("°")])
    assert ax.get_xlabel().endswith("(kN)")  # the press's shaking force is drawn in kN
    reach = 1e-3 * float(np.abs(r.shaking_force).max())
    assert 4 <= len(anchors) < 12
    gaps = np.hypot(*(anchors[:, None, :] - anchors[None, :, :]).transpose(2, 0, 1))
    assert gaps[np.triu_indices(len(anchors), 1)].min() >= 0.08 * reach * (1 - 1e-9)
    plt.close("all")


@pytest.mark.parametrize("how", ["categories", "fixed labels", "function"])
def test_names_on_tick_labels_are_shown_as_written_however_the_axis_labels_them(how):
    """A name with $ signs on a category axis, a fixed list or a function's labels is shown as written;
    a log axis keeps its powers of ten (mathtext its formatter writes)."""
    from matplotlib.text import Text
    from matplotlib.ticker import FuncFormatter

    from mechdyn.plotting import fit_titles, plain_text

    fig, (_top, ax) = plt.subplots(2, 1, sharex=True, layout="constrained")
    names = ["cost $1 $of", "b"]
    if how == "categories":
        ax.bar(names, [1, 2])
    elif how == "fixed labels":
        ax.plot([0, 1], [1, 2])
        ax.set_xticks([0, 1], names)
    else:
        ax.plot([0, 1], [1, 2])
        ax.set_xticks([0, 1])
        ax.xaxis.set_major_formatter(FuncFormatter(lambda x, _: names[round(x)]))
    ax.set_yscale("log")
    plain_text(fig)
    fit_titles(fig)
    fig.canvas.draw()
    texts = fig.findobj(Text)
    plt.close(fig)
    named = [t for t in texts if "cost" in t.get_text()]
    assert named and not any(t.get_parse_math() for t in named)  # the hidden top labels too
    powers = [t for t in texts if "mathdefault" in t.get_text()]
    assert powers and all(t.get_parse_math() for t in powers)


def test_a_legend_goes_to_the_corner_its_curves_leave_clearest():
    """Placed here, never by matplotlib's "best" search (slow on long curves and warning so on a
    loaded machine): a curve rising into the upper right leaves the upper left clearest."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from mechdyn.plotting import legend

    fig, ax = plt.subplots()
    x = np.linspace(0, 1, 100_000)
    ax.plot(x, x**4, label="rising")
    assert legend(ax)._loc == 2  # matplotlib's code of "upper left"
    ax.plot(x, 1 - x, label="falling")
    assert legend(ax, loc="center")._loc == 10  # a place given is kept
    plt.close(fig)


def test_a_legend_keeps_clear_of_bars_as_of_curves():
    """Bars are drawn areas too: with bars falling from zero to the lower right (the frequency errors
    of a model update), the legend goes where no bar is (the lower left, matplotlib's code 3), and
    its box overlaps none of them."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mechdyn.plotting import legend

    fig, ax = plt.subplots()
    bars = ax.bar(range(6), [1.0, -2.0, -4.0, -6.0, -8.0, -8.5], label="error")
    ax.axhline(0.0, color="0.5", label="zero")
    box = legend(ax)
    assert box._loc == 3
    fig.canvas.draw()
    drawn = box.get_window_extent()
    assert not any(drawn.overlaps(bar.get_window_extent()) for bar in bars)
    plt.close(fig)


def test_every_legend_the_product_draws_is_placed_explicitly():
    """No legend is left to matplotlib's "best" search: every ``.legend(...)`` call in the package
    names its ``loc`` (not ``"best"``), or goes through :func:`mechdyn.plotting.legend`, which picks
    the corner (the helper's own call is the one exception)."""
    import ast
    from pathlib import Path

    import mechdyn

    root = Path(mechdyn.__file__).parent
    unplaced = []
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Attribute)
                and node.func.attr == "legend"
                and not any(
                    k.arg == "loc"
                    and not (isinstance(k.value, ast.Constant) and k.value.value in ("best", 0))
                    for k in node.keywords
                )
            ):
                unplaced.append(f"{path.relative_to(root)}:{node.lineno}")
    assert [u.split(":")[0] for u in unplaced] == ["plotting.py"], unplaced  # the helper's own call
