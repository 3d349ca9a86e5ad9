"""Golden results of the reference machines and the gear and mount examples.

Every scalar (and list of scalars) of each case's ``summary()`` is kept in ``tests/golden/CASE.json``
with its tolerance beside it, so that any change to a published figure shows in review as a diff of
these files. Regenerate them, after checking that a change is intended, with::

    python tests/test_golden.py --regenerate
"""

from __future__ import annotations

import json
import math
import sys
import warnings
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
GOLDEN = HERE / "golden"
ROOT = HERE.parent
REGENERATE = "python tests/test_golden.py --regenerate"

# case → (analysis, example file, options, relative tolerance)
CASES = {
    "A_press_mechanism": ("mechanism", "press_link_drive.toml", {}, 1e-9),
    "A_press_on_support": ("support", "press_on_support.toml", {}, 1e-9),
    "A_press_on_mounts": ("support", "press_on_mounts.toml", {}, 1e-9),
    "A_press_on_pads": ("support", "press_on_pads.toml", {}, 1e-9),
    "mount_press_pad": ("mount", "press_pad.toml", {}, 1e-9),
    "B_turret_indexing": ("modal", "turret_indexing.toml", {"compare_rigid": True}, 1e-9),
    "C_turret_milling": ("modal", "turret_milling.toml", {"compare_rigid": True}, 1e-9),
    "C_turret_milling_gear_data": ("modal", "turret_milling_gear_data.toml", {"compare_rigid": True}, 1e-9),
    "B_turret_indexing_gear_data": ("modal", "turret_indexing_gear_data.toml", {"compare_rigid": True}, 1e-9),
    "D_transplanter_rp1": ("mechanism", "transplanter_rp1.toml", {}, 1e-9),
    "gear_spur_pair": ("gear", "spur_pair.toml", {}, 1e-9),
    "gear_tooth_pair1_published": ("gear", "tooth_pair1_published.toml", {}, 1e-9),
    "gear_tooth_pair2_published": ("gear", "tooth_pair2_published.toml", {}, 1e-9),
    "mount_pad_shore60": ("mount", "pad_shore60.toml", {}, 1e-9),
    "mount_anchor_concrete": ("mount", "anchor_concrete.toml", {}, 1e-9),
    "mount_wedge": ("mount", "wedge_mount.toml", {}, 1e-9),
}
# values this close to zero are compared absolutely, in the key's unit
ATOL = 1e-9
# the start-up is integrated with rtol 1e-9 (DOP853): its figures carry the integrator's error
STARTUP_RTOL = 1e-7
# the FE reference's error estimates and order are differences of successive meshes' stiffnesses,
# which agree to a few 1e-3: the solves' rounding, which moves with the CPU's BLAS kernels (1e-11 of
# the stiffness between two machines), shows in them some 300 times larger (1.3e-8 measured)
FE_DIFFERENCE_RTOL = 1e-6
FE_DIFFERENCES = ("fe_error_bound_relative", "fe_discretisation_error_relative", "fe_convergence_order")


def _rtol(key: str, rtol: float) -> float:
    """The tolerance of one key: the case's, or the start-up's or the FE differences' where wider."""
    if key.startswith("startup_"):
        return STARTUP_RTOL
    return FE_DIFFERENCE_RTOL if key in FE_DIFFERENCES else rtol


def _is_number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _numbers(summary):
    """The summary's numbers: scalars and flat lists of scalars (nested tables are covered by the
    scalars derived from them)."""
    out = {}
    for k, v in summary.items():
        if isinstance(v, bool) or k == "n_angles":
            continue
        if isinstance(v, (int, float)):
            out[k] = float(v)
        elif isinstance(v, list) and v and all(_is_number(x) for x in v):
            out[k] = [float(x) for x in v]
        elif isinstance(v, dict) and v and all(isinstance(x, (int, float)) for x in v.values()):
            out[k] = {n: float(x) for n, x in v.items()}
    return out


def _compute(case, tmp):
    from mechdyn.errors import ModelWarning
    from mechdyn.io import load_model
    from mechdyn.registry import get
    from mechdyn.store import ResultStore

    name, example, options, _ = CASES[case]
    analysis = get(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        loaded = load_model(ROOT / "examples" / example)
        if analysis.uses_store:
            with ResultStore(str(Path(tmp) / f"{case}.db")) as store:
                return analysis.run(loaded, store=store, **options).summary()
        return analysis.run(loaded, **options).summary()


def _close(a, b, rtol):
    return math.isclose(a, b, rel_tol=rtol, abs_tol=ATOL)


@pytest.mark.parametrize("case", sorted(CASES))
def test_reference_results_match_their_golden_file(case, tmp_path):
    golden = json.loads((GOLDEN / f"{case}.json").read_text())
    assert golden["regenerate"] == REGENERATE
    now = _numbers(_compute(case, tmp_path))
    assert set(now) == set(golden["values"]), f"keys changed: {set(now) ^ set(golden['values'])}"
    for key, entry in golden["values"].items():
        want, rtol, got = entry["value"], entry["rtol"], now[key]
        if isinstance(want, list):
            assert len(got) == len(want), key
            assert all(_close(g, w, rtol) for g, w in zip(got, want, strict=True)), key
        elif isinstance(want, dict):
            assert set(got) == set(want) and all(_close(got[n], want[n], rtol) for n in want), key
        else:
            assert _close(got, want, rtol), f"{key}: {got!r} against the golden {want!r} (rtol {rtol})"


def regenerate() -> None:
    import tempfile

    GOLDEN.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        for case, (analysis, example, options, rtol) in CASES.items():
            values = {
                k: {"value": v, "rtol": _rtol(k, rtol)} for k, v in _numbers(_compute(case, tmp)).items()
            }
            doc = {
                "regenerate": REGENERATE,
                "analysis": analysis,
                "model": f"examples/{example}",
                "options": options,
                "values": values,
            }
            (GOLDEN / f"{case}.json").write_text(json.dumps(doc, indent=1) + "\n")
            print(f"{case}: {len(values)} values")


if __name__ == "__main__":
    if sys.argv[1:] != ["--regenerate"]:
        sys.exit(f"usage: {REGENERATE}")
    regenerate()
