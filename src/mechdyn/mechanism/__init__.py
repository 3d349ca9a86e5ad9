"""Planar mechanisms: kinematics, inverse dynamics, shaking force and moment (SPEC §1)."""
