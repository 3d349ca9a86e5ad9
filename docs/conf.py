"""Sphinx configuration of the mechdyn documentation.

Build locally with ``sphinx-build -W -b html docs docs/_build/html`` (the test suite builds it the same
way, warnings as errors). The gallery runs every script of ``examples/gallery``; the model-file
reference is generated from the validation schemas by ``_ext/modelfile_reference.py``.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import mechdyn

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE / "_ext"))
os.environ.setdefault("MPLBACKEND", "Agg")

project = "mechdyn"
author = "the mechdyn developers"
copyright = "2026, the mechdyn developers"
release = mechdyn.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "modelfile_reference",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "**.ipynb_checkpoints", "sg_execution_times.rst"]
myst_enable_extensions = ["colon_fence", "dollarmath"]
myst_heading_anchors = 3

# API reference: the public names of each subpackage, from their docstrings
autosummary_generate = True
autodoc_default_options = {"members": True, "inherited-members": False}
autodoc_typehints = "none"  # numpydoc's Parameters sections carry the types with their units
numpydoc_show_class_members = False
numpydoc_xref_param_type = False
# every parameter documented: tests/test_docstrings.py checks it over __all__ (with units)

# no intersphinx: the build must not need the internet (CI machines and shop floors may have none)

sphinx_gallery_conf = {
    "examples_dirs": str(HERE.parent / "examples" / "gallery"),
    "gallery_dirs": str(HERE / "auto_examples"),
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "min_reported_time": 1,
    "matplotlib_animations": False,
    "abort_on_example_error": True,
    "write_computation_times": False,
    "capture_repr": (),  # a plot call's returned axes is not output
}


def _write_api_reference() -> None:
    """``api/index.rst``: every name in ``__all__`` of the package's public modules, so that the API
    reference follows the code (the same list that tests/test_docstrings.py checks)."""
    import importlib

    modules = [
        ("mechdyn", "The package"),
        ("mechdyn.mechanism", "Planar mechanisms"),
        ("mechdyn.support", "The machine on its supports"),
        ("mechdyn.drive", "The mechanism driven by a motor, gears and a flywheel"),
        ("mechdyn.balance", "Counterweights"),
        ("mechdyn.drivetrain", "Torsional vibration of geared drivetrains"),
        ("mechdyn.gears", "Gear tooth and mesh stiffness"),
        ("mechdyn.gear_dynamics", "Geared drivetrains in time"),
        ("mechdyn.mounts", "Mount stiffness from the drawing"),
        ("mechdyn.vibration", "The linear-vibration core"),
        ("mechdyn.studies", "Design studies"),
        ("mechdyn.uncertainty", "Tolerances to probabilities"),
        ("mechdyn.measurement", "Measured frequency responses"),
        ("mechdyn.store", "The results database"),
        ("mechdyn.reports", "Reports"),
        ("mechdyn.io", "Model files"),
        ("mechdyn.registry", "The analysis registry"),
        ("mechdyn.results", "The result protocol"),
        ("mechdyn.units", "Units"),
        ("mechdyn.errors", "Errors and warnings"),
        ("mechdyn.plotting", "Plot helpers"),
        ("mechdyn.figure_workers", "Figures drawn in parallel"),
    ]
    lines = [
        "API reference",
        "=============",
        "",
        "The public names of each module, from their docstrings. Python constructors take quantities",
        '(``"80.8 GPa"``, ``mechdyn.Q_(80.8, "GPa")``) or plain floats, which are SI by contract.',
        "",
    ]
    for name, title in modules:
        module = importlib.import_module(name)
        heading = f"{title} (``{name}``)"
        lines += [heading, "-" * len(heading), "", f".. automodule:: {name}", "   :no-members:", ""]
        lines += [f".. currentmodule:: {name}", ""]
        names = [n for n in getattr(module, "__all__", []) if not n.startswith("_")]
        documented = [
            n
            for n in names
            if callable(getattr(module, n))
            and getattr(getattr(module, n), "__module__", "").startswith("mechdyn")
        ]
        if documented:
            lines += [".. autosummary::", "   :toctree: generated", "   :nosignatures:", ""]
            lines += [f"   {n}" for n in sorted(documented)]
            lines.append("")
    api = HERE / "api"
    api.mkdir(exist_ok=True)
    text = "\n".join(lines)
    target = api / "index.rst"
    if not target.exists() or target.read_text() != text:
        target.write_text(text)


_write_api_reference()

html_theme = "pydata_sphinx_theme"
html_title = "mechdyn"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
}
html_static_path: list[str] = []
html_show_sourcelink = False
