"""
Anchor bolt in concrete: stiffness from the drawing and its FE reference
========================================================================

An anchor bolt clamping a steel base plate to a concrete block. The estimate by pressure cones is
checked against an axisymmetric finite-element model with contact, refined until its discretisation
error (Richardson) is below the tolerance; the cone angle is calibrated against it.
``mechdyn mount examples/anchor_concrete.toml`` does the same.
"""

from pathlib import Path

import matplotlib.pyplot as plt

import mechdyn
from mechdyn.registry import get
from mechdyn.store import ResultStore

# the examples folder (this script runs from examples/gallery)
EXAMPLES = Path(globals().get("__file__", "gallery.py")).resolve().parents[1]
with ResultStore("sqlite://") as store:  # an in-memory database keeps the calibration
    result = get("mount").run(mechdyn.load(EXAMPLES / "anchor_concrete.toml"), store=store)
s = result.summary()
print(f"members, cone estimate  {s['member_stiffness_N_per_m'] / 1e6:.0f} MN/m")
print(f"members, FE (converged) {s['fe_stiffness_N_per_m'] / 1e6:.1f} MN/m")

# %%
# The FE reference over its mesh refinements, with the extrapolated value.
result.plots()["fe_convergence.png"]()

# %%
# The contact pressure between plate and concrete for each preload, against the threshold.
result.plots()["contact_pressure.png"]()
plt.show()
