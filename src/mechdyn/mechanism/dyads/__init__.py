"""The fast path: closed-form dyads, vectorised over crank angles *and* design variants.

Most linkages decompose into a crank and Assur groups of class II — RRR dyads (a joint between two
links whose other ends are known) and RRP dyads (a link end sliding on a frame guide) — plus rigid
bodies whose points follow from two known ones. For those, positions have closed forms (circle and
circle-line intersections, the branch taken from each variant's drawing), and velocities and
accelerations come from the differentiated constraints of each dyad, 2×2 and 1×1 linear systems
solved in closed form: the constraint Jacobian is block-triangular in this order. (E.g. Norton,
*Design of Machinery*, ch. 4–7; Hansen's Assur-group method.) No Newton iterations, no loops over
angles or variants: the whole study is a few array expressions.

Every load follows, in the same compiled pass, from the constraint multipliers λ, solved group by
group from the output back to the crank (Assur groups are statically determinate: each dyad's six
Newton–Euler equations reduce, by moments about its inner pin, to a 2×2 system solved by Cramer's
rule; e.g. Norton, *Design of Machinery*, ch. 11; Uicker, Pennock & Shigley, ch. 14): the joint
forces, the driving torque −λ_last, and the frame's share (its joints' reactions and the motor's).
They are the multipliers of the general engine's equations Φ_qᵀ λ = Q − M q̈, solved here in their
block-triangular order; the tests compare every load with the general engine's dense solve.
Mechanisms that do not decompose (closed loops of higher class, sliders on moving guides) are
refused here and run on the general engine.

The package by job: :mod:`.decomposition` (the plan: the order in which the points become known),
:mod:`.arguments` (the plan and the loads encoded for the kernel, :class:`~.arguments.KernelArgs`),
:mod:`._kernel` (the compiled kernel, motion and λ in one pass), :mod:`.run` (:func:`cycle`),
:mod:`.results` (:class:`CycleBatch`), :mod:`.angles` (the crank angles of a cycle), and
:mod:`.summary` with :mod:`._reduce` (:func:`cycle_summary`: the scalar figures alone, reduced in
compiled code). Variant *models* in one evaluation, and the general engine's batch for what does not
decompose: :mod:`mechdyn.mechanism.designs`.
"""

from mechdyn.mechanism.dyads.decomposition import NotDecomposable, plan
from mechdyn.mechanism.dyads.decomposition import Step as Step  # the plan's steps, as before
from mechdyn.mechanism.dyads.results import CycleBatch
from mechdyn.mechanism.dyads.run import cycle
from mechdyn.mechanism.dyads.summary import CycleSummary, cycle_summary

__all__ = [
    "CycleBatch",
    "CycleSummary",
    "NotDecomposable",
    "cycle",
    "cycle_summary",
    "plan",
]
