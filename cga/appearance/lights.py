"""Ceiling lights per room, from a light table (docs/appearance.md).

``rules/lights.csv`` has one row per room type (``*`` for any other room)::

    Room;Count;Spacing;Lumens;Temperature
    Office;3;;800..1200;3500..5000

* ``Count`` a number: that many lights in one row along the room's length, at the
  centres of equal stretches, ``(2i + 1) L / 2n`` — three lights in an office of
  length L hang at L/6, L/2 and 5L/6, as the TFG's offices have them (Ruiz 2016 §3.3);
* ``Count`` ``auto``: a grid with ``max(1, round(L / Spacing))`` lights along and
  ``max(1, round(W / Spacing))`` across (default spacing 3 m), at most
  :data:`MAX_LIGHTS` in all: a larger grid is spread wider, as a count is capped at 100
  (a 100 km hall would otherwise hang 800,000 lights).

The length runs along the longer side of the room's minimum rotated rectangle; a light
that would fall outside the room (an L-shaped room) is left out, and a room keeps at
least one light (at a point inside it). Lights hang 5 cm under the ceiling. ``Lumens``
and ``Temperature`` (kelvin) are ranges a random build draws from once per room
(stream ``("lights", floor, room)``); a neutral build takes their middles.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Polygon

from cga.errors import RuleTableError
from cga.model import FloorPlan, Room
from cga.randomness import stream
from cga.textfiles import read_table_text

from .material import RGB, srgb_to_linear
from .tables import Range, rows_of

__all__ = ["Light", "LightRule", "LightRules", "load_light_rules", "parse_light_rules",
           "room_light_points", "plan_lights", "kelvin_to_rgb", "HANG", "MAX_LIGHTS"]

HANG = 0.05
"""How far under the ceiling a light hangs (m)."""

_COLUMNS = ("Room", "Count", "Spacing", "Lumens", "Temperature")


@dataclass(frozen=True)
class LightRule:
    """One row: ``count`` lights in a row (None: ``auto`` grid at ``spacing`` metres)."""

    room: str
    count: int | None
    spacing: float
    lumens: Range
    temperature: Range
    row: int


@dataclass(frozen=True)
class LightRules:
    """The rows of a light table, by lower-case room type (``*``: any other room)."""

    rules: dict[str, LightRule]
    file: str

    def for_room(self, room_type: str | None) -> LightRule:
        return self.rules.get((room_type or "").lower()) or self.rules["*"]


@dataclass(frozen=True)
class Light:
    """A point light under a room's ceiling.

    ``position`` is in the world frame (metres, y up); ``lumens`` its luminous flux and
    :attr:`intensity` the same light in candela (glTF ``KHR_lights_punctual`` point
    lights are in candela: lm / 4π sr); ``temperature`` in kelvin and ``color`` the
    linear RGB of that temperature (largest component 1).
    """

    name: str
    floor: int
    room: int
    position: tuple[float, float, float]
    lumens: float
    temperature: float
    color: RGB

    @property
    def intensity(self) -> float:
        return self.lumens / (4.0 * math.pi)


def kelvin_to_rgb(kelvin: float) -> RGB:
    """Linear RGB (largest component 1) of a black body at ``kelvin`` (1000–40000 K).

    Tanner Helland's fit (2012) to Mitchell Charity's black-body colour table gives sRGB
    components; they are turned linear here, as glTF light colours are.
    """
    t = min(max(kelvin, 1000.0), 40000.0) / 100.0
    red = 255.0 if t <= 66 else 329.698727446 * (t - 60) ** -0.1332047592
    green = (99.4708025861 * math.log(t) - 161.1195681661 if t <= 66
             else 288.1221695283 * (t - 60) ** -0.0755148492)
    blue = 255.0 if t >= 66 else (0.0 if t <= 19 else
                                  138.5177312231 * math.log(t - 10) - 305.0447927307)
    srgb = np.clip(np.array([red, green, blue]) / 255.0, 0.0, 1.0)
    linear = srgb_to_linear(srgb)
    linear = linear / max(float(linear.max()), 1e-9)
    r, g, b = (round(float(v), 6) for v in linear)
    return (r, g, b)


MAX_LIGHTS = 100
"""Lights of one room at most, whether counted in the table or laid out on a grid."""


def room_light_points(interior: Polygon, rule: LightRule) -> list[tuple[float, float]]:
    """Plan points ``(x, z)`` of a room's lights (module notes)."""
    if interior.is_empty:
        return []
    rect = interior.minimum_rotated_rectangle
    corners = np.asarray(rect.exterior.coords)[:4] if isinstance(rect, Polygon) else None
    if corners is None or len(corners) < 4:
        p = interior.representative_point()
        return [(float(p.x), float(p.y))]
    a, b, c = corners[0], corners[1], corners[2]
    u, v = b - a, c - b
    if np.linalg.norm(u) < np.linalg.norm(v):
        a, u, v = b, v, a - b  # the long side first: from corner b along b → c
    length, width = float(np.linalg.norm(u)), float(np.linalg.norm(v))
    if rule.count is not None:
        along, across = rule.count, 1
    else:
        along = max(1, round(length / rule.spacing))
        across = max(1, round(width / rule.spacing))
        if along * across > MAX_LIGHTS:  # a hall-sized room: the grid spreads out
            spread = math.sqrt(along * across / MAX_LIGHTS)
            across = max(1, min(across, math.floor(across / spread)))
            along = max(1, min(along, MAX_LIGHTS // across))
    points = [a + u * (2 * i + 1) / (2 * along) + v * (2 * j + 1) / (2 * across)
              for i in range(along) for j in range(across)]
    inside = [(float(p[0]), float(p[1])) for p in points
              if shapely.contains_xy(interior, float(p[0]), float(p[1]))]
    if not inside:
        p = interior.representative_point()
        inside = [(float(p.x), float(p.y))]
    return inside


def plan_lights(plan: FloorPlan, rules: LightRules, seed: int, *, random: bool) -> list[Light]:
    """The ceiling lights of every room of a storey."""
    ceiling = plan.elevation + plan.height - (plan.settings.slab_thickness if plan.is_top else 0.0)
    out = []
    for room in plan.rooms:
        rule = rules.for_room(room.type)
        lumens, kelvin = _draw(rule, seed, plan, room, random)
        color = kelvin_to_rgb(kelvin)
        for k, (x, z) in enumerate(room_light_points(room.interior, rule)):
            out.append(Light(f"floor{plan.index}/{room.label}/light{k}", plan.index, room.id,
                             (round(x, 6), round(ceiling - HANG, 6), round(z, 6)),
                             round(lumens, 3), round(kelvin, 1), color))
    return out


def _draw(rule: LightRule, seed: int, plan: FloorPlan, room: Room, random: bool
          ) -> tuple[float, float]:
    if not random:
        return rule.lumens.mid, rule.temperature.mid
    rng = stream(seed, ("lights", f"floor{plan.index}", f"room{room.id}"))
    return rule.lumens.draw(rng), rule.temperature.draw(rng)


def load_light_rules(path: str | Path) -> LightRules:
    """Read a light table.

    Raises
    ------
    RuleTableError
        A bad cell (naming row and column), a room given twice, or no ``*`` row.
    """
    return parse_light_rules(read_table_text(path), file=str(path))


def parse_light_rules(text: str, *, file: str = "<lights>") -> LightRules:
    """Parse the text of a light table (see :func:`load_light_rules`)."""
    rules: dict[str, LightRule] = {}
    for cells in rows_of(text, file, _COLUMNS, ("Room", "Lumens", "Temperature")):
        room = cells.text("Room", required=True).lower()
        if room in rules:
            raise cells.error("Room", f"room type {room!r} is already given in row "
                                      f"{rules[room].row}")
        count_text = cells.text("Count").lower()
        count: int | None = None
        if count_text and count_text != "auto":
            value = cells.number("Count", 1, MAX_LIGHTS)
            if value != int(value):
                raise cells.error("Count", f"expected a whole number of lights or auto, got "
                                           f"{count_text!r}")
            count = int(value)
        rules[room] = LightRule(room, count, cells.number("Spacing", 0.5, 100.0, default=3.0),
                                cells.range("Lumens", 0.0, 1e6),
                                cells.range("Temperature", 1000.0, 40000.0), cells.row)
    if "*" not in rules:
        raise RuleTableError("no '*' row: the lights of rooms of other types", file=file)
    return LightRules(rules, file)
