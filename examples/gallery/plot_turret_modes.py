"""
Mill turret: modes with flexible and rigid gear meshes
======================================================

Reference machine B, the indexing path of an NC lathe's mill turret (SPEC §3): six disks, three
shafts, two gear meshes with the published mesh stiffness. ``mechdyn modal FILE --compare-rigid``
does the same.
"""

from pathlib import Path

import matplotlib.pyplot as plt

import mechdyn
from mechdyn.drivetrain import compare_rigid, modal

# the examples folder (this script runs from examples/gallery)
EXAMPLES = Path(globals().get("__file__", "gallery.py")).resolve().parents[1]
turret = mechdyn.load(EXAMPLES / "turret_indexing.toml").model

# %%
# Natural frequencies with flexible meshes; the rigid-body mode of the free chain is set aside.
modes = modal(turret)
print(modes.frequencies_hz.round(1))

# %%
# The same model with every mesh a rigid constraint, paired with the flexible modes by their shape
# (MAC). The two highest flexible modes are mesh modes: they have no rigid twin.
comparison = compare_rigid(turret)
print(comparison.to_frame().round(3).to_string(index=False))

# %%
# Mode shapes: one panel per mode; a gear mesh shows as a jump between its two disks.
modes.plots()["mode_shapes.png"]()
plt.show()
