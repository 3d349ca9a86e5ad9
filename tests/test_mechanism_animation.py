"""The linkage animated over one crank cycle: ``mechdyn mechanism FILE --animate PATH``,
``DynamicsResult.animate`` and the animation in a mechanism run's report."""

from __future__ import annotations

import base64
import io
import json
import re
import warnings

import matplotlib
import numpy as np
import pytest
from PIL import Image

from conftest import EXAMPLES
from mechdyn.cli.main import main
from mechdyn.errors import MechdynError, ModelWarning
from mechdyn.io import load_model
from mechdyn.registry import get

matplotlib.use("Agg")
import matplotlib.pyplot as plt

CRANK_COLOUR = np.array([0x1F, 0x77, 0xB4])  # C0: the first body of both examples is the crank


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


def _run(example: str, angles: int = 72):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        return get("mechanism").run(load_model(EXAMPLES / example), angles=angles)


def _gif_frames(data: bytes) -> list[np.ndarray]:
    gif = Image.open(io.BytesIO(data))
    assert gif.format == "GIF" and gif.is_animated
    frames = []
    for f in range(gif.n_frames):
        gif.seek(f)
        frames.append(np.asarray(gif.convert("RGB")))
    return frames


def _shown(degrees: float) -> str:
    """The crank angle as a frame shows it (359.99999° is 0°)."""
    return f"crank angle {round(degrees) % 360:.0f}°"


def _line(anim, label: str):
    """The line a link is drawn with (labelled with the body's name)."""
    (line,) = [ln for ln in anim._fig.axes[0].get_lines() if ln.get_label() == label]
    return line


@pytest.mark.parametrize("example", ["fourbar.toml", "press_link_drive.toml"])
def test_the_gif_shows_the_linkage_where_the_kinematics_puts_it(example, tmp_path):
    result = _run(example)
    path = tmp_path / "cycle.gif"
    anim = result.animate(path, frames=24)
    frames = _gif_frames(path.read_bytes())
    assert len(frames) == 24
    k, m = result.kinematics, result.mechanism
    # frame 0 is sample 0 (the angle datum): every link's line runs through its joints, in mm
    for b in m.bodies:
        drawn = np.asarray(_line(anim, b.name).get_xydata())
        joints = 1e3 * np.array([k.point(b.name, p)[0][0] for p in b.points])
        np.testing.assert_allclose(drawn[: len(joints)], joints, rtol=0, atol=1e-9)
    # and the pixels of the first frame: the middle of the crank is drawn in the crank's colour
    ax = anim._fig.axes[0]
    crank = m.bodies[0]
    mid = 1e3 * np.mean([k.point(crank.name, p)[0][0] for p in crank.points], axis=0)
    x, y = ax.transData.transform(mid)
    height = frames[0].shape[0]
    patch = frames[0][int(height - y) - 2 : int(height - y) + 3, int(x) - 2 : int(x) + 3].reshape(-1, 3)
    assert np.abs(patch.astype(int) - CRANK_COLOUR).max(axis=1).min() < 40
    # the view holds the whole motion, on equal axes in mm, the same in every frame
    assert ax.get_xlabel() == "x (mm)" and ax.get_ylabel() == "y (mm)" and ax.get_aspect() == 1.0
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    for b in m.bodies:
        for p in b.points:
            xy = 1e3 * k.point(b.name, p)[0]
            assert x0 < xy[:, 0].min() and xy[:, 0].max() < x1 and y0 < xy[:, 1].min() and xy[:, 1].max() < y1
    # the frame's pivots are marked; the crank angle is shown
    pivots = [ln for ln in ax.get_lines() if ln.get_marker() == "^"]
    assert len(pivots) == sum(1 for j in m.joints if "ground" in j.bodies and not j.slides)
    assert any(t.get_text() == _shown(np.degrees(k.angle[0])) for t in ax.texts)
    assert frames[0].shape == frames[-1].shape and not np.array_equal(frames[0], frames[12])


def test_the_frames_follow_the_crank_and_trace_the_coupler_curves(tmp_path):
    result = _run("fourbar.toml")
    anim = result.animate(tmp_path / "cycle.gif", frames=12)
    k = result.kinematics
    ax = anim._fig.axes[0]
    paths = [ln for ln in ax.get_lines() if ln.get_linestyle() == "-" and ln.get_marker() in ("None", "")]
    assert len(paths) == 1  # the coupler's centre of mass (no point is traced in the file)
    lengths = []
    for f in range(12):
        anim._func(f)
        i = 6 * f  # 72 angles, 12 frames: every sixth, counter-clockwise from the datum
        crank = np.asarray(_line(anim, "crank").get_xydata())
        np.testing.assert_allclose(crank[1], 1e3 * k.point("crank", "A")[0][i], rtol=0, atol=1e-9)
        lengths.append(len(paths[0].get_xdata()))
        label = [t.get_text() for t in ax.texts if t.get_text().startswith("crank angle")]
        assert label == [_shown(np.degrees(k.angle[i]))]
    assert lengths == [1 + 6 * f for f in range(12)]  # the curve grows as the crank turns


def test_a_crank_turning_clockwise_is_animated_clockwise(tmp_path):
    text = (EXAMPLES / "fourbar.toml").read_text().replace('speed = "12 rad/s"', 'speed = "-12 rad/s"')
    model = tmp_path / "clockwise.toml"
    model.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        result = get("mechanism").run(load_model(model), angles=72)
    anim = result.animate(tmp_path / "cw.gif", frames=72)
    shown = []
    for f in (0, 1, 2):
        anim._func(f)
        shown.append(next(t.get_text() for t in anim._fig.axes[0].texts if t.get_text()))
    first = np.degrees(result.kinematics.angle[0])
    assert shown == [_shown(first - 5 * f) for f in range(3)]


def test_more_frames_than_angles_give_one_per_angle_and_no_path_gives_the_animation(tmp_path):
    result = _run("fourbar.toml", angles=36)
    path = tmp_path / "short.gif"
    result.animate(path, frames=72)
    assert len(_gif_frames(path.read_bytes())) == 36
    from matplotlib.animation import FuncAnimation

    anim = result.animate(frames=3)  # not written: shown in a notebook
    assert isinstance(anim, FuncAnimation)
    assert anim.to_jshtml().count("data:image/png;base64,") == 3


def test_an_mp4_without_ffmpeg_is_refused_with_the_fix(tmp_path, monkeypatch, capsys):
    from matplotlib import animation

    monkeypatch.setattr(animation.writers, "is_available", lambda name: False)
    result = _run("fourbar.toml", angles=36)
    with pytest.raises(MechdynError, match=r"ffmpeg.*\.gif|\.gif.*ffmpeg"):
        result.animate(tmp_path / "cycle.mp4")
    assert not (tmp_path / "cycle.mp4").exists()
    argv = ["mechanism", str(EXAMPLES / "fourbar.toml"), "--db", str(tmp_path / "r.db")]
    with pytest.raises(SystemExit) as stop:
        main([*argv, "--animate", str(tmp_path / "cycle.mp4")])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert "install ffmpeg" in err and ".gif" in err and "Traceback" not in err
    with pytest.raises(SystemExit):
        main([*argv, "--animate", str(tmp_path / "cycle.png")])
    assert "give a file ending .gif" in capsys.readouterr().err
    assert not (tmp_path / "r.db").exists()  # refused before anything ran


def test_the_command_writes_the_animation(tmp_path, capsys):
    out = tmp_path / "anim" / "fourbar.gif"
    argv = ["mechanism", str(EXAMPLES / "fourbar.toml"), "--db", str(tmp_path / "r.db"), "--angles", "72"]
    assert main([*argv, "--animate", str(out), "--animate-frames", "18", "--json"]) == 0
    json.loads(capsys.readouterr().out)  # --json prints only the JSON document
    assert len(_gif_frames(out.read_bytes())) == 18
    assert main([*argv, "--animate", str(out)]) == 0
    assert f"animation: {out}" in capsys.readouterr().out
    assert len(_gif_frames(out.read_bytes())) == 72  # the default
    blocked = tmp_path / "file"
    blocked.write_text("")
    assert main([*argv, "--animate", str(blocked / "x.gif")]) == 2
    assert "cannot write the animation" in capsys.readouterr().err


def test_the_help_lists_the_option_for_mechanisms_only(capsys):
    with pytest.raises(SystemExit):
        main(["mechanism", "--help"])
    text = capsys.readouterr().out
    assert "--animate PATH" in text and "--animate-frames N" in text and ".gif" in text
    with pytest.raises(SystemExit):
        main(["modal", "--help"])
    assert "--animate" not in capsys.readouterr().out


def _gifs(html: str) -> list[bytes]:
    return [base64.b64decode(m) for m in re.findall(r'src="data:image/gif;base64,([^"]+)"', html)]


@pytest.mark.slow  # CI's heavy step (issue 48: the test command's minutes)
def test_a_mechanism_report_shows_the_animation_and_a_support_report_does_not(tmp_path, capsys):
    db = str(tmp_path / "r.db")
    assert main(["mechanism", str(EXAMPLES / "press_link_drive.toml"), "--db", db, "--angles", "72"]) == 0
    out = tmp_path / "press.html"
    assert main(["report", "1", "--db", db, "--output", str(out)]) == 0  # a stored run, recomputed
    html = out.read_text()
    (gif,) = _gifs(html)
    assert len(_gif_frames(gif)) == 72
    assert "the linkage over one crank cycle" in html
    assert re.search(r'src="data:image/png;base64,', html)  # the plots stay PNG
    support = tmp_path / "support.html"
    argv = ["support", str(EXAMPLES / "press_on_support.toml"), "--db", db, "--cycles", "1"]
    assert main([*argv, "--report", str(support)]) == 0
    capsys.readouterr()
    assert "image/gif" not in support.read_text()
