"""
Press on its support: the force on the floor
============================================

Press A on the published one-degree-of-freedom support (SPEC §2): the steady state under the
mechanism's shaking force, computed exactly in the frequency domain, and the start-up from rest by
time integration. ``mechdyn support examples/press_on_support.toml`` does the same.
"""

from pathlib import Path

import matplotlib.pyplot as plt

import mechdyn
from mechdyn.registry import get

# the examples folder (this script runs from examples/gallery)
EXAMPLES = Path(globals().get("__file__", "gallery.py")).resolve().parents[1]
loaded = mechdyn.load(EXAMPLES / "press_on_support.toml")
result = get("support").run(loaded)

s = result.summary()
TONF = 9806.65
print(f"natural frequency {s['natural_frequencies_hz'][0]:.2f} Hz")
print(f"exciting force range    {s['inertia_force_range_N'] / TONF:.1f} tonf")
print(f"transmitted force range {s['transmitted_force_range_N'] / TONF:.1f} tonf")

# %%
# The force the machine puts on the floor against the exciting force, over one period.
result.plots()["transmitted_vs_exciting.png"]()

# %%
# The bed's displacement: the start-up from rest lands on the steady state.
result.plots()["displacement.png"]()
plt.show()
