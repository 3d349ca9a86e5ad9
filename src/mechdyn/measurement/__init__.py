"""Measured frequency responses in, modes out, the model against the measurement (issue 47).

Read measured FRFs (:func:`read_uff` for Universal File dataset 58, :func:`read_csv`) into a
:class:`MeasuredFRF` in SI, or identified mode shapes (dataset 55, :func:`read_uff_modes`);
identify the modes with their scatter and a stabilisation chart (:func:`identify_modes`: LSCF
poles from sdypy-EMA, LSFD residues, refined together by nonlinear least squares); read one mode as
a mount's stiffness and damping (:func:`single_dof`); pair them with a model's modes by MAC
(:func:`compare_modes`, :func:`mac`; points mapped to model coordinates by
:func:`observation_matrix`); and update the model's values so that its modes match, with their
uncertainty and identifiability (:func:`update_model`, a :class:`ModelUpdate`).
:func:`simulate_frf` makes synthetic measurements of a known model. A measurement model file
(``[model] type = "measurement"``: the data, the tested model, the points' mapping, the values to
update) runs the whole loop as ``mechdyn modes-from-test`` (:func:`modes_from_test`, a
:class:`TestCorrelation`).
"""

from mechdyn._lazy import attach

__all__ = attach(
    __name__,
    {
        "IdentifiedModes": "identify",
        "MeasuredFRF": "data",
        "ModelUpdate": "update_result",
        "ModeComparison": "compare",
        "PosteriorWarning": "posterior",
        "Prediction": "prediction",
        "SampledPosterior": "posterior",
        "SingleDof": "sdof",
        "StabilisationChart": "identify",
        "TestCorrelation": "correlation_result",
        "compare_modes": "compare",
        "identify_modes": "identify",
        "mac": "identify",
        "modes_from_test": "correlation",
        "observation_matrix": "compare",
        "plot_frf_overlay": "plots",
        "read_csv": "data",
        "read_uff": "data",
        "read_uff_modes": "modefile",
        "simulate_frf": "synthetic",
        "single_dof": "sdof",
        "update_model": "updating",
    },
)
