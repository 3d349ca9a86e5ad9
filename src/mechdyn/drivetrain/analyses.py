"""The drivetrain's analyses in the registry: ``modal``, ``campbell``, ``frf``.

Each function takes the model a ``type = "drivetrain"`` file builds (its optional ``[campbell]`` and
``[response]`` tables are the defaults of the options) and returns a result of the protocol.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from mechdyn.errors import MechdynError
from mechdyn.registry import Analysis, ModelType, Option, Output, register, register_model_type
from mechdyn.units import convert

if TYPE_CHECKING:  # the numerical modules are imported when an analysis runs, not for --help
    from mechdyn.drivetrain.response import Method
    from mechdyn.vibration.eigen import Solver

__all__: list[str] = []

_MODAL_OUTPUTS = (
    Output("frequencies_hz", "natural frequencies of the flexible modes, ascending"),
    Output("rigid_body_modes", "number of rigid-body (0 Hz) modes set aside", ""),
    Output("rigid_gears", "whether every mesh was taken as a rigid constraint", ""),
    Output("solver", "the eigen solver that ran", ""),
    Output("modes", "per mode: frequency (Hz), dominant element and its share, unit-scaled shape", ""),
)


def _modal(
    loaded: Any,
    rigid_gears: bool = False,
    compare_rigid: bool = False,
    modes: int | None = None,
    solver: Solver = "auto",
) -> Any:
    from mechdyn.drivetrain.compare import compare_rigid as compare
    from mechdyn.drivetrain.modal import modal

    if rigid_gears and compare_rigid:
        raise MechdynError("give --rigid-gears or --compare-rigid, not both")
    if compare_rigid:
        return compare(loaded.model)
    modes = _default_modes(loaded.model, modes, "--modes N")
    return modal(loaded.model, rigid_gears=rigid_gears, n_modes=modes, solver=solver)


def _default_modes(model: Any, modes: int | None, how: str) -> int | None:
    """All modes of a small model; the lowest _DEFAULT_MODES of a large one, said on stderr. A number
    of modes whose shapes the run could not keep (its memory and its stored summary grow with modes ×
    disks) is refused before the work, with the number that fits."""
    n = len(model.dof_names)  # the disks and the nodes inside divided shafts
    if modes is not None and modes * n > _MAX_SHAPE_VALUES:
        raise MechdynError(
            f"{modes} modes of a {n}-disk model are {modes * n:,} shape values (about "
            f"{convert(modes * n * 200, 'B', 'GB'):.1f} GB while the run is stored); ask for at most "
            f"{max(1, _MAX_SHAPE_VALUES // n)} ({how})"
        )
    if modes is not None or n <= _ALL_MODES_UP_TO:
        return modes
    # all modes of a 10⁴-disk chain are 10⁸ numbers (GBs); nobody reads past the lowest few
    import warnings

    from mechdyn.errors import ModelWarning

    warnings.warn(
        f"{n} disks: computing the lowest {_DEFAULT_MODES} flexible modes; {how} for another number",
        ModelWarning,
        stacklevel=3,
    )
    return _DEFAULT_MODES


# a model with more disks than this gets its lowest _DEFAULT_MODES modes unless --modes says otherwise
_ALL_MODES_UP_TO = 200
_DEFAULT_MODES = 20
# the most mode-shape values one run keeps (every mode of a 1000-disk model); beyond, --modes is refused
_MAX_SHAPE_VALUES = 1_000_000


def _modal_batch(loaded: Any, columns: Any, keys: Any, **options: Any) -> Any:
    from mechdyn.drivetrain.batch import modal_batch

    return modal_batch(loaded, columns, keys, **options)


def _where(loaded: Any) -> str:
    return loaded.source.path if loaded.source is not None else repr(loaded.name)


def _file_settings(loaded: Any) -> tuple[Any, Any]:
    """The file's [campbell] and [response] settings (None for a model built in Python)."""
    s = loaded.settings
    return (s.campbell, s.response) if s is not None else (None, None)


def _campbell(
    loaded: Any,
    speed_range: tuple[float, float] | None = None,
    reference: str | None = None,
    rigid_gears: bool = False,
) -> Any:
    from mechdyn.drivetrain.campbell import campbell

    model = loaded.model
    camp, _ = _file_settings(loaded)
    speed = speed_range or (camp.speed_range if camp else None)
    if speed is None:
        raise MechdynError(
            f"{_where(loaded)}: no speed range; add a [campbell] table with speed_range, "
            "or pass --speed-range LOW HIGH (e.g. '0 rpm' '3000 rpm')"
        )
    kw = {"shaft_orders": camp.shaft_orders, "mesh_orders": camp.mesh_orders} if camp else {}
    ref = reference or (camp.reference_disk if camp else None)
    n_modes = _default_modes(model, None, "call mechdyn.drivetrain.campbell with modes=")
    if n_modes is not None:
        from mechdyn.drivetrain.modal import modal

        kw["modes"] = modal(model, n_modes=n_modes, rigid_gears=rigid_gears)
    return campbell(model, speed, reference=ref, rigid_gears=rigid_gears, **kw)


def _frf(
    loaded: Any,
    excite: list[str] | None = None,
    frequency_range: tuple[float, float] | None = None,
    points: int | None = None,
    damping: float | None = None,
    method: Method = "auto",
) -> Any:
    import numpy as np

    from mechdyn.drivetrain.damping import ModalDamping
    from mechdyn.drivetrain.response import frf

    model = loaded.model
    _, resp = _file_settings(loaded)
    if resp is None and not excite:
        raise MechdynError(f"{_where(loaded)}: no excitation; add a [response] table, or pass --excite DISK")
    excitation = {d: 1.0 + 0j for d in excite} if excite else resp.excitation
    lo, hi = frequency_range or (resp.frequency_range if resp else (1.0, 1e4))
    n = points or (resp.points if resp else 1000)
    if damping is not None:
        zeta = ModalDamping(damping)
    else:
        zeta = resp.damping if resp else ModalDamping()
    outputs = tuple(resp.outputs) if resp and resp.outputs else tuple(model.disk_names)
    return frf(model, np.geomspace(lo, hi, n), excitation, damping=zeta, outputs=outputs, method=method)


# the files its analyses run on: the builder returns the Drivetrain; the analysis tables are read apart
register_model_type(
    ModelType(
        "drivetrain",
        builder="mechdyn.drivetrain.schema:build",
        schema="mechdyn.drivetrain.schema:DrivetrainFile",
        settings="mechdyn.drivetrain.schema:settings",
        model_class="mechdyn.drivetrain.model:Drivetrain",
        writer="mechdyn.drivetrain.save:to_toml",
    )
)

register(
    Analysis(
        "modal",
        ("drivetrain",),
        _modal,
        "natural frequencies, mode shapes and modal energy of a drivetrain",
        headline=("frequencies_hz",),
        batch=_modal_batch,
        options=(
            Option("rigid_gears", "flag", "treat every gear mesh as a rigid constraint"),
            Option(
                "compare_rigid",
                "flag",
                "also solve with rigid gears and pair the modes by shape (MAC)",
            ),
            Option(
                "modes",
                "int",
                f"number of lowest flexible modes (default: all up to {_ALL_MODES_UP_TO} disks, else "
                f"the lowest {_DEFAULT_MODES})",
                minimum=1,
            ),
            Option(
                "solver",
                "choice",
                "eigen solver (default: auto)",
                choices=("auto", "dense", "banded", "sparse"),
            ),
        ),
        outputs=(
            *_MODAL_OUTPUTS,
            Output("comparison", "with --compare-rigid: each flexible mode, its rigid partner, MAC", ""),
            Output("rigid_frequencies_hz", "with --compare-rigid: the rigid-gear natural frequencies"),
        ),
        examples=(
            "mechdyn modal examples/turret_indexing.toml --compare-rigid --plots plots",
            "mechdyn modal examples/turret_milling.toml --modes 3 --json",
        ),
    )
)

register(
    Analysis(
        "campbell",
        ("drivetrain",),
        _campbell,
        "Campbell (interference) diagram and its crossings",
        headline=("frequencies_hz",),
        options=(
            Option(
                "speed_range",
                "quantity",
                "reference speed range, e.g. '0 rpm' '3000 rpm' (default: the file's [campbell])",
                unit="rad/s",
                nargs=2,
                metavar=("LOW", "HIGH"),
            ),
            Option("reference", "text", "disk whose speed is the abscissa", metavar="DISK"),
            Option("rigid_gears", "flag", "natural frequencies with rigid gears"),
        ),
        outputs=(
            Output("reference_disk", "the disk whose speed is the abscissa", ""),
            Output("speed_range_rpm", "the reference speed range"),
            Output("frequencies_hz", "natural frequencies of the flexible modes"),
            Output("rigid_body_modes", "number of rigid-body modes", ""),
            Output("lines", "excitation lines: label, kind, cycles per revolution of the reference", ""),
            Output("crossings", "line, mode, frequency (Hz) and reference speed (rpm) of each crossing", ""),
        ),
        examples=(
            "mechdyn campbell examples/turret_milling.toml --speed-range '0 rpm' '6000 rpm' --plots plots",
        ),
    )
)

register(
    Analysis(
        "frf",
        ("drivetrain",),
        _frf,
        "steady-state response to harmonic torques",
        headline=("natural_frequencies_hz",),
        options=(
            Option(
                "excite",
                "names",
                "unit torque (1 N·m) at these disks, replacing [response]",
                metavar="DISK",
            ),
            Option(
                "frequency_range",
                "quantity",
                "e.g. '10 Hz' '5 kHz' (default: the file's [response], else 1 Hz to 10 kHz)",
                unit="Hz",
                nargs=2,
                metavar=("LOW", "HIGH"),
            ),
            Option("points", "int", "number of frequencies (log-spaced), at least 2", minimum=2),
            Option("damping", "float", "modal damping ratio for every mode, e.g. 0.02", minimum=0.0),
            Option(
                "method",
                "choice",
                "sum the modes where exact, else solve at each frequency (auto); or insist on one",
                choices=("auto", "modal", "direct"),
            ),
        ),
        outputs=(
            Output("excitation", "complex torque amplitude at each excited disk, N·m", ""),
            Output("frequency_range_hz", "lowest and highest excitation frequency"),
            Output("points", "number of frequencies", ""),
            Output("damping", "the added damping", ""),
            Output("method", "how the response was computed: modal superposition, or direct and why", ""),
            Output("natural_frequencies_hz", "undamped natural frequencies"),
            Output("peaks", "per output disk and element: largest amplitude, unit, frequency (Hz)", ""),
        ),
        examples=("mechdyn frf examples/turret_indexing.toml --points 400 --plots plots",),
    )
)
