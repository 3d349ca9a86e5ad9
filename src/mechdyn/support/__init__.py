"""The machine on its supports: steady-state and start-up vibration, floor forces, modes (SPEC §2).

Model the machine as a :class:`RigidBody` on :class:`Mount` s (:class:`MountedMachine`, or
:meth:`MountedMachine.single_dof` for the published one-degree-of-freedom model), load it with a
:class:`PeriodicLoad` (samples, harmonics, or a mechanism's shaking force and moment through
:meth:`PeriodicLoad.from_mechanism`), and ask for :func:`periodic_response` (exact, frequency
domain), :func:`startup_response` (time integration from rest), :func:`modes` and
:func:`influence`. A ``type = "support"`` model file holds all of it (``mechdyn support``).
"""

from mechdyn.support.excitation import CHANNELS, PeriodicLoad, Placement
from mechdyn.support.model import DOFS, PLANAR, SPATIAL, Mount, MountedMachine, RigidBody
from mechdyn.support.modes import SupportModes, elastic_centre, modes
from mechdyn.support.response import (
    SupportResponse,
    harmonic_response,
    influence,
    periodic_response,
    startup_response,
)

__all__ = [
    "CHANNELS",
    "DOFS",
    "PLANAR",
    "SPATIAL",
    "Mount",
    "MountedMachine",
    "PeriodicLoad",
    "Placement",
    "RigidBody",
    "SupportModes",
    "SupportResponse",
    "elastic_centre",
    "harmonic_response",
    "influence",
    "modes",
    "periodic_response",
    "startup_response",
]
