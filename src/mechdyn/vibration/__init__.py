"""The linear-vibration core shared by drivetrains and machines on mounts.

One eigen path (:func:`solve_eigen`: dense, banded and sparse), one dynamic stiffness
K + iωC − ω²M solved frequency by frequency (:func:`harmonic_solve`, memory independent of the
number of frequencies), one modal interface (:class:`Modes`: circular frequencies in rad/s, ``frequencies_hz``
in Hz, mass-normalised shapes, kinetic-energy shares) and one check of assembled matrices
(:func:`check_matrices`: symmetry, semi-definiteness, rigid-body mode count). :mod:`mechdyn.drivetrain`
and :mod:`mechdyn.support` build their matrices from their models and hand them to this core.
"""

from mechdyn._lazy import attach

__all__ = attach(
    __name__,
    {
        "SOLVERS": "eigen",
        "Modes": "modes",
        "check_matrices": "checks",
        "dynamic_stiffness": "harmonic",
        "harmonic_solve": "harmonic",
        "modal_superposition": "harmonic",
        "solve_eigen": "eigen",
    },
)
