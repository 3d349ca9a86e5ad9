"""The ``[analysis]`` table of a support model file: the coordinates kept, the start-up, gravity and
the settings of the vibration verdict, as :class:`mechdyn.support.spec.SupportSpec` carries them."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, model_validator

from mechdyn.io.fields import Acceleration, FileModel, Length
from mechdyn.units import STANDARD_GRAVITY

__all__ = ["AnalysisTable"]


class AnalysisTable(FileModel):
    dofs: Literal["planar", "spatial"] = "spatial"
    """``spatial`` (all six rigid-body coordinates) or ``planar`` (x–z with rocking about y)."""
    start_up_cycles: int = Field(default=5, ge=1, le=1000)
    """Load periods integrated from rest for the start-up."""
    start_up_method: Literal["exact", "DOP853", "RK45", "RK23", "Radau", "BDF", "LSODA", "duhamel"] = "exact"
    """How the start-up is computed: ``exact`` (the steady state plus the free vibration from rest, to
    round-off), a ``scipy.integrate.solve_ivp`` method, or ``duhamel`` (the convolution in state-space
    form)."""
    gravity: Acceleration = STANDARD_GRAVITY
    """Gravity, for the mounts' static deflection."""
    machine_group: Literal[1, 2] | None = None
    """ISO 20816-3 machine group of the vibration verdict: 1, large machines (300 kW to 50 MW, Table
    A.1); 2, medium machines (15 kW to 300 kW, Table A.2); by default 2, the stricter, and the verdict
    says so."""
    foundation: Literal["auto", "rigid", "flexible"] = "auto"
    """ISO 20816-3 foundation class of the vibration verdict; ``auto``: rigid when the lowest natural
    frequency on the mounts is at least 25 % above the running frequency, else flexible."""
    vibration_points: list[tuple[Length, Length, Length]] | None = Field(
        default=None,
        min_length=1,
        description="points of the frame [x, y, z] whose vibration velocity is judged by ISO 20816-3 "
        "(default: the mounts' tops, where each mount holds the machine)",
    )
    separation_margin: float = Field(default=0.2, gt=0.0, lt=1.0)
    """A natural frequency closer than this ratio to an exciting harmonic of the running speed is
    flagged (0.2: ±20 %)."""

    @model_validator(mode="before")
    @classmethod
    def _moved(cls, data: Any) -> Any:
        moved = [k for k in ("stiffness_factors", "damping_factors") if isinstance(data, dict) and k in data]
        if moved:
            raise ValueError(
                f"{' and '.join(moved)}: the influence of the support is a design study now; remove "
                "them and run `mechdyn study examples/studies/press_support_influence.toml` (any "
                "value of the file can be varied there)"
            )
        return data
