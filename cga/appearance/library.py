"""The material library: a shipped, editable table of PBR materials (docs/appearance.md).

``rules/materials.csv`` (or a grammar's own table) has one row per material::

    Material;Surface;Color;Roughness;Metallic;Alpha;Value;Weight;Models;Parts;Rooms
    oak;wood;#b88c5c;0.55..0.75;0;1;0.75..1.2;3;;;

* ``Surface`` is the class of surface the material may dress: structure classes
  (:data:`STRUCTURE_SURFACES`: ``wall`` paint, ``facade``, ``floor``, ``ceiling``,
  ``slab`` edges, ``roof``, ``stair``, ``rail``, massing ``mass`` and ``face``) or a
  furniture part class (``wood``, ``fabric``, ``metal``, ...), which a model names in its
  OBJ group names (``g part_3_wood``); ``furniture`` dresses parts of no known class.
* ``Color`` (sRGB ``#rrggbb``), ``Roughness`` (a number or a range ``lo..hi``),
  ``Metallic`` and ``Alpha`` (< 1: see-through) are glTF metallic-roughness values.
* ``Value`` (default 1): the range a random build scales the colour's HSV value by, hue
  and saturation kept (the TFG's wood variation, Ruiz 2016 §3.2); ``Weight`` (default 1)
  how often a random build picks the row; 0 never (a neutral row).
* ``Models``, ``Parts`` and ``Rooms`` (``;``-separated, empty for any) restrict the row
  to furniture models, to part (group) names, and to room types: the MSU generator's
  material targets (Kaňuch et al., model class and part).

The first row of a surface class that a surface may take is its neutral look (a build
without ``--materials random``).
"""

from __future__ import annotations

import colorsys
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import TypeVar

import numpy as np

from cga.errors import RuleTableError
from cga.textfiles import read_table_text

from .material import RGB, Material
from .tables import Cells, Range, rows_of

__all__ = ["STRUCTURE_SURFACES", "FALLBACK_PART", "MaterialRow", "MaterialLibrary",
           "load_material_library", "parse_material_library", "part_class"]

STRUCTURE_SURFACES = ("wall", "facade", "floor", "ceiling", "slab", "roof", "stair", "rail",
                      "mass", "face")
"""Surface classes of the building itself; a material table must give each one a row."""

FALLBACK_PART = "furniture"
"""The class of a furniture part whose group name names no class of the table."""

_COLUMNS = ("Material", "Surface", "Color", "Roughness", "Metallic", "Alpha", "Value", "Weight",
            "Models", "Parts", "Rooms")
_REQUIRED = ("Material", "Surface", "Color", "Roughness")
_HEX = re.compile(r"^#?([0-9a-fA-F]{6})$")
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
_TOKENS = re.compile(r"[^A-Za-z]+")
_T = TypeVar("_T")


@dataclass(frozen=True)
class MaterialRow:
    """One row of the material table (see the module notes)."""

    name: str
    surface: str
    color: RGB
    roughness: Range
    metallic: float
    alpha: float
    value: Range
    weight: float
    models: tuple[str, ...]
    parts: tuple[str, ...]
    rooms: tuple[str, ...]
    row: int

    @property
    def restricted(self) -> bool:
        return bool(self.models or self.parts or self.rooms)

    def allows(self, model: str | None, part: str | None, room: str | None) -> bool:
        """Whether the row may dress a surface of ``model``'s part ``part`` in a room of
        type ``room`` (names compared in lower case; None: not a furniture part / no room)."""
        return ((not self.models or (model or "").lower() in self.models)
                and (not self.parts or (part or "").lower() in self.parts)
                and (not self.rooms or (room or "").lower() in self.rooms))

    def look(self, rng: np.random.Generator | None, color: RGB | None = None) -> Material:
        """The row's material: neutral (``rng`` None: the given ``color`` or the row's,
        mid roughness), or varied by ``rng`` (HSV value scaled within ``value``, hue and
        saturation kept; roughness drawn within ``roughness``)."""
        base = self.color if color is None or rng is not None else color
        if rng is None:
            return Material.of(self.name, self.surface, base, self.roughness.mid,
                               self.metallic, self.alpha)
        h, s, v = colorsys.rgb_to_hsv(*base)
        scaled = min(1.0, v * self.value.draw(rng))
        varied = colorsys.hsv_to_rgb(h, s, scaled)
        return Material.of(self.name, self.surface, varied, self.roughness.draw(rng),
                           self.metallic, self.alpha)


@dataclass(frozen=True)
class MaterialLibrary:
    """The rows of a material table, in table order, and the file they came from.

    A library serves every build of a process (a batch dresses thousands of houses from
    one table), so its answers are remembered per question."""

    rows: tuple[MaterialRow, ...]
    file: str
    _answers: dict[tuple[object, ...], object] = field(default_factory=dict, init=False,
                                                       repr=False, compare=False)

    @cached_property
    def part_classes(self) -> tuple[str, ...]:
        """Surface classes that furniture parts may name (every class but the structure's)."""
        return tuple(sorted({r.surface for r in self.rows} - set(STRUCTURE_SURFACES)))

    def candidates(self, surface: str, *, model: str | None = None, part: str | None = None,
                   room: str | None = None) -> list[MaterialRow]:
        """Rows of ``surface`` allowed for the model, part and room, in table order."""
        question = ("candidates", surface, model, part, room)
        if question not in self._answers:
            self._answers[question] = tuple(r for r in self.rows if r.surface == surface
                                            and r.allows(model, part, room))
        return list(self._answers[question])  # type: ignore[call-overload]

    def remember(self, question: tuple[object, ...], answer: Callable[[], _T]) -> _T:
        """The answer to ``question`` (a tuple naming everything the answer depends on
        besides the table), worked out by ``answer()`` the first time it is asked."""
        if question not in self._answers:
            self._answers[question] = answer()
        return self._answers[question]  # type: ignore[return-value]

    def targets(self, model: str, part: str) -> bool:
        """Whether some row names this part of this model specifically."""
        question = ("targets", model, part)
        if question not in self._answers:
            self._answers[question] = any(
                part.lower() in r.parts and (not r.models or model.lower() in r.models)
                for r in self.rows)
        return bool(self._answers[question])


def part_class(group_name: str, classes: tuple[str, ...]) -> str:
    """The material class an OBJ group name names: its last word that is a class of the
    table (``part_3_wood`` → ``wood``, ``Seat.Fabric`` → ``fabric``), else
    :data:`FALLBACK_PART`."""
    for word in reversed(_TOKENS.split(group_name.lower())):
        if word in classes:
            return word
    return FALLBACK_PART


def load_material_library(path: str | Path) -> MaterialLibrary:
    """Read a material table.

    Raises
    ------
    RuleTableError
        The file cannot be read, or a cell, row or the table is invalid (naming the
        row and column).
    """
    return parse_material_library(read_table_text(path), file=str(path))


def parse_material_library(text: str, *, file: str = "<materials>") -> MaterialLibrary:
    """Parse the text of a material table (see :func:`load_material_library`)."""
    rows: list[MaterialRow] = []
    seen: dict[str, int] = {}
    for cells in rows_of(text, file, _COLUMNS, _REQUIRED):
        row = _row(cells)
        if row.name in seen:
            raise cells.error("Material", f"material {row.name!r} is already defined in row "
                                          f"{seen[row.name]}")
        seen[row.name] = cells.row
        rows.append(row)
    present = {r.surface for r in rows}
    missing = [s for s in (*STRUCTURE_SURFACES, FALLBACK_PART) if s not in present]
    if missing:
        raise RuleTableError(f"no material for the surface class{'es' * (len(missing) > 1)} "
                             f"{', '.join(missing)}; every build needs one", file=file)
    for surface in sorted(present):
        if not any(not r.restricted for r in rows if r.surface == surface):
            first = next(r for r in rows if r.surface == surface)
            raise RuleTableError(f"every material of surface {surface!r} is restricted; one "
                                 f"row without Models, Parts and Rooms is its neutral look",
                                 file=file, row=first.row)
    return MaterialLibrary(tuple(rows), file)


def _row(cells: Cells) -> MaterialRow:
    name = cells.text("Material", required=True)
    if not _NAME.match(name):
        raise cells.error("Material", f"{name!r} is not a name (a letter, then letters, digits "
                                      f"or _)")
    surface = cells.text("Surface", required=True).lower()
    if not _NAME.match(surface) or not surface.isalpha():
        raise cells.error("Surface", f"{surface!r} is not a surface class (letters only, e.g. "
                                     f"wall, floor, wood, fabric)")
    color = cells.text("Color", required=True)
    match = _HEX.match(color)
    if match is None:
        raise cells.error("Color", f"expected an sRGB colour #rrggbb, got {color!r}")
    code = match.group(1)
    rgb = tuple(int(code[i:i + 2], 16) / 255.0 for i in (0, 2, 4))
    weight = cells.number("Weight", 0.0, 1e6, default=1.0)
    return MaterialRow(
        name=name, surface=surface, color=(rgb[0], rgb[1], rgb[2]),
        roughness=cells.range("Roughness", 0.0, 1.0),
        metallic=cells.number("Metallic", 0.0, 1.0, default=0.0),
        alpha=cells.number("Alpha", 0.0, 1.0, default=1.0),
        value=cells.range("Value", 0.0, 10.0, default=Range(1.0, 1.0)),
        weight=weight, models=cells.names("Models"), parts=cells.names("Parts"),
        rooms=cells.names("Rooms"), row=cells.row)
