"""Measured frequency responses in, modes out, the model against the measurement (issue 47).

Read measured FRFs (:func:`read_uff` for Universal File dataset 58, :func:`read_csv`) into a
:class:`MeasuredFRF` in SI, identify the modes with their scatter and a stabilisation chart
(:func:`identify_modes`: LSCF poles from sdypy-EMA, LSFD residues), and pair them with a model's
modes by MAC (:func:`compare_modes`, :func:`mac`; points mapped to model coordinates by
:func:`observation_matrix`).
"""

from mechdyn._lazy import attach

__all__ = attach(
    __name__,
    {
        "IdentifiedModes": "identify",
        "MeasuredFRF": "data",
        "ModeComparison": "compare",
        "StabilisationChart": "identify",
        "compare_modes": "compare",
        "identify_modes": "identify",
        "mac": "identify",
        "observation_matrix": "compare",
        "read_csv": "data",
        "read_uff": "data",
    },
)
