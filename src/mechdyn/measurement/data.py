"""Measured frequency response functions: UFF 58 and CSV files in, SI arrays out.

A :class:`MeasuredFRF` holds H (n_f, n_out, n_ref) in SI (m/N, m/s/N or m/s²/N for forces, rad/(N·m)
… for moments) at circular frequencies in rad/s, with each output and reference named as a point and
a direction (``"c1"``, ``"z"``). Readers convert at the edge (pint, :mod:`mechdyn.units`); nothing
downstream sees a unit.

Sources: the Universal File Format dataset 58 (SDRC I-DEAS, *Universal File Datasets Summary*), read
with pyuff (Slavič et al., https://github.com/ladisk/pyuff).
"""

from __future__ import annotations

import csv
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mechdyn.errors import ModelFileError

__all__ = ["MeasuredFRF", "read_csv", "read_uff"]

DIRECTIONS = ("x", "y", "z", "rx", "ry", "rz")
_KIND_UNITS = (  # the FRF's kind from the SI dimension of response / excitation (force or moment)
    ("receptance", "m/N"),
    ("mobility", "m/s/N"),
    ("accelerance", "m/s**2/N"),
    ("receptance", "rad/(N*m)"),
    ("mobility", "rad/s/(N*m)"),
    ("accelerance", "rad/s**2/(N*m)"),
)


def _kind(q: Any) -> str | None:
    """The FRF kind of a pint quantity, force and moment alike (rad is dimensionless)."""
    for kind, text in _KIND_UNITS:
        if q.dimensionality == q._REGISTRY.Quantity(1.0, text).dimensionality:
            return kind
    return None


@dataclass(frozen=True)
class MeasuredFRF:
    """Measured frequency responses of several outputs to several references, in SI.

    Attributes
    ----------
    omega : ndarray
        (n_f,) circular frequencies, rad/s, ascending.
    H : ndarray
        (n_f, n_out, n_ref) complex FRFs in SI: m/N (receptance), m/(s·N) (mobility) or m/(s²·N)
        (accelerance); rad instead of m and N·m instead of N for rotations and moments.
    outputs : tuple of (str, str)
        (point, direction) of each response, direction in ``"x" … "rz"`` (positive axis).
    references : tuple of (str, str)
        (point, direction) of each excitation.
    kind : {"receptance", "mobility", "accelerance"}
        What the response measures.
    source : str
        The file the data came from (or ``"synthetic"``).
    """

    omega: np.ndarray
    H: np.ndarray
    outputs: tuple[tuple[str, str], ...]
    references: tuple[tuple[str, str], ...]
    kind: str = "receptance"
    source: str = ""

    def __post_init__(self) -> None:
        H = np.asarray(self.H, dtype=complex)
        omega = np.asarray(self.omega, dtype=float)
        if H.ndim != 3 or H.shape != (omega.size, len(self.outputs), len(self.references)):
            raise ValueError(
                f"H has shape {H.shape}, expected (n_f, n_out, n_ref) = "
                f"({omega.size}, {len(self.outputs)}, {len(self.references)})"
            )
        if self.kind not in ("receptance", "mobility", "accelerance"):
            raise ValueError(f"kind {self.kind!r} must be receptance, mobility or accelerance")
        object.__setattr__(self, "H", H)
        object.__setattr__(self, "omega", omega)

    @property
    def frequencies_hz(self) -> np.ndarray:
        """(n_f,) frequencies, Hz."""
        return self.omega / (2.0 * np.pi)

    def as_receptance(self) -> MeasuredFRF:
        """The same data as receptance (m/N): divided by iω (mobility) or −ω² (accelerance)."""
        s = 1j * self.omega[:, None, None]
        power = {"receptance": 0, "mobility": 1, "accelerance": 2}[self.kind]
        return MeasuredFRF(
            self.omega, self.H / s**power, self.outputs, self.references, "receptance", self.source
        )

    def summary(self) -> dict[str, Any]:
        """Frequency range (Hz), number of lines, outputs and references."""
        return {
            "kind": self.kind,
            "frequency_min_hz": float(self.frequencies_hz[0]),
            "frequency_max_hz": float(self.frequencies_hz[-1]),
            "lines": int(self.omega.size),
            "outputs": [f"{p}:{d}" for p, d in self.outputs],
            "references": [f"{p}:{d}" for p, d in self.references],
        }


def _assemble(
    path: str, records: list[tuple[tuple[str, str], tuple[str, str], np.ndarray, np.ndarray, str]], what: str
) -> MeasuredFRF:
    """Stack (output, reference, f_hz, H_si, kind) records on one frequency grid into a MeasuredFRF."""
    if not records:
        raise ModelFileError(path, what, "holds no frequency response function")
    f0, kind0 = records[0][2], records[0][4]
    outputs = tuple(dict.fromkeys(r[0] for r in records))
    refs = tuple(dict.fromkeys(r[1] for r in records))
    H = np.full((f0.size, len(outputs), len(refs)), np.nan + 0j)
    for i, (o, r, f, h, kind) in enumerate(records):
        if f.shape != f0.shape or not np.allclose(f, f0, rtol=1e-9):
            raise ModelFileError(
                path,
                f"{what} #{i + 1}",
                f"frequencies {f[0]:g}…{f[-1]:g} Hz ({f.size} lines) differ from the "
                f"first record's {f0[0]:g}…{f0[-1]:g} Hz ({f0.size}); resample every FRF on one grid",
            )
        if kind != kind0:
            raise ModelFileError(
                path,
                f"{what} #{i + 1}",
                f"is a {kind} where the first record is {kind0}; export one kind of FRF",
                value=kind,
            )
        H[:, outputs.index(o), refs.index(r)] = h
    missing = np.argwhere(np.isnan(H[0]))
    if missing.size:
        o, r = missing[0]
        raise ModelFileError(
            path,
            what,
            f"has no FRF of output {':'.join(outputs[o])} to reference {':'.join(refs[r])}; "
            "every output needs every reference (or read the references from separate files)",
        )
    return MeasuredFRF(2.0 * np.pi * f0, H, outputs, refs, kind0, path)


def _si_factor(path: str, where: str, unit: str, field: str) -> tuple[float, str]:
    """The factor from ``unit`` to SI base units and the FRF kind it measures."""
    import mechdyn.units as u

    ureg = u.registry()
    try:
        q = ureg.Quantity(1.0, unit).to_base_units()
    except Exception as exc:
        raise ModelFileError(
            path,
            f"{where} → {field}",
            f"unit {unit!r} is not understood ({exc}); write e.g. 'm/s^2/N'",
            value=unit,
        ) from None
    kind = _kind(q)
    if kind is None:
        raise ModelFileError(
            path,
            f"{where} → {field}",
            f"unit {unit!r} ({q.dimensionality}) is not a displacement, velocity or "
            "acceleration per force or moment; write e.g. 'm/N', 'm/s/N', 'm/s^2/N' or 'rad/(N*m)'",
            value=unit,
        )
    return float(q.magnitude), kind


def _hz_factor(path: str, where: str, unit: str) -> float:
    import mechdyn.units as u

    ureg = u.registry()
    try:
        q = ureg.Quantity(1.0, unit or "Hz")
        if q.dimensionality == ureg.Quantity(1.0, "rad/s").dimensionality and "rad" in unit:
            return float(q.to("rad/s").magnitude) / (2.0 * np.pi)
        return float(q.to("Hz").magnitude)
    except Exception:
        raise ModelFileError(
            path, where, f"frequency unit {unit!r} is not a frequency; write 'Hz' or 'rad/s'", value=unit
        ) from None


# ---- UFF 58 ----------------------------------------------------------------------------------


def _uff_direction(path: str, where: str, code: Any) -> tuple[str, float]:
    try:
        c = int(code)
    except (TypeError, ValueError):
        c = 0
    if c == 0 or abs(c) > 6:
        raise ModelFileError(
            path, where, f"direction code {code!r} is not one of ±1…±6 (x, y, z, rx, ry, rz)", value=code
        )
    return DIRECTIONS[abs(c) - 1], float(np.sign(c))


def uff_sets(name: str) -> list[dict[str, Any]]:
    """Every dataset of a Universal File as pyuff reads it (a list of dicts, one a dataset).

    Parameters
    ----------
    name : str
        The file's path.

    Raises
    ------
    ModelFileError
        For a file that does not exist or that pyuff cannot read, naming it.
    """
    import pyuff  # type: ignore[import-untyped]

    if not Path(name).is_file():
        raise ModelFileError(name, "file", "does not exist")
    try:
        sets = pyuff.UFF(name).read_sets()
    except Exception as exc:
        raise ModelFileError(name, "file", f"is not a readable Universal File ({exc})") from None
    return [sets] if isinstance(sets, dict) else list(sets)


def read_uff(path: str | Path, *, units: str | None = None) -> MeasuredFRF:
    """Read the frequency response functions of a Universal File (dataset 58).

    Parameters
    ----------
    path : str or Path
        The ``.uff``/``.unv`` file (ASCII or binary 58). Every dataset 58 with function type 4
        (frequency response function) is read; other datasets are skipped.
    units : str, optional
        The FRF unit when the file does not say it (e.g. ``"m/s^2/N"``); the file's ordinate and
        denominator labels (``ordinate_axis_units_lab`` / ``orddenom_axis_units_lab``) win when present.

    Returns
    -------
    MeasuredFRF
        In SI, frequencies converted from the abscissa label (Hz when empty), directions made
        positive (a response or reference along −z flips the sign of H).

    Raises
    ------
    ModelFileError
        Naming the file, the dataset and field, the value and what to write instead.
    """

    name = str(path)
    sets = uff_sets(name)
    records = []
    for i, s in enumerate(sets):
        if s.get("type") != 58 or int(s.get("func_type", 0)) != 4:
            continue
        where = f"dataset #{i + 1} (type 58, {s.get('id1', '').strip() or 'no id'})"
        num = str(s.get("ordinate_axis_units_lab", "") or "").strip()
        den = str(s.get("orddenom_axis_units_lab", "") or "").strip()
        if num and den:
            unit, field = f"({num})/({den})", "ordinate_axis_units_lab / orddenom_axis_units_lab"
        elif units is not None:
            unit, field = units, "units (argument)"
        else:
            raise ModelFileError(
                name,
                f"{where} → ordinate_axis_units_lab",
                f"is {num!r} and orddenom_axis_units_lab {den!r}: the FRF's unit is unknown; pass "
                "read_uff(..., units='m/s^2/N') or write both labels",
                value=num,
            )
        factor, kind = _si_factor(name, where, unit, field)
        hz = _hz_factor(
            name,
            f"{where} → abscissa_axis_units_lab",
            str(s.get("abscissa_axis_units_lab", "") or "").strip(),
        )
        x = np.asarray(s["x"], dtype=float) * hz
        data = np.asarray(s["data"])
        if not np.iscomplexobj(data):
            raise ModelFileError(
                name,
                f"{where} → ord_data_type",
                "holds real data; an FRF needs complex ordinates (5 or 6)",
                value=s.get("ord_data_type"),
            )
        rdir, rsign = _uff_direction(name, f"{where} → rsp_dir", s.get("rsp_dir"))
        edir, esign = _uff_direction(name, f"{where} → ref_dir", s.get("ref_dir"))
        out = (str(s.get("rsp_node")), rdir)
        ref = (str(s.get("ref_node")), edir)
        records.append((out, ref, x, data.astype(complex) * factor * rsign * esign, kind))
    return _assemble(name, records, "type-58 FRF datasets")


# ---- CSV -------------------------------------------------------------------------------------

_COLUMN = re.compile(
    r"^\s*(?P<out>[^:/\s]+):(?P<od>[a-z]+)\s*/\s*(?P<ref>[^:/\s]+):(?P<rd>[a-z]+)\s+"
    r"(?P<part>re|im|mag|phase_deg)\s*\[(?P<unit>[^\]]*)\]\s*$"
)
_FREQ = re.compile(r"^\s*frequency\s*\[(?P<unit>[^\]]+)\]\s*$")


def read_csv(path: str | Path) -> MeasuredFRF:
    """Read frequency response functions from a CSV file, several channels in columns.

    The first column is ``frequency [Hz]`` (or ``[rad/s]``); then, for each FRF, two columns named
    ``<point>:<dir>/<point>:<dir> <part> [<unit>]``: response, then reference, ``<dir>`` one of
    ``x y z rx ry rz``, ``<part>`` either ``re`` and ``im`` or ``mag`` and ``phase_deg`` (the unit of
    ``phase_deg`` is ``deg``), e.g.::

        frequency [Hz],c1:z/c1:z re [m/s^2/N],c1:z/c1:z im [m/s^2/N]

    Lines starting with ``#`` are comments.

    The single-FRF form of a mount's calibration file (:func:`mechdyn.mounts.read_frf_csv`) is read
    too: columns ``frequency_Hz`` and either ``real`` and ``imag`` or ``magnitude`` and
    ``phase_deg``, in SI, with a comment ``# kind: receptance`` (the default), ``mobility`` or
    ``accelerance``; its one FRF is the driving point ``mount:z/mount:z``.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    MeasuredFRF

    Raises
    ------
    ModelFileError
        Naming the file, the line or column, the value and the expected form.
    """
    name = str(path)
    if not Path(name).is_file():
        raise ModelFileError(name, "file", "does not exist")
    with open(name, newline="") as fh:
        rows = [r for r in csv.reader(line for line in fh if not line.lstrip().startswith("#")) if r]
    if len(rows) < 3:
        raise ModelFileError(
            name, "file", f"has {len(rows)} non-comment rows; need a header and two or more lines"
        )
    header = rows[0]
    if header[0].strip() == "frequency_Hz":
        return _read_single_csv(name, header, rows[1:])
    fm = _FREQ.match(header[0])
    if fm is None:
        raise ModelFileError(
            name,
            "header column 1",
            f"is {header[0]!r}; it must be 'frequency [Hz]' (or '[rad/s]')",
            value=header[0],
        )
    hz = _hz_factor(name, "header column 1", fm["unit"].strip())
    try:
        table = np.array([[float(v) for v in r] for r in rows[1:]])
    except ValueError:
        for line, r in enumerate(rows[1:], 2):
            for col, v in enumerate(r, 1):
                try:
                    float(v)
                except ValueError:
                    raise ModelFileError(
                        name,
                        f"data row {line}, column {col} ({header[col - 1] if col <= len(header) else '?'})",
                        f"is {v!r}, not a number",
                        value=v,
                    ) from None
        raise
    if table.ndim != 2 or table.shape[1] != len(header):
        raise ModelFileError(name, "data rows", f"must each have {len(header)} values like the header")
    columns: dict[tuple[tuple[str, str], tuple[str, str]], dict[str, tuple[int, str]]] = {}
    for col, text in enumerate(header[1:], 2):
        m = _COLUMN.match(text)
        if m is None or m["od"] not in DIRECTIONS or m["rd"] not in DIRECTIONS:
            raise ModelFileError(
                name,
                f"header column {col}",
                f"is {text!r}; it must read '<point>:<dir>/<point>:<dir> <re|im|mag|phase_deg> "
                "[<unit>]' with <dir> in x y z rx ry rz, e.g. 'c1:z/c1:z re [m/s^2/N]'",
                value=text,
            )
        key = ((m["out"], m["od"]), (m["ref"], m["rd"]))
        columns.setdefault(key, {})[m["part"]] = (col - 1, m["unit"].strip())
    records = []
    for (out, ref), parts in columns.items():
        label = f"FRF {':'.join(out)}/{':'.join(ref)}"
        if {"re", "im"} <= parts.keys():
            (ci, unit), (cj, unit_j) = parts["re"], parts["im"]
            h = table[:, ci] + 1j * table[:, cj]
        elif {"mag", "phase_deg"} <= parts.keys():
            (ci, unit), (cj, unit_j) = parts["mag"], parts["phase_deg"]
            if unit_j not in ("deg", "°"):
                raise ModelFileError(
                    name,
                    f"header column {cj + 1}",
                    f"phase_deg has unit [{unit_j}]; write [deg]",
                    value=unit_j,
                )
            unit_j = unit
            h = table[:, ci] * np.exp(1j * np.deg2rad(table[:, cj]))
        else:
            raise ModelFileError(
                name,
                label,
                f"has columns {sorted(parts)}; give either 're' and 'im' or 'mag' and 'phase_deg'",
            )
        if unit_j != unit:
            raise ModelFileError(name, label, f"has two units {unit!r} and {unit_j!r}; use one", value=unit_j)
        factor, kind = _si_factor(name, label, unit, "unit")
        records.append((out, ref, table[:, 0] * hz, h * factor, kind))
    return _assemble(name, records, "columns")


def _read_single_csv(name: str, header: list[str], rows: list[list[str]]) -> MeasuredFRF:
    """The single-FRF form of a mount calibration file (see :func:`read_csv`), SI, driving point."""
    kind = "receptance"
    with open(name, encoding="utf-8") as fh:
        for line in fh:
            if line.lstrip().startswith("#") and "kind:" in line:
                kind = line.split("kind:", 1)[1].strip()
    if kind not in ("receptance", "mobility", "accelerance"):
        raise ModelFileError(
            name, "comment '# kind:'", f"is {kind!r}; write receptance, mobility or accelerance", value=kind
        )
    cols = {c.strip(): i for i, c in enumerate(header)}
    if {"real", "imag"} <= cols.keys():
        parts = ("real", "imag")
    elif {"magnitude", "phase_deg"} <= cols.keys():
        parts = ("magnitude", "phase_deg")
    else:
        raise ModelFileError(
            name,
            "header",
            f"has columns {sorted(cols)}; with frequency_Hz give real and imag, or magnitude and phase_deg",
        )
    try:
        table = np.array([[float(r[cols[c]]) for c in ("frequency_Hz", *parts)] for r in rows])
    except (ValueError, IndexError):
        raise ModelFileError(
            name, "data rows", f"must each hold numbers in the columns frequency_Hz, {', '.join(parts)}"
        ) from None
    a, b = table[:, 1], table[:, 2]
    h = a + 1j * b if parts[0] == "real" else a * np.exp(1j * np.deg2rad(b))
    point = ("mount", "z")
    return _assemble(name, [(point, point, table[:, 0], h, kind)], "columns")
