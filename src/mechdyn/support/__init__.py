"""The machine on its supports: steady-state and start-up vibration, floor forces, modes (SPEC §2).

Model the machine as a :class:`RigidBody` on :class:`Mount` s (:class:`MountedMachine`, or
:meth:`MountedMachine.single_dof` for the published one-degree-of-freedom model), load it with a
:class:`PeriodicLoad` (samples, harmonics, a mechanism's shaking force and moment through
:meth:`PeriodicLoad.from_mechanism`, or unbalanced :class:`Rotor` s through
:meth:`PeriodicLoad.from_unbalance`), and ask for :func:`periodic_response` (exact, frequency
domain), :func:`startup_response` (time integration from rest), :func:`modes` and, for rotors,
:func:`unbalance_sweep` (floor force and isolation over their speed range). A ``type = "support"``
model file holds all of it (``mechdyn support``).
"""

from mechdyn._lazy import attach

__all__ = attach(
    __name__,
    {
        "CHANNELS": "excitation",
        "DOFS": "model",
        "Foundation": "foundation",
        "FoundationSystem": "coupled",
        "Soil": "foundation",
        "floor_vibration": "floor",
        "Mount": "model",
        "MountedMachine": "model",
        "PLANAR": "model",
        "PeriodicLoad": "excitation",
        "Placement": "excitation",
        "RigidBody": "model",
        "Rotor": "unbalance",
        "SPATIAL": "model",
        "SupportModes": "modes",
        "SupportResponse": "response",
        "UnbalanceSweep": "sweep",
        "elastic_centre": "modes",
        "harmonic_response": "response",
        "modes": "modes",
        "periodic_response": "response",
        "startup_response": "response",
        "unbalance_sweep": "sweep",
    },
)
