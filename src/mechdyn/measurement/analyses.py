"""The measurement's file type and analysis in the registry: ``modes-from-test`` (the modes identified
from a measured test, paired with the tested model's by MAC, the model updated, and the file's
``[predict]`` analysis run on the updated model with its band)."""

from __future__ import annotations

from typing import Any

from mechdyn.registry import Analysis, ModelType, Option, Output, register, register_model_type

__all__: list[str] = []


def _modes_from_test(loaded: Any, **options: Any) -> Any:
    from mechdyn.measurement.correlation import modes_from_test

    return modes_from_test(loaded.model, **options)


# the files its analysis runs on: the builder returns a MeasurementSpec (the test, the tested model,
# the points' mapping), which is both the model and its settings
register_model_type(
    ModelType(
        "measurement",
        builder="mechdyn.measurement.schema:build",
        schema="mechdyn.measurement.schema:MeasurementFile",
    )
)

register(
    Analysis(
        "modes-from-test",
        ("measurement",),
        _modes_from_test,
        "modes identified from a measured test, paired with the model's by MAC; the model updated, and "
        "an analysis of it predicted with the band the test leaves",
        model_noun="measurement",
        headline=("identified_modes", "frequency_error_max_percent", "updated_frequency_error_max_percent"),
        options=(
            Option("max_order", "int", "highest pole-pair order of the stabilisation chart", minimum=4),
            Option("bootstrap", "int", "bootstrap data sets for the modes' scatter (0: none)", minimum=0),
            Option("starts", "int", "Sobol start points of the updating's global search", minimum=0),
            Option("no_update", "flag", "identify and compare only; leave the [[update]] rows aside"),
            Option(
                "write_updated",
                "text",
                "write the updated model file (TOML) to this path",
                metavar="PATH",
                writes=True,
            ),
            Option(
                "samples",
                "int",
                "samples of the [predict] band (default: the file's [predict] samples)",
                minimum=8,
            ),
        ),
        outputs=(
            Output("data_file", "the measured data file, as the measurement file names it", ""),
            Output("tested_model_file", "the model file the test is compared with", ""),
            Output("band_min_hz", "lower end of the identification band"),
            Output("band_max_hz", "upper end of the identification band"),
            Output("measured_points", "measurement points in the data", ""),
            Output("identified_modes", "modes found stable in the band", ""),
            Output("frequencies_hz", "identified natural frequencies"),
            Output("frequency_scatter_hz", "standard uncertainty of each identified frequency"),
            Output("damping_ratios", "identified modal damping ratios", "1"),
            Output("damping_scatter", "standard uncertainty of each identified damping ratio", "1"),
            Output(
                "paired_modes", "measured modes paired with a model mode (MAC at or above the threshold)", ""
            ),
            Output("model_frequencies_hz", "the paired model modes' frequencies"),
            Output("frequency_error_percent", "model minus measured frequency of each pair, over measured"),
            Output("damping_error_percent", "model minus measured damping ratio of each pair, over measured"),
            Output("mac", "modal assurance criterion of each pair", "1"),
            Output("frequency_error_max_percent", "largest frequency error of a pair"),
            Output("mac_min", "smallest MAC of a pair", "1"),
            Output("updated_parameters", "model values updated", ""),
            Output("identifiable_parameters", "updated values the measured modes pin down", ""),
            Output("updated_model_frequencies_hz", "the paired modes' frequencies of the updated model"),
            Output("updated_frequency_error_percent", "frequency error of each pair after updating"),
            Output("updated_damping_error_percent", "damping error of each pair after updating"),
            Output("updated_mac", "MAC of each pair after updating", "1"),
            Output("updated_frequency_error_max_percent", "largest frequency error of a pair after updating"),
            Output("chi2_before", "weighted squared residuals before updating", "1"),
            Output("chi2_after", "weighted squared residuals after updating", "1"),
            Output("birge_ratio", "factor the covariance was scaled by for residuals above the scatter", "1"),
            Output(
                "updated_values", "each updated value (SI) with its 95 % interval and identifiability", ""
            ),
            Output(
                "posterior_method",
                "how the updated values' uncertainty was found: linear (Laplace covariance) or sampling",
                "",
            ),
            Output(
                "posterior_diagnostics",
                "with posterior = sampling: effective sample size, Pareto k, validity in words",
                "",
            ),
            Output("updated_model_file", "the updated model file written (with --write-updated)", ""),
            Output("prediction_analysis", "the analysis of the tested model the [predict] table runs", ""),
            Output("prediction_samples", "model evaluations of the prediction's band (0: no band)", ""),
            Output(
                "predicted",
                "each [predict] output (SI): the tested model's and the updated model's value, the median "
                "and the 95 % band (2.5 % and 97.5 % quantiles) over the updated values' posterior with "
                "the confidence interval of each end, and whether a band is claimed",
                "",
            ),
        ),
        examples=(
            "mechdyn modes-from-test examples/measured/tap_test.toml --plots plots",
            "mechdyn modes-from-test examples/measured/tap_test.toml --write-updated machine_updated.toml",
        ),
    )
)
