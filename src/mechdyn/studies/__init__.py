"""Design studies (SPEC §7): parameters by their path in the model file, sweeps, sensitivities,
constrained optimization and synthesis, every variant stored, resumable, on a Dask cluster.

Read a study file with :func:`load_study` (or build a :class:`Study` in Python) and run it with
:func:`run_study`; ``mechdyn study FILE`` does both. Variants are evaluated through the analysis
registry: a block of mechanism variants goes through the batched engine at once, anything else is
built from its files and run one by one, with the same numbers.
"""

from mechdyn._lazy import attach

__all__ = attach(
    __name__,
    {
        "Constraint": "outputs",
        "Evaluator": "evaluate",
        "ModelTree": "paths",
        "Objective": "outputs",
        "Parameter": "parameters",
        "Study": "plan",
        "StudyError": "errors",
        "StudyResult": "result",
        "Watched": "outputs",
        "load_studies": "study",
        "load_study": "study",
        "recompute": "run",
        "run_studies": "run",
        "run_study": "run",
    },
)
