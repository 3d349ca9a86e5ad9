"""Materials for mount estimates: shipped as data with their sources, extendable, storable.

The shipped table (``mechdyn/mounts/data/materials.toml``) holds steels, cast irons, concrete grades
and rubbers by Shore A hardness, each value with its source. A user adds materials from a file of the
same form or in Python; :func:`save_materials` writes a database's materials into the results store
with their provenance, and :meth:`MaterialDatabase.from_store` reads them back.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, Literal, get_args

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.units import si_field

__all__ = ["Material", "MaterialDatabase", "default_materials", "save_materials"]

_Kind = Literal["steel", "cast_iron", "concrete", "rubber", "other"]
KINDS: tuple[str, ...] = get_args(_Kind)


_SOFTEST = 1e3  # Pa: the least Young's modulus of a material a machine stands on
# Poisson's ratios a material of each kind can have (rubber and "other": the whole physical range)
_POISSON = {"steel": (0.2, 0.4), "cast_iron": (0.15, 0.35), "concrete": (0.1, 0.3)}


@dataclass(frozen=True)
class Material:
    """A linear-elastic material.

    Parameters
    ----------
    name : str
    kind : {"steel", "cast_iron", "concrete", "rubber", "other"}
    youngs_modulus : float or quantity
        E, Pa, from 1 kPa to 1e13 Pa.
    poissons_ratio : float, optional
        ν: 0.2–0.4 for steel, 0.15–0.35 for cast iron, 0.1–0.3 for concrete, −1 < ν < 0.5 for rubber
        and other materials. For rubber it follows from E and the bulk modulus when not given.
    shear_modulus : float or quantity, optional
        G, Pa, positive (at most 1e13 Pa); by default E / (2 (1 + ν)).
    bulk_modulus : float or quantity, optional
        B, Pa, positive (at most 1e13 Pa); by default E / (3 (1 − 2ν)).
    compression_coefficient : float, optional
        k of the shape-factor formula E_c = E (1 + 2 k S²), in (0, 1] (rubber; 1 for an ideal
        elastic solid).
    shore_a : float, optional
        Hardness (rubber), Shore A, from 0 to 100.
    density : float or quantity, optional
        kg/m³, between 1 and 25 000.
    source : str
        Where the values come from.
    """

    name: str
    kind: str
    youngs_modulus: Any
    poissons_ratio: Any = None
    shear_modulus: Any = None
    bulk_modulus: Any = None
    compression_coefficient: float = 1.0
    shore_a: float | None = None
    density: Any = None
    source: str = ""

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ModelError(f"{self.kind!r} must be one of {KINDS}", element=self.name, field="kind")
        E = si_field(self.name, "youngs_modulus", self.youngs_modulus, "Pa")
        if not E >= _SOFTEST:
            raise ModelError(
                f"{E:g} Pa: give a Young's modulus of at least {_SOFTEST:g} Pa (the softest foam rubber is "
                "about 1e5 Pa); check the number and its unit",
                element=self.name,
                field="youngs_modulus",
            )
        object.__setattr__(self, "youngs_modulus", E)
        B = (
            None
            if self.bulk_modulus is None
            else si_field(self.name, "bulk_modulus", self.bulk_modulus, "Pa", positive=True)
        )
        nu = self.poissons_ratio
        if nu is None:
            if B is None:
                raise ModelError(
                    "give poissons_ratio (or, for rubber, bulk_modulus)",
                    element=self.name,
                    field="poissons_ratio",
                )
            nu = 0.5 - E / (6.0 * B)
        nu = si_field(self.name, "poissons_ratio", nu, "")
        if not -1.0 < nu < 0.5:
            raise ModelError(
                f"{nu:g} must lie between −1 and 0.5 (0.5 is an incompressible solid, which has no finite "
                "bulk modulus; give rubber a bulk modulus instead)",
                element=self.name,
                field="poissons_ratio",
            )
        lo, hi = _POISSON.get(self.kind, (-1.0, 0.5))
        if not lo <= nu <= hi:
            raise ModelError(
                f"{nu:g} is no Poisson's ratio of a {self.kind.replace('_', ' ')} (between {lo:g} and "
                f"{hi:g}; only rubber comes near 0.5)",
                element=self.name,
                field="poissons_ratio",
            )
        object.__setattr__(self, "poissons_ratio", nu)
        G = (
            E / (2 * (1 + nu))
            if self.shear_modulus is None
            else si_field(self.name, "shear_modulus", self.shear_modulus, "Pa", positive=True)
        )
        object.__setattr__(self, "shear_modulus", G)
        object.__setattr__(self, "bulk_modulus", E / (3 * (1 - 2 * nu)) if B is None else B)
        k = si_field(self.name, "compression_coefficient", self.compression_coefficient, "")
        if not 0 < k <= 1:
            raise ModelError(f"{k:g} must lie in (0, 1]", element=self.name, field="compression_coefficient")
        object.__setattr__(self, "compression_coefficient", k)
        if self.density is not None:
            rho = si_field(self.name, "density", self.density, "kg/m^3")
            if not 1.0 <= rho <= 25_000.0:
                raise ModelError(
                    f"{rho:g} kg/m³: give a density between 1 and 25000 kg/m³ (steel: 7850)",
                    element=self.name,
                    field="density",
                )
            object.__setattr__(self, "density", rho)
        if self.shore_a is not None:
            hardness = si_field(
                self.name, "shore_a", self.shore_a, "", low=0.0, high=100.0, what="Shore A hardness"
            )
            object.__setattr__(self, "shore_a", hardness)

    def as_dict(self) -> dict[str, Any]:
        """SI values, JSON-ready."""
        return {
            "name": self.name,
            "kind": self.kind,
            "youngs_modulus_Pa": self.youngs_modulus,
            "poissons_ratio": self.poissons_ratio,
            "shear_modulus_Pa": self.shear_modulus,
            "bulk_modulus_Pa": self.bulk_modulus,
            "compression_coefficient": self.compression_coefficient,
            "shore_a": self.shore_a,
            "density_kg_per_m3": self.density,
            "source": self.source,
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> Material:
        """A material from :meth:`as_dict`'s form.

        Parameters
        ----------
        d : dict
            SI values, as :meth:`as_dict` writes them.
        """
        return cls(
            d["name"],
            d["kind"],
            d["youngs_modulus_Pa"],
            d["poissons_ratio"],
            d["shear_modulus_Pa"],
            d["bulk_modulus_Pa"],
            d["compression_coefficient"],
            d["shore_a"],
            d["density_kg_per_m3"],
            d["source"],
        )


def _read(path: str | Path) -> list[Material]:
    """The materials of a ``[[materials]]`` file, validated like a model file."""
    from mechdyn.errors import ModelFileError
    from mechdyn.io.modelfile import field_context, read_toml, validate

    source = read_toml(path, "a .toml materials file ([[materials]] rows, as shipped)")
    f = validate(_materials_schema(), source)
    out = []
    names = [row.name for row in f.materials]
    for i, row in enumerate(f.materials):
        if names.index(row.name) != i:
            raise ModelFileError(
                source.path,
                f"[[materials]] #{i + 1} (name = {row.name!r})",
                f"the name is given to [[materials]] #{names.index(row.name) + 1} too; give each material "
                "a name of its own",
            )
        with field_context(source, f"[[materials]] #{i + 1} (name = {row.name!r})"):
            out.append(Material(**row.model_dump()))
    return out


def _materials_schema() -> Any:
    """The schema of a materials file (built on first use: pydantic is not imported before)."""
    global _SCHEMA
    if _SCHEMA is None:
        from pydantic import Field

        from mechdyn.io.fields import Density, Dimensionless, FileModel, Pressure

        class MaterialRow(FileModel):
            name: str = Field(min_length=1)
            kind: _Kind
            youngs_modulus: Pressure
            poissons_ratio: Dimensionless | None = None
            shear_modulus: Pressure | None = None
            bulk_modulus: Pressure | None = None
            compression_coefficient: Dimensionless = 1.0
            shore_a: float | None = Field(default=None, ge=0, le=100)
            density: Density | None = None
            source: str = Field(min_length=1, description="where the values come from")

        class MaterialsFile(FileModel):
            materials: list[MaterialRow] = Field(min_length=1)

        _SCHEMA = MaterialsFile
    return _SCHEMA


_SCHEMA: Any = None


@dataclass(frozen=True)
class MaterialDatabase:
    """Materials by name; the shipped ones plus whatever the user adds (a new object each time).

    Parameters
    ----------
    materials : dict of str to Material
        The materials by name.
    """

    materials: dict[str, Material] = field(default_factory=dict)

    def __getitem__(self, name: str) -> Material:
        try:
            return self.materials[name]
        except KeyError:
            import difflib

            close = difflib.get_close_matches(name, list(self.materials), n=3)
            hint = f"; did you mean {', '.join(map(repr, close))}?" if close else ""
            raise ModelError(
                f"no material {name!r} in the database{hint}", element=name, field="material"
            ) from None

    def __contains__(self, name: str) -> bool:
        return name in self.materials

    def names(self, kind: str | None = None) -> list[str]:
        """The materials' names, of one kind (``"steel"``, ``"concrete"``, ``"rubber"``, …) or all.

        Parameters
        ----------
        kind : str, optional
            Only materials of this kind.
        """
        return [n for n, m in self.materials.items() if kind is None or m.kind == kind]

    def add(self, *materials: Material) -> MaterialDatabase:
        """A database with these materials added (a material of the same name is replaced)."""
        return MaterialDatabase({**self.materials, **{m.name: m for m in materials}})

    def with_file(self, path: str | Path) -> MaterialDatabase:
        """A database with the materials of a TOML file (``[[materials]]`` rows, as shipped) added.

        Parameters
        ----------
        path : str or Path
            The TOML file.
        """
        return self.add(*_read(path))

    def rubber(self, shore_a: float) -> Material:
        """Rubber of a Shore A hardness, interpolated linearly between the tabulated hardnesses.

        E and G interpolate in log scale (the table grows roughly exponentially with hardness).

        Parameters
        ----------
        shore_a : float
            Hardness, Shore A, within the table (30–75).

        Raises
        ------
        mechdyn.errors.ModelError
            For a hardness that is not finite or outside the table.
        """
        shore_a = si_field("rubber", "shore_a", shore_a, "", low=0.0, high=100.0, what="Shore A hardness")
        table = sorted(
            (m for m in self.materials.values() if m.kind == "rubber" and m.shore_a is not None),
            key=lambda m: float(m.shore_a or 0.0),
        )
        h = np.array([m.shore_a for m in table], dtype=float)
        if not table or not h[0] <= shore_a <= h[-1]:
            raise ModelError(
                f"Shore A {shore_a:g} is outside the table ({h[0]:g}–{h[-1]:g}); give the rubber's "
                "moduli instead",
                element="rubber",
                field="shore_a",
            )
        exact = [m for m in table if m.shore_a == shore_a]
        if exact:
            return exact[0]

        def interp(values, log=False):
            v = np.log(values) if log else np.asarray(values)
            out = float(np.interp(shore_a, h, v))
            return float(np.exp(out)) if log else out

        lo = table[int(np.searchsorted(h, shore_a)) - 1]
        return Material(
            f"rubber shore {shore_a:g}",
            "rubber",
            interp([m.youngs_modulus for m in table], log=True),
            shear_modulus=interp([m.shear_modulus for m in table], log=True),
            bulk_modulus=interp([m.bulk_modulus for m in table]),
            compression_coefficient=interp([m.compression_coefficient for m in table]),
            shore_a=shore_a,
            source=f"interpolated in hardness; {lo.source}",
        )

    @classmethod
    def from_store(cls, store: Any, base: MaterialDatabase | None = None) -> MaterialDatabase:
        """The materials saved in a results store (latest of each name) over ``base``.

        Parameters
        ----------
        store : mechdyn.store.ResultStore
            The results database.
        base : MaterialDatabase, optional
            The database they are added to (default: the shipped one).
        """
        rows = store.records("material")
        return (base or cls()).add(*(Material.from_dict(r.data) for r in reversed(rows)))


def default_materials() -> MaterialDatabase:
    """The shipped materials (a new database each time: the shipped file is read once a process)."""
    return MaterialDatabase({m.name: m for m in _shipped()})


@functools.lru_cache(maxsize=1)
def _shipped() -> tuple[Material, ...]:
    """The shipped file's materials, read and checked once (each :class:`Material` is immutable)."""
    with resources.as_file(resources.files("mechdyn.mounts").joinpath("data/materials.toml")) as path:
        return tuple(_read(path))


def save_materials(store: Any, materials: MaterialDatabase, provenance: str) -> list[int]:
    """Write every material into the results store with its provenance; returns the record ids.

    Parameters
    ----------
    store : mechdyn.store.ResultStore
        The results database.
    materials : MaterialDatabase
        The materials to write.
    provenance : str
        Where they come from.
    """
    return [
        store.put_record("material", m.name, m.as_dict(), provenance) for m in materials.materials.values()
    ]
