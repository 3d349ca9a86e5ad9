"""
Link-drive press: loads over one crank revolution
=================================================

Reference machine A, a 15 rpm six-bar link-drive press (SPEC §1). The inverse dynamics gives every
joint load, the driving torque, the inertia forces and the shaking force and moment over the cycle;
``mechdyn mechanism examples/press_link_drive.toml`` prints the same summary.
"""

from pathlib import Path

import matplotlib.pyplot as plt

import mechdyn
from mechdyn.mechanism import inverse_dynamics

# the examples folder (this script runs from examples/gallery)
EXAMPLES = Path(globals().get("__file__", "gallery.py")).resolve().parents[1]
press = mechdyn.load(EXAMPLES / "press_link_drive.toml").model
result = inverse_dynamics(press, 360)

s = result.summary()
TONF = 9806.65
print(f"stroke {s['stroke_m'] * 1e3:.1f} mm, top dead centre at {s['tdc_deg']:.2f}°")
print(f"inertia force {s['inertia_force_max_N'] / TONF:+.1f} / {s['inertia_force_min_N'] / TONF:+.1f} tonf")
print(f"power balance residual {s['power_balance_residual_relative']:.1e}")

# %%
# The slide's inertia force against the crank angle, with the dead centres marked.
result.plots()["inertia_forces.png"]()

# %%
# The driving torque the motor applies to the crank.
result.plots()["driving_torque.png"]()

# %%
# The linkage drawn at several crank angles.
result.plots()["frames.png"]()
plt.show()
