"""What could not be stored is kept in a file beside the database, and imported from it later.

A run or a block of study variants that the database refuses (server gone, disk full, a value the
backend will not take) is written, complete with its arrays, to ``mechdyn-unsaved-TIME-PID.json``
beside the SQLite file (or in the working directory for a server); ``mechdyn results import FILE``
stores it when the database is back. Nothing computed is lost.
"""

from __future__ import annotations

import base64
import json
import os
from collections.abc import Mapping
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from mechdyn.store.database import StoreError, is_sqlite, sqlite_path
from mechdyn.store.store import jsonable, pack_array, unpack_array

__all__ = ["keep_unsaved", "read_unsaved"]

FORMAT = "mechdyn-unsaved/1"


def _arrays_out(arrays: Mapping[str, tuple[np.ndarray, str]] | None) -> dict[str, Any]:
    return {
        k: {"unit": u, "npy": base64.b64encode(pack_array(np.asarray(a))).decode()}
        for k, (a, u) in (arrays or {}).items()
    }


def _arrays_in(doc: Mapping[str, Any]) -> dict[str, tuple[np.ndarray, str]]:
    return {k: (unpack_array(base64.b64decode(v["npy"])), v["unit"]) for k, v in doc.items()}


def keep_unsaved(url: str, kind: str, content: Mapping[str, Any]) -> Path:
    """Write what could not be stored to a file beside the database; returns its path.

    Parameters
    ----------
    url : str
        The database it was meant for (a SQLite file: the file goes into its folder).
    kind : {"run", "variants"}
        A run's :meth:`ResultStore.record` arguments, or a study's block of variants
        (``study`` and ``rows`` as :meth:`StudyStore.add` takes them).
    content : mapping
        What to keep; arrays and curves as ``name → (array, unit)``.
    """
    doc: dict[str, Any] = {"format": FORMAT, "kind": kind, "database": url.split("@")[-1]}
    if kind == "run":
        doc["run"] = {**jsonable({k: v for k, v in content.items() if k != "arrays"}),
                      "arrays": _arrays_out(content.get("arrays"))}  # fmt: skip
    else:
        doc["study"] = content["study"]
        doc["rows"] = [
            {**jsonable({k: v for k, v in r.items() if k != "curves"}),
             "curves": _arrays_out(r.get("curves"))}
            for r in content["rows"]
        ]  # fmt: skip
    stamp = datetime.now(UTC).strftime("%Y%m%d-%H%M%S")
    folders = [Path(sqlite_path(url)).parent] if is_sqlite(url) else []
    for folder in [*folders, Path.cwd()]:
        path = folder / f"mechdyn-unsaved-{stamp}-{os.getpid()}-{kind}.json"
        try:
            path.write_text(json.dumps(doc), encoding="utf-8")
            return path
        except OSError:
            continue
    raise StoreError(f"cannot write the unsaved {kind} beside {url} nor in {Path.cwd()}")


def read_unsaved(path: str | os.PathLike[str]) -> dict[str, Any]:
    """What :func:`keep_unsaved` kept, read back with its arrays: ``kind`` (``"run"`` or
    ``"study"``), and ``run`` (the keywords of :meth:`ResultStore.record`) or ``study`` and ``rows``
    (a study's name and its variants, for :meth:`mechdyn.studies.storage.StudyStore.add`).

    Parameters
    ----------
    path : str or path
        The file.

    Raises
    ------
    StoreError
        Where the file cannot be read or is not a file of unsaved results.
    """
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise StoreError(f"{path}: cannot read it as a file of unsaved results ({exc})") from None
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise StoreError(f"{path}: not a file of unsaved mechdyn results (no format {FORMAT!r})")
    if doc["kind"] == "run":
        run = dict(doc["run"])
        run["arrays"] = _arrays_in(run.get("arrays", {}))
        return {"kind": "run", "run": run}
    rows = [{**r, "curves": _arrays_in(r.get("curves", {}))} for r in doc["rows"]]
    return {"kind": "study", "study": doc["study"], "rows": rows}
