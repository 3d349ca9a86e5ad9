"""
Spur pair: mesh stiffness over a mesh cycle against ISO 6336-1
==============================================================

A standard steel spur pair (module 2 mm, 20/40 teeth, 20 mm face): the stiffness of one tooth pair
term by term, the mesh stiffness over one mesh cycle, and ISO 6336-1 Method B's c′ and c_γα for
comparison. ``mechdyn gear examples/spur_pair.toml`` does the same.
"""

from pathlib import Path

import matplotlib.pyplot as plt

import mechdyn
from mechdyn.registry import get

# the examples folder (this script runs from examples/gallery)
EXAMPLES = Path(globals().get("__file__", "gallery.py")).resolve().parents[1]
result = get("gear").run(mechdyn.load(EXAMPLES / "spur_pair.toml"))
s = result.summary()
b_mm = s["face_width_m"] * 1e3
print(f"contact ratio {s['contact_ratio']:.3f}")
print(f"mean mesh stiffness {s['mesh_stiffness_mean_N_per_m'] / b_mm / 1e6:.1f} N/(mm·µm)")
print(f"ISO c_γα            {s['iso_c_gamma_N_per_mm_um']:.1f} N/(mm·µm)")

# %%
# The mesh stiffness over one mesh cycle: two tooth pairs in contact, then one.
next(iter(result.plots().values()))()
plt.show()
