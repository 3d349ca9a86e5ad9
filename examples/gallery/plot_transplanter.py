"""
Rice transplanter: the planting mechanism from its design variables
===================================================================

Reference machine D (RP-1): a rotating carrier with eccentric gears that turn the planting forks
(SPEC §6). The model is built from the design variables of ``examples/transplanter_rp1_design.toml``;
``mechdyn mechanism`` on that file does the same.
"""

from pathlib import Path

import matplotlib.pyplot as plt

import mechdyn
from mechdyn.registry import get

# the examples folder (this script runs from examples/gallery)
EXAMPLES = Path(globals().get("__file__", "gallery.py")).resolve().parents[1]
result = get("mechanism").run(mechdyn.load(EXAMPLES / "transplanter_rp1_design.toml"))
s = result.summary()
print(f"largest tooth force {s['tooth_force_max_N']:.1f} N")
print(f"driving torque range {s['driving_torque_range_Nm']:.2f} N·m")

# %%
# The fork tips' paths relative to the machine and over the field.
plots = result.plots()
for name in plots:
    if name.startswith("paths") or name.startswith("trajector"):
        plots[name]()

# %%
# The joint and tooth forces over one revolution of the carrier.
plots["joint_forces.png"]()
plt.show()
