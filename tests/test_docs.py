"""The documentation builds with warnings as errors: a broken link, a field of a model file without a
description, a docstring that is not valid reST or a gallery example that fails stops CI. The gallery
runs every script of ``examples/gallery``."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from conftest import ROOT


@pytest.mark.step
def test_the_documentation_builds_without_a_warning(tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONWARNINGS="ignore")
    where = ["-d", str(tmp_path / "doctrees"), str(ROOT / "docs"), str(tmp_path / "html")]
    run = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-E", "-b", "html", *where],
        capture_output=True,
        text=True,
        env=env,
        timeout=900,
    )
    assert run.returncode == 0, run.stdout[-5000:] + run.stderr[-20000:]
    html = tmp_path / "html"
    # every model-file type has its reference page, with its tables generated from the schema
    for file_type in (
        "drivetrain",
        "mechanism",
        "planting_mechanism",
        "support",
        "mount",
        "gear_pair",
        "tooth_pair",
        "study",
    ):
        page = (html / "model_files" / f"{file_type}.html").read_text()
        assert "meaning" in page and "required" in page, file_type
    assert "youngs_modulus" in (html / "model_files" / "gear_pair.html").read_text()
    # the gallery ran its scripts and shows their figures
    gallery = html / "auto_examples"
    assert len(list(gallery.glob("plot_*.html"))) == len(
        list((ROOT / "examples" / "gallery").glob("plot_*.py"))
    )
    assert list((html / "_images").glob("sphx_glr_plot_*.png"))
    # the API reference has a page per public name
    assert (html / "api" / "generated" / "mechdyn.drivetrain.modal.html").exists()
