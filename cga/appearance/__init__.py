"""Appearance: PBR materials for every surface and ceiling lights for every room
(DESIGN §14, docs/appearance.md).

* :mod:`.material`: a resolved material (glTF metallic-roughness) and sRGB/linear;
* :mod:`.tables`: the CSV conventions of the appearance tables;
* :mod:`.library`: the material table (``rules/materials.csv``) and part classes;
* :mod:`.palette`: which material dresses which surface, neutral or drawn with the seed;
* :mod:`.dress`: a material index for every triangle of every scene node;
* :mod:`.lights`: the light table (``rules/lights.csv``) and the lights of each room.

A build's :class:`Appearance` says which tables it reads and whether it randomises
(``cga build --materials random``, or the grammar variable ``materials = "random"``;
``material_table`` and ``light_table`` name the grammar's own tables).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any

from cga.errors import UsageError

from .library import MaterialLibrary, load_material_library
from .lights import Light, LightRules, load_light_rules, plan_lights
from .material import Material
from .palette import MATERIAL_MODES, MaterialMode, Palette

if TYPE_CHECKING:  # pragma: no cover
    from cga.sandbox import Sandbox

__all__ = ["Appearance", "Light", "Material", "MATERIAL_MODES", "MaterialMode", "Palette",
           "MATERIAL_TABLE", "LIGHT_TABLE", "appearance_from", "check_mode", "scene_lights",
           "shipped_appearance"]

MATERIAL_TABLE = "materials.csv"
"""The shipped material table (in ``cga.rules``)."""

LIGHT_TABLE = "lights.csv"
"""The shipped light table (in ``cga.rules``)."""


@dataclass(frozen=True)
class Appearance:
    """How a build looks: ``mode`` (``neutral`` or ``random``), its material table and
    its light table."""

    mode: MaterialMode
    materials: MaterialLibrary
    lights: LightRules

    @property
    def random(self) -> bool:
        return self.mode == "random"

    def palette(self, seed: int) -> Palette:
        return Palette(self.materials, seed, self.mode)


def check_mode(mode: Any, what: str = "--materials") -> MaterialMode:
    """``mode`` if it is a material mode.

    Raises
    ------
    UsageError
        It is not one of :data:`MATERIAL_MODES`.
    """
    if mode not in MATERIAL_MODES:
        raise UsageError(f"{what} must be one of {', '.join(MATERIAL_MODES)}, got {mode!r}")
    return mode


def _shipped_tables() -> tuple[MaterialLibrary, LightRules]:
    """The shipped tables, found on every call (a batch records each build's inputs,
    cga.provenance) and parsed once per process."""
    from cga.resources import resolve_resource

    return _load_tables(resolve_resource(MATERIAL_TABLE), resolve_resource(LIGHT_TABLE))


@lru_cache(maxsize=8)
def _load_tables(materials: Path, lights: Path) -> tuple[MaterialLibrary, LightRules]:
    return load_material_library(materials), load_light_rules(lights)


def shipped_appearance(mode: MaterialMode = "neutral") -> Appearance:
    """The shipped tables in ``mode`` (each table read once per process)."""
    materials, lights = _shipped_tables()
    return Appearance(check_mode(mode), materials, lights)


def appearance_from(variables: dict[str, Any], *, mode: str | None = None,
                    base_dir: Path | None = None, sandbox: "Sandbox | None" = None) -> Appearance:
    """A build's appearance from its options and grammar variables.

    ``mode`` (the ``--materials`` option) wins over the grammar variable ``materials``;
    the variables ``material_table`` and ``light_table`` name tables found like rule
    tables (the grammar's folder, then the shipped ones).

    Raises
    ------
    UsageError
        A mode that is not ``neutral`` or ``random``.
    RuleTableError, ResourceNotFoundError
        A table cannot be found or read.
    """
    from cga.resources import resolve_resource

    chosen = check_mode(mode) if mode is not None else check_mode(
        variables.get("materials", "neutral"), "the grammar variable 'materials'")
    materials, lights = _shipped_tables()
    table = variables.get("material_table")
    if isinstance(table, str) and table:
        materials = load_material_library(resolve_resource(table, base_dir=base_dir,
                                                           sandbox=sandbox))
    table = variables.get("light_table")
    if isinstance(table, str) and table:
        lights = load_light_rules(resolve_resource(table, base_dir=base_dir, sandbox=sandbox))
    return Appearance(chosen, materials, lights)


def scene_lights(floors: Any, appearance: Appearance, seed: int) -> list[Light]:
    """Every ceiling light of a build, storey by storey."""
    return [light for plan in floors
            for light in plan_lights(plan, appearance.lights, seed, random=appearance.random)]
