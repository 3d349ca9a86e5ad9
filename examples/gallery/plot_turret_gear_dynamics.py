"""
Mill turret: dynamic factor over speed and parametric stability
===============================================================

Reference machine C, the milling path of the turret (SPEC §3), with both meshes from gear data
(``examples/turret_milling_startup.toml``): the mesh stiffness varies over each mesh cycle as the
generated teeth give it. At each speed of the motor the periodic steady state (harmonic balance)
gives the dynamic mesh force and the dynamic factor K_v, set against ISO 6336-1's K_v for the same
pairs; the Floquet multipliers of the time-periodic system say where a larger stiffness variation
would make the train unstable, which a Campbell diagram does not show.
``mechdyn simulate`` runs the same file in time (a start-up from rest, then cutting).
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import mechdyn
from mechdyn.gear_dynamics import GearSystem, speed_sweep, stability_chart
from mechdyn.units import convert

# the examples folder (this script runs from examples/gallery)
EXAMPLES = Path(globals().get("__file__", "gallery.py")).resolve().parents[1]
loaded = mechdyn.load(EXAMPLES / "turret_milling_startup.toml")
dynamics = loaded.settings.dynamics

# %%
# The time-varying system: each mesh's stiffness over its cycle from the gears (its backlash and
# transmission error are left out here: the steady state below is the linear one).
profiles = dynamics.system_options()["mesh_profiles"]
system = GearSystem.from_drivetrain(loaded.model, mesh_profiles=profiles)
pairs = {name: mesh.gear_pair for name, mesh in dynamics.meshes.items() if mesh.gear_pair is not None}
for mesh in system.meshes:
    amplitude, _ = pairs[mesh.name].mesh_cycle().harmonics(1)
    mean = convert(mesh.mean_stiffness, "N/m", "N/um")
    print(f"{mesh.name}: mean {mean:.0f} N/µm, first harmonic {100 * amplitude[0]:.0f} % of it")

# %%
# The periodic steady state from 600 to 12 000 rpm of the motor, which runs free on its torque-speed
# curve (the file's induction motor, its curve moved to each speed), 6.2 N·m drawn at the tool
# spindle: the dynamic factor of each mesh, and ISO 6336-1's K_v (Method B) for the same pair, which
# describes the pair alone on its own mesh mode (resonant near 24 000 rpm), not the train's modes.
sweep = speed_sweep(
    system,
    convert(np.linspace(600.0, 12000.0, 32), "rpm", "rad/s"),
    reference="1",
    load={"7": 6.2},
    motor=dynamics.inputs()[0],
    gear_pairs=pairs,
)
print(sweep.method)
table = sweep.tables()[0]
print(table.title)
for row in table.rows:
    print(dict(zip(table.columns[:4], row[:4], strict=True)))
sweep.plot()

# %%
# Stability over speed and stiffness variation ε of mesh 1 (its profile scaled about its mean):
# shaded where the largest Floquet multiplier exceeds one. The gears' own variation lies far below
# the unstable regions, which open only near twice a natural frequency over the mesh orders.
chart = stability_chart(
    system,
    convert(np.linspace(2000.0, 30000.0, 20), "rpm", "rad/s"),
    np.linspace(0.0, 0.8, 6),
    reference="1",
    mesh="mesh 1",
)
chart.plot()
plt.show()
