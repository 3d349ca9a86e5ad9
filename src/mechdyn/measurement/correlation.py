"""The measurement file's analysis: the modes identified from the test, paired with the tested model's,
the model updated where the file asks, and the FRFs of both at the measured points.

One function over the pieces of :mod:`mechdyn.measurement` (:func:`identify_modes`,
:func:`compare_modes`, :func:`update_model`, :func:`simulate_frf` without noise for the model's FRFs,
and :func:`mechdyn.measurement.prediction.predict` for the file's ``[predict]`` table),
read from a measurement file (:mod:`mechdyn.measurement.schema`); its result
(:class:`TestCorrelation`) follows the result protocol, so the command line, the results database,
the run report and the dashboard show it as they show any analysis.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from mechdyn.measurement.correlation_result import TestCorrelation

__all__ = ["TestCorrelation", "modes_from_test"]


def model_frf(model: Any, measured: Any, mapping: Any) -> Any:
    """The FRFs of a model at the measured points, for the measured references and lines, noise-free.

    H(ω) = B_out (K − ω²M + iωC)⁻¹ B_refᵀ, in the measured kind (receptance, mobility or
    accelerance): :func:`mechdyn.measurement.simulate_frf` with no noise (Ewins, *Modal Testing*,
    2nd ed., 2000, §2.5).

    Parameters
    ----------
    model : MountedMachine or Drivetrain
        The model (its mass, stiffness and damping matrices).
    measured : MeasuredFRF
        The measurement whose outputs, references, lines and kind are taken.
    mapping : mapping
        Measurement point → model coordinate or location (x, y, z) in m.

    Returns
    -------
    MeasuredFRF
        Source ``"model"``.
    """
    from dataclasses import replace

    from mechdyn.measurement.synthetic import simulate_frf

    H = simulate_frf(
        model,
        measured.outputs,
        measured.references,
        measured.frequencies_hz,
        mapping,
        kind=measured.kind,
        relative_noise=0.0,
        noise_floor=0.0,
    )
    return replace(H, source="model")


def modes_from_test(
    spec: Any,
    *,
    max_order: int | None = None,
    bootstrap: int | None = None,
    starts: int | None = None,
    no_update: bool = False,
    write_updated: str | Path | None = None,
    samples: int | None = None,
) -> TestCorrelation:
    """Identify a test's modes, pair them with the tested model's, update the model, and predict the
    file's ``[predict]`` outputs with the band the test leaves.

    Parameters
    ----------
    spec : MeasurementSpec
        A measurement file as read (``mechdyn.load(path).model``).
    max_order : int, optional
        Highest pole-pair order of the stabilisation chart (default: the file's ``max_order``).
    bootstrap : int, optional
        Bootstrap data sets for the modes' scatter (default: the file's).
    starts : int, optional
        Sobol start points of the updating's global search (default: the file's ``[updating]``).
    no_update : bool
        Identify and compare only, even when the file has ``[[update]]`` rows.
    write_updated : str or Path, optional
        Write the updated model file here (with its analysis settings); only with ``[[update]]`` rows.
    samples : int, optional
        Samples of the prediction's band (default: the file's ``[predict]`` samples); checked as the
        file's are.

    Returns
    -------
    TestCorrelation

    Raises
    ------
    mechdyn.measurement.updating.UpdateError
        When the file asks for an update and no measured mode pairs with a model mode, or
        ``write_updated`` is given without anything to update.
    mechdyn.errors.ModelFileError
        When a ``[predict]`` output names no number of its analysis' summary, or ``samples`` is too
        few.
    """
    from mechdyn.measurement.compare import compare_modes
    from mechdyn.measurement.identify import identify_modes
    from mechdyn.measurement.updating import UpdateError, _default_modes, update_model

    ident = spec.identification
    found = identify_modes(
        spec.measured,
        f_min_hz=spec.f_min_hz,
        f_max_hz=spec.f_max_hz,
        max_order=ident.max_order if max_order is None else max_order,
        bootstrap=ident.bootstrap if bootstrap is None else bootstrap,
    )
    tested = spec.tested
    before = compare_modes(found, _default_modes(tested), spec.mapping, min_mac=ident.min_mac)
    frf_before = model_frf(tested.model, spec.measured, spec.mapping)
    update = frf_after = written = None
    if spec.parameters and not no_update:
        u = spec.updating
        update = update_model(
            tested.source,
            found,
            list(spec.parameters),
            spec.mapping,
            shape_weight=u.shape_weight,
            prior_uncertainty=list(spec.prior_scatter),
            search=u.search,
            starts=u.starts if starts is None else starts,
            max_uncertainty=u.max_uncertainty,
            min_mac=ident.min_mac,
            model_error=u.model_error,
            damping_error=u.damping_error,
            posterior=u.posterior,
            samples=u.samples,
        )
        frf_after = model_frf(update.load().model, spec.measured, spec.mapping)
        if write_updated is not None:
            written = str(update.save(write_updated))
    elif write_updated is not None:
        why = "--no-update is given" if spec.parameters else "the file has no [[update]] rows"
        raise UpdateError(f"write_updated={str(write_updated)!r}: nothing is updated ({why})")
    prediction = _prediction(spec, update, samples)
    return TestCorrelation(
        name=spec.name,
        data_file=spec.data_file,
        model_file=spec.model_file,
        f_min_hz=spec.f_min_hz,
        f_max_hz=spec.f_max_hz,
        measured=spec.measured,
        modes=found,
        before=before,
        model_frf=frf_before,
        update=update,
        updated_frf=frf_after,
        written=written,
        prediction=prediction,
    )


def _prediction(spec: Any, update: Any, samples: int | None) -> Any:
    """The file's ``[predict]`` analysis on the tested and the updated model, with its band."""
    from dataclasses import replace

    from mechdyn.measurement.prediction import check_samples, predict
    from mechdyn.measurement.updating import UpdateError

    p = spec.predict
    if p is None:
        if samples is not None:
            raise UpdateError(f"samples={samples!r}: the file has no [predict] table, nothing is predicted")
        return None
    if samples is not None:
        check_samples(p.path, samples, p.method, where="samples (the command's --samples)")
        p = replace(p, samples=int(samples))
    return predict(p, spec.tested, update)
