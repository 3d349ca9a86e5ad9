"""The type checker runs clean on the package (mypy, configured in pyproject.toml): model-file field
types are real types, optionals are narrowed where they are used. It found a crash of ``mechdyn gear``
with the involute tooth model."""

from __future__ import annotations

import subprocess
import sys

import pytest

from conftest import ROOT


@pytest.mark.step
def test_mypy_finds_no_error_in_the_package(tmp_path):
    run = subprocess.run(
        [sys.executable, "-m", "mypy", "--cache-dir", str(tmp_path / "mypy-cache")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert run.returncode == 0, run.stdout[-10000:] + run.stderr[-2000:]
    assert "Success: no issues found" in run.stdout
