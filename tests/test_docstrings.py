"""The public API documents itself: every callable exported in ``__all__`` of the package and of its
subpackages has a numpydoc docstring that names every parameter, and every physical parameter carries
its unit (in the manner of python-control's ``docstrings_test.py``). The examples in the docstrings
run as doctests."""

from __future__ import annotations

import doctest
import importlib
import inspect
import pkgutil
import re

import pytest
from numpydoc.docscrape import NumpyDocString

import mechdyn

# the public API: the top-level package and the modules and subpackages directly under it
_INTERNAL = ("mechdyn.cli", "mechdyn.dashboard")
PUBLIC = [
    "mechdyn",
    *sorted(
        m.name
        for m in pkgutil.iter_modules(mechdyn.__path__, "mechdyn.")
        if not m.name.rsplit(".", 1)[-1].startswith("_") and m.name not in _INTERNAL
    ),
]

# how a physical quantity's unit is written in a description: an SI symbol (or a product, quotient or
# power of them), or a word saying that the quantity has none
_SYMBOL = r"(?:[kMGTmµnu]?(?:m|g|s|N|Pa|Hz|J|W|rad|K|A)|deg|°|rpm|min|h|bar|tonf|kgf|kg|%|dB|ppm|1/s|rad/s)"
_UNIT = re.compile(
    rf"(?<![\w/·*])(?:{_SYMBOL}(?:[·*/]{_SYMBOL}|[²³⁻¹]+|\^-?\d)*)(?![\w])"
    r"|dimensionless|unitless|inch(?:es)?|ratio|factor|fraction|per unit|count|[Nn]umber of|index|"
    r"in units of|in ``\w+``|"
    r"the unit|its unit|in the model's units|SI|with units|quantit(?:y|ies)"
)
# parameters that are dimensionless by their name (a ratio, a factor, a coefficient, a tolerance)
_DIMENSIONLESS = re.compile(
    r"(ratio|factor|coefficient|shift|addendum|dedendum|shore_a|mac|rtol|atol|tolerance|residual)$"
)
# the numpydoc type of a parameter that holds a physical quantity
_PHYSICAL = re.compile(r"\b(float|array|ndarray|quantity|ArrayLike)\b", re.IGNORECASE)


def _public_objects():
    seen: set[int] = set()
    for module_name in PUBLIC:
        module = importlib.import_module(module_name)
        for name in getattr(module, "__all__", []):
            obj = getattr(module, name)
            if id(obj) in seen or not (inspect.isclass(obj) or inspect.isfunction(obj)):
                continue
            if not obj.__module__.startswith("mechdyn"):  # e.g. pint's Quantity, exported as Q_
                continue
            seen.add(id(obj))
            yield f"{module_name}.{name}", obj
            if inspect.isclass(obj):
                for attr, member in vars(obj).items():
                    if attr.startswith("_"):
                        continue
                    if isinstance(member, staticmethod | classmethod):
                        member = member.__func__
                    if inspect.isfunction(member):
                        yield f"{module_name}.{name}.{attr}", member


CALLABLES = dict(_public_objects())


def _documented(doc: NumpyDocString, is_class: bool) -> dict[str, tuple[str, str]]:
    sections = ["Parameters", "Other Parameters"] + (["Attributes"] if is_class else [])
    out = {}
    for section in sections:
        for p in doc[section]:
            for name in p.name.split(","):
                out[name.strip().lstrip("*")] = (p.type, " ".join(p.desc))
    return out


def _parameters(obj) -> list[str]:
    try:
        signature = inspect.signature(obj)
    except (TypeError, ValueError):  # pragma: no cover - builtins
        return []
    skip = {"self", "cls"}
    kinds = (inspect.Parameter.VAR_POSITIONAL, inspect.Parameter.VAR_KEYWORD)
    return [p.name for p in signature.parameters.values() if p.name not in skip and p.kind not in kinds]


def test_the_public_api_is_found():
    assert len(CALLABLES) > 200
    assert "mechdyn.drivetrain.modal" in CALLABLES and "mechdyn.mounts.BoltedJoint" in CALLABLES


@pytest.mark.parametrize("name", sorted(CALLABLES))
def test_every_parameter_is_documented_with_its_unit(name):
    obj = CALLABLES[name]
    text = inspect.getdoc(obj)  # a method that implements a protocol inherits the protocol's docstring
    assert text and text.strip(), f"{name} has no docstring"
    doc = NumpyDocString(text)
    assert doc["Summary"], f"{name}: the docstring has no one-line summary"
    documented = _documented(doc, inspect.isclass(obj))
    if inspect.isclass(obj):  # fields and arguments a class inherits are documented by its bases
        for base in obj.__mro__[1:]:
            if base.__module__.startswith("mechdyn") and base.__doc__:
                documented = _documented(NumpyDocString(inspect.getdoc(base)), True) | documented
    missing = [p for p in _parameters(obj) if p not in documented and not p.startswith("_")]
    assert not missing, f"{name}: parameters not documented: {missing}"
    no_unit = [
        p
        for p, (kind, description) in documented.items()
        if _PHYSICAL.search(kind)
        and not (_UNIT.search(description) or _UNIT.search(kind) or _DIMENSIONLESS.search(p))
    ]
    assert not no_unit, f"{name}: physical parameters without a unit in their description: {no_unit}"


def test_the_unit_pattern_finds_units_and_only_units():
    units = ("Stiffness, N/m.", "in kg·m²", "E, Pa", "angle, rad", "length (mm)", "dimensionless", "N·m/rad")
    for text in units:
        assert _UNIT.search(text), text
    for text in ("The crank", "Number-free prose about gears", "a name"):
        assert not _UNIT.search(text), text


@pytest.mark.parametrize("module_name", PUBLIC)
def test_the_docstring_examples_run(module_name):
    module = importlib.import_module(module_name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    tests = []
    for name in getattr(module, "__all__", []):
        obj = getattr(module, name)
        if inspect.isclass(obj) or inspect.isfunction(obj):
            tests += finder.find(obj, f"{module_name}.{name}", globs={})
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in tests:
        runner.run(test)
    assert runner.failures == 0, f"{runner.failures} docstring example(s) of {module_name} failed"
