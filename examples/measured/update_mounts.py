"""From the tap test to the updated model: modes identified, compared, the mounts updated (issue 47).

    python examples/measured/update_mounts.py [--out FOLDER]

1. read the hammer test ``tap_test.uff`` (UFF 58 accelerances, 12 accelerometers on the four mount
   tops, blows at point 1 along z and point 4 along x; made by ``make_data.py``);
2. identify its modes (LSCF poles, LSFD shapes, with their scatter) between 3 and 28 Hz;
3. compare them with the modes of the designed model ``machine.toml`` (the accelerometer points
   are the mounts' positions, as the measurement file ``tap_test.toml`` maps them), paired by MAC;
4. update the mounts' stiffness and damping along x, y and z (every mount alike:
   ``mounts.*.stiffness.x`` …, ``mounts.*.damping.x`` …) from the frequencies and damping ratios,
   with their 95 % intervals and identifiability, and write the updated model file
   ``machine_updated.toml`` into FOLDER (default: the current folder);
5. predict the floor force of the spindle's unbalance (12.5 Hz) on the updated model with the band
   that the measurement leaves (the mounts' posterior carried through by sampling).

Steps 1–4 run from the measurement file ``tap_test.toml`` too::

    mechdyn modes-from-test examples/measured/tap_test.toml --write-updated machine_updated.toml

The machine that ``make_data.py`` built the test from has mounts of 0.6, 0.7 and 2.3 MN/m and
600, 700 and 2300 N·s/m.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import mechdyn
from mechdyn.measurement import compare_modes, identify_modes, read_uff, update_model
from mechdyn.support import modes, periodic_response

HERE = Path(__file__).resolve().parent
STIFFNESS = ["mounts.*.stiffness.x", "mounts.*.stiffness.y", "mounts.*.stiffness.z"]
DAMPING = ["mounts.*.damping.x", "mounts.*.damping.y", "mounts.*.damping.z"]


def floor_force_amplitude(loaded) -> list[float]:
    """The largest vertical force on the floor over the steady period of the machine's load, N."""
    r = periodic_response(loaded.model, loaded.settings.load)
    return [float(np.abs(r.transmitted_force).max())]


def main(out: Path, samples: int = 64) -> dict:
    """Run the five steps; print their tables; return the figures (for the tests)."""
    measured = read_uff(HERE / "tap_test.uff")
    found = identify_modes(measured, f_min_hz=3.0, f_max_hz=28.0)
    print("identified modes\n", found.to_frame().round(4).to_string(), "\n")

    designed = mechdyn.load(HERE / "machine.toml")
    points = dict(mechdyn.load(HERE / "tap_test.toml").model.mapping)  # the test file's [[points]]
    before = compare_modes(found, modes(designed.model), points)
    print("designed model against the test\n", before.to_frame().round(4).to_string(), "\n")

    # the damping ratios too (damping_error: the model's proportional-damping estimate against the
    # measured modes, 5 %), so that a prediction near a resonance carries the measured damping
    update = update_model(HERE / "machine.toml", found, STIFFNESS + DAMPING, points, damping_error=0.05)
    print("updated mounts\n", update.to_frame().to_string(), "\n")
    print(f"chi2 {update.chi2_before:.4g} -> {update.chi2_after:.4g}\n")
    written = update.save(out / "machine_updated.toml")
    print(f"wrote {written}\n")

    band = update.predict(floor_force_amplitude, ["floor_force_amplitude_N"], samples, seed=1)
    nominal = floor_force_amplitude(designed)[0]
    low, median, high = (band.distributions[0].quantiles[q].value for q in (0.025, 0.5, 0.975))
    print(
        f"floor force at 12.5 Hz: designed model {nominal:.0f} N; updated model {median:.0f} N "
        f"(95 % band {low:.0f} … {high:.0f} N)"
    )
    return {
        "modes": found,
        "before": before,
        "update": update,
        "written": written,
        "floor_force_designed_N": nominal,
        "floor_force_band_N": (low, median, high),
    }


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path.cwd(), help="folder for machine_updated.toml")
    main(parser.parse_args().out)
