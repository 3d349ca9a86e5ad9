"""The backlash contact law of a gear mesh, compiled once (numba) for every caller.

A mesh j with total backlash b along its line of action sees the relative displacement
x = δ − e(τ) (the deflection less the static transmission error, m) and its rate ẋ (m/s). The
teeth touch on the drive flanks where x > 0, on the back flanks where x < −b and nowhere in between
(the dead zone). The force along the line of action is Kelvin–Voigt in contact,

    f = k h(x) + c ẋ,  h(x) = x (drive side),  h(x) = x + b (back side),

and 0 in the gap, so that ∂f/∂x = k and ∂f/∂ẋ = c where the mesh is in contact (active) and both are 0
in the gap (Kahraman & Singh, *J. Sound Vib.* 142 (1990) 49–75). Without backlash the mesh is
always on its drive flanks. The damping force is on where the teeth touch only: it may pull just
before they part.

:func:`mesh_force` is that law, once, for all its callers:

* the compiled right-hand side of the time integration (:mod:`._kernel`) and the forces, strain
  energy and contact of its result (:mod:`.simulate`), in the contact *mode* the events switch;
* the event-located flow that Newton's shooting integrates (:mod:`._nonsmooth`), likewise;
* the mesh forces along a periodic orbit (:mod:`.steady`) and :meth:`.system.MeshLink.force`, which
  have no discrete mode and take the region of x itself (``BY_SIGN``).

A mode given by the caller, not the sign of x, decides the force in the hybrid integrations: a
contact change located a rounding error on either side of its boundary must not make the force
chatter. :func:`mesh_forces` maps the law over arrays for the callers written in NumPy (one call for
many meshes or many instants, not one per element).

Compiled on first use and cached on disk, like :mod:`._kernel` (:func:`announce` says so where the
cache is empty); the modules that import it import numba. numba keys the cache of :mod:`._kernel`'s
functions, which call :func:`mesh_force`, on their own file only: after a change here, touch
``_kernel.py`` too (or clear the cache), lest the time integration keep the old law.
"""

import numba
import numpy as np

__all__ = ["BACK", "BY_SIGN", "DRIVE", "GAP", "NO_BACKLASH", "announce", "mesh_force", "mesh_forces"]

#: The contact modes: the drive flanks touch, the teeth are in the gap, the back flanks touch.
DRIVE, GAP, BACK = 0, 1, 2
#: The mode that asks :func:`mesh_force` for the region x lies in (no discrete contact state).
BY_SIGN = -1
#: The backlash of a mesh whose teeth never part (any negative value reads so), m.
NO_BACKLASH = -1.0


@numba.njit(cache=True, error_model="numpy")
def mesh_force(k, c, x, rate, gap, mode):
    """Force of one mesh along its line of action, with its spring term and whether it is in contact.

    Parameters
    ----------
    k : float
        Mesh stiffness k(τ) at the present phase, N/m.
    c : float
        Mesh damping c, N·s/m.
    x : float
        Relative displacement x = δ − e(τ), m.
    rate : float
        Its rate ẋ = δ̇ − e′(τ) τ̇, m/s.
    gap : float
        Total backlash b, m; negative (:data:`NO_BACKLASH`): none, the teeth never part.
    mode : int
        :data:`DRIVE`, :data:`GAP` or :data:`BACK` (the contact state of a hybrid integration), or
        :data:`BY_SIGN`: the region x lies in (drive where x > 0 or without backlash, back where
        x < −b, else the gap).

    Returns
    -------
    force : float
        f = k h + c ẋ in contact, 0 in the gap (NaN where k, ẋ or c is), N.
    h : float
        The spring's compression h: x on the drive flanks, x + b on the back flanks, 0 in the gap, m.
    active : float
        1.0 in contact, 0.0 in the gap: ∂f/∂x = k · active and ∂f/∂ẋ = c · active (dimensionless).

    Notes
    -----
    Kahraman & Singh, *J. Sound Vib.* 142 (1990) 49–75: the piecewise-linear backlash function of a
    spur pair with clearance, the mesh damping acting in contact only.
    """
    if mode == BY_SIGN:
        if gap < 0.0 or x > 0.0:
            mode = DRIVE
        elif x < -gap:
            mode = BACK
        else:
            mode = GAP
    if mode == GAP:  # no force, yet NaN where the state is NaN: a failed orbit stays visible
        return k * 0.0 + c * rate * 0.0, 0.0, 0.0
    h = x + gap if mode == BACK else x
    return k * h + c * rate, h, 1.0


@numba.njit(cache=True, error_model="numpy")
def mesh_forces(k, c, x, rate, gap, mode):
    """:func:`mesh_force` element by element over 1-D arrays of one length (float64; ``mode`` int64).

    Parameters
    ----------
    k : ndarray
        Mesh stiffnesses, N/m.
    c : ndarray
        Mesh dampings, N·s/m.
    x : ndarray
        Relative displacements, m.
    rate : ndarray
        Their rates, m/s.
    gap : ndarray
        Total backlashes, m (negative: none).
    mode : ndarray
        Contact modes, or :data:`BY_SIGN`.

    Returns
    -------
    force, h, active : ndarray
        As :func:`mesh_force`, N, m and dimensionless.
    """
    n = x.size
    force = np.empty(n)
    h = np.empty(n)
    active = np.empty(n)
    for i in range(n):
        force[i], h[i], active[i] = mesh_force(k[i], c[i], x[i], rate[i], gap[i], mode[i])
    return force, h, active


def announce() -> None:
    """Say on stderr, once per process, that the law compiles where it is not cached yet
    (:func:`mechdyn._compiled.announce`)."""
    from mechdyn._compiled import announce as announce_compile

    announce_compile(mesh_force, mesh_forces)
