"""No hand-typed unit conversion outside mechdyn.units: display units go through its one registry."""

from __future__ import annotations

import ast
from pathlib import Path

import mechdyn

SRC = Path(mechdyn.__file__).resolve().parent
# factors that convert units when they multiply or divide a value (percentages and tolerances are
# not conversions: 100 and small tolerance factors are allowed)
CONVERSION_FACTORS = {1e3, 1e6, 1e9, 1e-3, 1e-6, 1e-9, 9.80665, 9806.65, 60.0, 3600.0}
# tolerances written as a factor of a scale (1e-9 * scale) are not conversions
TOLERANCE_NAMES = ("scale", "mass", "radius", "h", "max")


def _is_tolerance(node: ast.BinOp, const: ast.AST) -> bool:
    other = node.right if const is node.left else node.left
    text = ast.unparse(other)
    return float(const.value) < 1 and any(n in text for n in TOLERANCE_NAMES)


def test_no_hand_typed_conversion_factor_outside_units():
    found = []
    for path in sorted(SRC.rglob("*.py")):
        if path.name == "units.py":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not (isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Mult, ast.Div))):
                continue
            for side in (node.left, node.right):
                if (
                    isinstance(side, ast.Constant)
                    and isinstance(side.value, (int, float))
                    and float(side.value) in CONVERSION_FACTORS
                    and not _is_tolerance(node, side)
                ):
                    found.append(f"{path.relative_to(SRC)}:{node.lineno}: {ast.unparse(node)}")
    assert not found, "convert with mechdyn.units.convert/show instead:\n" + "\n".join(found)


def test_the_top_level_shows_what_a_user_reaches():
    """`dir(mechdyn)` listed `Any` and `PackageNotFoundError` and not `load`: it lists the public names
    and the subpackages, and `load`, `save`, `Q_` are there."""
    import mechdyn

    shown = dir(mechdyn)
    assert {"load", "save", "Q_", "ureg", "drivetrain", "mechanism", "support"} <= set(shown)
    assert not {"Any", "PackageNotFoundError", "version"} & set(shown)
    assert abs(mechdyn.Q_("12 mm").to("m").magnitude - 0.012) < 1e-15
