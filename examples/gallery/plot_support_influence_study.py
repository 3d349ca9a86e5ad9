"""
A design study: how the press's support changes the force on the floor
======================================================================

A one-at-a-time study of press A's support (``examples/studies/press_support_influence.toml``):
its stiffness and damping ratio each lowered by up to 30 %. Every variant is stored in a results
database (here a temporary SQLite file); ``mechdyn study FILE`` does the same.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

from mechdyn.cli.common import print_table
from mechdyn.studies import load_study, run_study
from mechdyn.studies.plots import tornado

# the examples folder (this script runs from examples/gallery)
EXAMPLES = Path(globals().get("__file__", "gallery.py")).resolve().parents[1]
study = load_study(EXAMPLES / "studies" / "press_support_influence.toml")
with tempfile.TemporaryDirectory() as folder:
    result = run_study(study, f"{folder}/study.db")
for table in result.tables():
    print_table(table)  # as the command prints it

# %%
# The change of the floor-force range in per cent of the base design, level by level.
tornado(result, study.outputs[0])
plt.show()
