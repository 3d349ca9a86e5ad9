"""The machine on its supports: steady-state and start-up vibration, floor forces, modes (SPEC §2).

Model the machine as a :class:`RigidBody` on :class:`Mount` s (:class:`MountedMachine`, or
:meth:`MountedMachine.single_dof` for the published one-degree-of-freedom model), load it with a
:class:`PeriodicLoad` (samples, harmonics, or a mechanism's shaking force and moment through
:meth:`PeriodicLoad.from_mechanism`), and ask for :func:`periodic_response` (exact, frequency
domain), :func:`startup_response` (time integration from rest), :func:`modes` and
:func:`influence`. A ``type = "support"`` model file holds all of it (``mechdyn support``).
"""

from mechdyn._lazy import attach

__all__ = attach(
    __name__,
    {
        "CHANNELS": "excitation",
        "DOFS": "model",
        "Mount": "model",
        "MountedMachine": "model",
        "PLANAR": "model",
        "PeriodicLoad": "excitation",
        "Placement": "excitation",
        "RigidBody": "model",
        "SPATIAL": "model",
        "SupportModes": "modes",
        "SupportResponse": "response",
        "elastic_centre": "modes",
        "harmonic_response": "response",
        "modes": "modes",
        "periodic_response": "response",
        "startup_response": "response",
    },
)
