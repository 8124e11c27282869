"""``<name>.scene.json``: everything a build decided, as plain data with a schema.

The document lists floors, rooms, walls (with openings), doors, windows, furniture
poses, room-graph edges (door edges per floor, stair edges between floors), stairs,
the materials and ceiling lights (docs/appearance.md), diagnostics, checks, the seed and
the tool version, in the
world frame of docs/architecture.md ("Units and frames") (metres, y up, plan coordinates
``(x, z)``). Its JSON Schema (draft 2020-12) ships as package data,
``cga/schema/scene.schema.json``.

The text is deterministic: keys sorted, floats rounded to 1e-6, lists in model order
(ids ascending). The one exception is ``timings`` (wall-clock seconds per stage), kept
in its own top-level key so a comparison can drop it.

:func:`scene_as_dict` builds the document (a pure function); :func:`export_scene_json`
writes it.
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Iterable, Mapping, Sequence
from functools import cache
from importlib.resources import files
from json.encoder import encode_basestring
from pathlib import Path
from typing import Any

import numpy as np
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.polygon import orient

import cga
from cga.appearance.lights import Light
from cga.errors import ExportError
from cga.fsutil import atomic_write
from cga.model import OUTSIDE, Door, Flight, FloorPlan, FurnitureItem, Room, Stair, Wall, Window
from cga.quality import quality_report
from cga.scene import Scene, SceneNode
from cga.semantics import class_names, class_table, instance_ids, node_class

from .palette import node_materials

__all__ = [
    "FORMAT",
    "FORMAT_VERSION",
    "load_schema",
    "scene_as_dict",
    "scene_json_text",
    "json_text",
    "export_scene_json",
]

FORMAT = "cga.scene"
"""Value of the document's ``format`` key."""

FORMAT_VERSION = 1
"""Incremented when a key changes meaning or disappears (additions keep the version)."""

_DIGITS = 6


@cache
def load_schema() -> dict[str, Any]:
    """The scene document's JSON Schema (draft 2020-12), from the package data."""
    text = (files("cga") / "schema" / "scene.schema.json").read_text(encoding="utf-8")
    return json.loads(text)


def scene_as_dict(scene: Scene, nodes: Sequence[SceneNode]) -> dict[str, Any]:
    """Build the scene document.

    Parameters
    ----------
    scene:
        The build result.
    nodes:
        Its scene nodes; they give the ``nodes`` index (path, kind, bounds) and link
        rooms and furniture to the glTF node of the same name.

    Returns
    -------
    dict
        JSON-ready data (only dicts, lists, strings, finite rounded floats, ints, bools
        and None) matching ``scene.schema.json``.

    Raises
    ------
    ExportError
        A value cannot be represented in JSON (e.g. a NaN in the checks).
    """
    return _clean(_document(scene, nodes))


def scene_json_text(scene: Scene, nodes: Sequence[SceneNode]) -> str:
    """The document as text: :func:`json_text` of :func:`scene_as_dict`.

    Written in one walk over the document as :func:`_document` makes it, rounding floats
    as they are written: the text of cleaning it (:func:`_clean`) and then writing it,
    without the second walk. A value that walk does not take as it is (not plain JSON
    data, a number not finite, a key not exactly a string) sends the document the long
    way, which converts it or names where it is unfit.

    Raises
    ------
    ExportError
        A value cannot be represented in JSON (e.g. a NaN in the checks).
    """
    return _document_text(_document(scene, nodes))


def _document_text(document: Any) -> str:
    """``json_text(_clean(document))``, in one walk where it can (:func:`scene_json_text`)."""
    try:
        return _text(document, _Rounded())
    except (TypeError, ValueError):
        return json_text(_clean(document))


def _document(scene: Scene, nodes: Sequence[SceneNode]) -> dict[str, Any]:
    """The document before :func:`_clean`: numbers as the model holds them."""
    labels = _node_labels(nodes)
    node_paths = set(labels)
    leaves = {node.path: node for node in nodes if node.door is not None}
    floors = scene.floors
    stairs = sorted({s.id: s for p in floors for s in p.stairs}.values(), key=lambda s: s.id)
    return {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "generator": {"name": "cga", "version": cga.__version__},
        "name": scene.name,
        "seed": int(scene.seed),
        "units": float(scene.units),
        "georeference": (None if scene.georeference is None
                         else scene.georeference.to_dict()),
        "frame": {
            "length_unit": "m",
            "up": "+y",
            "plan_axes": ["x", "z"],
            "furniture_front_at_rotation_0": "-z",
        },
        "floors": [_floor(p) for p in floors],
        "rooms": [_room(p, r, node_paths) for p in floors for r in p.rooms],
        "walls": [_wall(p, w) for p in floors for w in p.walls],
        "doors": [_door(p, d) for p in floors for d in p.doors],
        "windows": [_window(p, w) for p in floors for w in p.windows],
        "furniture": [_furniture(p, f, labels, leaves) for p in floors for f in p.furniture],
        "room_graph": [e for p in floors for e in _graph_edges(p)] + [_stair_edge(s) for s in stairs],
        "stairs": [_stair(s, node_paths) for s in stairs],
        "quality": quality_report(list(floors)),
        "nodes": [{**_node(n), **labels[n.path]} for n in nodes],
        "classes": [{"id": c.id, "name": c.name, "group": c.group} for c in class_table()],
        "diagnostics": [_fields(d) for d in scene.all_diagnostics()],
        "checks": {name: {**report.to_dict(), "summary": report.summary()}
                   for name, report in scene.checks.items()},
        "timings": dict(scene.timings),
        "difficulty": scene.difficulty.to_dict() if scene.difficulty is not None else None,
        "appearance": {"mode": scene.looks().mode, "materials": _materials(nodes)},
        "lights": [_light(light) for light in scene.lights],
    }


def json_text(document: Any) -> str:
    """JSON text as cga writes it: sorted keys, two-space indent, lists of numbers
    (points, matrix rows) on one line, trailing newline.

    The text is what ``json.dumps(document, sort_keys=True, indent=2,
    ensure_ascii=False, allow_nan=False)`` gives with every list of only numbers joined
    onto one line (``[1.0, 2.0]``), written in one walk: the standard library's
    encoder runs in pure Python as soon as it indents, and a scene holds tens of
    thousands of values.

    Raises
    ------
    ValueError
        A float is NaN or infinite.
    TypeError
        A value is not JSON data (dict with string keys, list, tuple, string, number,
        bool, None).
    """
    return _text(document, _Plain())


def _text(document: Any, style: _Plain) -> str:
    """The text of ``document`` (:func:`json_text`), its numbers written in ``style``."""
    parts: list[str] = []
    _write(document, "\n", parts, style)
    parts.append("\n")
    return "".join(parts)


def _write(value: Any, newline: str, parts: list[str], style: _Plain) -> None:
    """Append the JSON text of ``value`` to ``parts``; ``newline`` is a line break and
    the indent of the line ``value`` starts on."""
    text = _one_line(value, style)
    if text is not None:
        parts.append(text)
    else:
        _write_block(value, newline, parts, style)


def _write_block(value: dict[Any, Any] | Sequence[Any], newline: str, parts: list[str],
                 style: _Plain) -> None:
    """Append a dict or list that :func:`_one_line` spreads over lines."""
    if isinstance(value, dict):
        _write_dict(value, newline, parts, style)
    else:
        _write_list(value, newline, parts, style)


def _write_dict(value: dict[Any, Any], newline: str, parts: list[str],
                style: _Plain) -> None:
    inner = newline + "  "
    lead = "{" + inner
    names = style.names
    for key in sorted(value):
        item = value[key]
        if type(key) is str:
            name = names.get(key)
            if name is None:
                name = names[key] = _string(key) + ": "
        else:  # not kept: a subclass equal to a string is not written as that string
            name = _string(style.key(key)) + ": "
        head = lead + name
        text = _one_line(item, style)  # most values: one append, no call further down
        if text is not None:
            parts.append(head + text)
        else:
            parts.append(head)
            _write_block(item, inner, parts, style)
        lead = "," + inner
    parts.append(newline + "}")


def _write_list(value: Sequence[Any], newline: str, parts: list[str],
                style: _Plain) -> None:
    inner = newline + "  "
    lead = "[" + inner
    for item in value:
        text = _one_line(item, style)
        if text is not None:
            parts.append(lead + text)
        else:
            parts.append(lead)
            _write_block(item, inner, parts, style)
        lead = "," + inner
    parts.append(newline + "]")


def _one_line(value: Any, style: _Plain) -> str | None:
    """The text of ``value`` when it is written on one line (a scalar, an empty dict or
    list, a list of only numbers), None for a dict or list spread over lines."""
    kind = type(value)  # exact types first, the commonest first: nearly every value is one
    if kind is str:
        return _string(value)
    if kind is int:
        return int.__repr__(value)
    if kind is dict:
        return None if value else "{}"
    if kind is float:
        return style.scalar(value)
    if kind is bool or value is None:
        return _LITERALS[value]
    if kind is list or kind is tuple:
        return _numbers(value, style) if value else "[]"
    if isinstance(value, str):
        return _string(value)
    if isinstance(value, dict):
        return None if value else "{}"
    if isinstance(value, (list, tuple)):
        return _numbers(value, style) if value else "[]"
    return style.scalar(value)


_LITERALS = {True: "true", False: "false", None: "null"}

_PLAIN_NUMBERS = frozenset({float, int})
"""The exact types whose :func:`repr` is their JSON text (NaN and infinities aside)."""


def _numbers(values: Sequence[Any], style: _Plain) -> str | None:
    """A non-empty list of only numbers (points, matrix rows) on one line, None for any
    other list."""
    if _PLAIN_NUMBERS.issuperset(map(type, values)):
        text = style.numbers(values)
        if "n" not in text:  # "nan", "inf": no finite number's repr has an n
            return "[" + text + "]"
    elif not all(_is_number(v) for v in values):
        return None
    return "[" + ", ".join(map(style.scalar, values)) + "]"


def _is_number(value: Any) -> bool:
    """Whether JSON writes ``value`` as a number (bools are ``true`` and ``false``)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool)


_string = encode_basestring
"""A JSON string literal, as :mod:`json` writes it with ``ensure_ascii=False``."""


class _Plain:
    """How :func:`json_text` writes numbers and keys: as :mod:`json` does.

    ``names`` holds the text of each key written so far (``"name": ``): a document
    writes its few hundred keys thousands of times."""

    def __init__(self) -> None:
        self.names: dict[str, str] = {}

    def numbers(self, values: Sequence[float | int]) -> str:
        """Floats and ints (exactly those types) as JSON text, comma-separated, NaN as
        ``nan`` and infinities as ``inf``."""
        return ", ".join(map(repr, values))

    def scalar(self, value: Any) -> str:
        """A JSON number or literal, as :mod:`json` writes it.

        Raises
        ------
        ValueError
            A float is NaN or infinite.
        TypeError
            ``value`` is not a number, a bool or None.
        """
        if isinstance(value, float):
            if not math.isfinite(value):
                raise ValueError(f"Out of range float values are not JSON compliant: {value!r}")
            return float.__repr__(value)
        if value is None:
            return "null"
        if value is True or value is False:
            return "true" if value else "false"
        if isinstance(value, int):
            return int.__repr__(value)
        raise TypeError(f"Object of type {type(value).__name__} is not JSON serializable")

    @staticmethod
    def key(key: Any) -> str:
        """A dict key that is not exactly a :class:`str`: a subclass as it is.

        Raises
        ------
        TypeError
            ``key`` is not a string.
        """
        if not isinstance(key, str):
            raise TypeError(f"keys must be str, not {type(key).__name__}")
        return key


_FLOATS = frozenset({float})
"""Lists of exactly these types are written from :class:`_Rounded`'s written floats."""


class _Rounded(_Plain):
    """How :func:`scene_json_text` writes numbers and keys: as :func:`json_text` writes
    them once :func:`_clean` has converted them (floats rounded to 1e-6, ``-0.0`` →
    ``0.0``, float and int subclasses as floats and ints). Any other value, and a key
    not exactly a string, raises :class:`TypeError`: :func:`_clean` has to convert it.

    Each distinct float is rounded and written once per document, then looked up: a
    scene's five thousand floats are some seven hundred values (colours, sizes, a wall's
    ends again in its rooms and nodes), and rounding one costs more than looking it up.
    ``-0.0`` and ``0.0`` are one key, and both are written ``0.0``; a NaN is refused
    before it is kept."""

    def __init__(self) -> None:
        super().__init__()
        self.written: dict[float, str] = {}

    def numbers(self, values: Sequence[float | int]) -> str:
        if _FLOATS.issuperset(map(type, values)):
            try:
                return ", ".join(map(self.written.__getitem__, values))
            except KeyError:  # a value not met before (or a NaN, refused)
                return ", ".join(map(self.scalar, values))
        return ", ".join([self.scalar(v) if type(v) is float else repr(v) for v in values])

    def scalar(self, value: Any) -> str:
        if isinstance(value, float):
            text = self.written.get(value)
            if text is None:
                text = self.written[value] = super().scalar(round(float(value), _DIGITS) + 0.0)
            return text
        if isinstance(value, int) and not isinstance(value, bool):
            return int.__repr__(int(value))
        if value is None or isinstance(value, bool):
            return super().scalar(value)
        raise TypeError(f"a {type(value).__name__} is left to _clean")

    @staticmethod
    def key(key: Any) -> str:
        raise TypeError(f"a {type(key).__name__} key is left to _clean")


def export_scene_json(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path,
                      name: str) -> list[Path]:
    """Write ``<out_dir>/<name>.scene.json`` atomically and return its path."""
    return [atomic_write(Path(out_dir) / f"{name}.scene.json", scene_json_text(scene, nodes))]


# -- pieces -----------------------------------------------------------------------------

def _fields(value: Any) -> dict[str, Any]:
    """A dataclass instance's fields by name, as they are: once :func:`_clean` has
    converted them (nested dataclasses too) the very data :func:`dataclasses.asdict`
    gives, without its deep copy of every value (a fifth of the document's making)."""
    return {field.name: getattr(value, field.name) for field in dataclasses.fields(value)}


def _floor(plan: FloorPlan) -> dict[str, Any]:
    return {
        "index": plan.index,
        "elevation": plan.elevation,
        "floor_y": plan.floor_y,
        "height": plan.height,
        "is_top": plan.is_top,
        "footprint": _polygon(plan.footprint),
        "area": float(plan.footprint.area),
        "settings": _fields(plan.settings),
        "stairwell": _polygon(plan.stairwell) if plan.stairwell is not None else None,
        "stair_core": plan.core_room,
    }


def _room(plan: FloorPlan, room: Room, node_paths: set[str]) -> dict[str, Any]:
    path = f"floor{plan.index}/{room.label}"
    return {
        "floor": plan.index,
        "id": room.id,
        "type": room.type,
        "circulation": room.circulation,
        "polygon": _polygon(room.polygon),
        "interior": _polygon(room.interior),
        "area": room.area,
        "floor_area": float(room.interior.area),
        "node": path if path in node_paths else None,
        "circulation": room.circulation,
        "private": room.private,
    }


def _wall(plan: FloorPlan, wall: Wall) -> dict[str, Any]:
    return {
        "floor": plan.index,
        "id": wall.id,
        "start": list(wall.start),
        "end": list(wall.end),
        "length": wall.length,
        "outer": wall.outer,
        "rooms": list(wall.rooms),
        "thickness": wall.thickness,
        "openings": [
            {**_fields(o), "position": list(wall.point_at(o.center))}
            for o in sorted(wall.openings, key=lambda o: (o.center, o.kind))
        ],
    }


def _door(plan: FloorPlan, door: Door) -> dict[str, Any]:
    return {
        "floor": plan.index,
        "id": door.id,
        "wall": door.wall,
        "rooms": list(door.rooms),
        "position": list(door.position),
        "width": door.width,
        "height": door.height,
        "swing_room": door.swing_room,
        "hinge": door.hinge,
        "front": door.is_front,
        "reason": door.reason,
        "leaf": door.leaf,
        **_door_joint(plan, door),
    }


def _door_joint(plan: FloorPlan, door: Door) -> dict[str, Any]:
    """The door's state and its leaf's hinge (:mod:`cga.doors`), in the world frame."""
    from cga.doors import door_leaf

    leaf = door_leaf(plan, door, thickness=1e-3)  # the hinge does not depend on it
    return {"state": door.state, "angle_degrees": math.degrees(door.angle),
            "limits_degrees": [math.degrees(leaf.lower), math.degrees(leaf.upper)],
            "hinge_point": list(leaf.hinge), "hinge_axis": list(leaf.axis)}


def _window(plan: FloorPlan, window: Window) -> dict[str, Any]:
    return {
        "floor": plan.index,
        "id": window.id,
        "wall": window.wall,
        "room": window.room,
        "position": list(window.position),
        "width": window.width,
        "height": window.height,
        "sill": window.sill,
    }


def _node_labels(nodes: Sequence[SceneNode]) -> dict[str, dict[str, Any]]:
    """Node path → its semantic labels (:mod:`cga.semantics`): class id and name, and
    instance id."""
    names = class_names()
    instances = instance_ids(nodes)
    out = {}
    for node in nodes:
        cid = node_class(node)
        out[node.path] = {"class_id": cid, "class": names[cid], "instance_id": instances[node.path]}
    return out


def _yaw_degrees(item: FurnitureItem) -> float:
    """The item's whole turn in degrees, in [0, 360): its quarter turns plus its free
    ``yaw`` (a disordered chair)."""
    turns = item.rotation % 4
    if not item.yaw:
        return 90.0 * turns
    degrees = math.degrees(item.heading) % 360.0
    return 0.0 if degrees >= 360.0 else degrees


def _furniture(plan: FloorPlan, item: FurnitureItem, labels: dict[str, dict[str, Any]],
               leaves: dict[str, SceneNode]) -> dict[str, Any]:
    turns = item.rotation % 4
    x, z = item.position
    y = plan.floor_y + item.elevation
    min_x, min_z, max_x, max_z = _footprint_bounds(item)
    path = f"floor{plan.index}/{plan.room(item.room).label}/furniture/{item.name}"
    bbox = {"min": [min_x, y, min_z], "max": [max_x, y + item.size[1], max_z]}
    if path in leaves:  # a door leaf stands where its hinge and angle put it
        bounds = np.asarray(leaves[path].mesh.bounds, dtype=float)
        bbox = {"min": bounds[0].tolist(), "max": bounds[1].tolist()}
    return {
        "floor": plan.index,
        "room": item.room,
        "name": item.name,
        "door": item.door,
        "model": item.model,
        "parent": item.parent,
        "pose": {"position": [x, y, z], "yaw_degrees": _yaw_degrees(item),
                 "quarter_turns": turns},
        "size": list(item.size),
        "front": list(item.front),
        "bbox": bbox,
        "is_detail": item.is_detail,
        "non_collision": item.non_collision,
        "node": path if path in labels else None,
        **labels.get(path, {"class_id": None, "class": None, "instance_id": None}),
    }


def _footprint_bounds(item: FurnitureItem) -> tuple[float, float, float, float]:
    """``item.footprint().bounds``, for an item on quarter turns without making the
    polygon: its half sizes, swapped on odd turns, about its position. The same floats,
    because shapely rotates quarter turns exactly (it rounds their cosine and sine to
    0 and ±1)."""
    if item.yaw:
        return item.footprint().bounds
    w, _, d = item.size
    half_x, half_z = (w / 2, d / 2) if item.rotation % 2 == 0 else (d / 2, w / 2)
    x, z = item.position
    return (x - half_x, z - half_z, x + half_x, z + half_z)


def _graph_edges(plan: FloorPlan) -> Iterable[dict[str, Any]]:
    if plan.room_graph is None:
        return []
    doors_by_pair: dict[frozenset[int], list[int]] = {}
    for door in plan.doors:
        doors_by_pair.setdefault(frozenset(door.rooms), []).append(door.id)
    edges = sorted(tuple(sorted((int(a), int(b)))) for a, b in plan.room_graph.edges)
    states = {door.id: door.state for door in plan.doors}
    out = []
    for a, b in edges:
        doors = sorted(doors_by_pair.get(frozenset((a, b)), []))
        out.append({"floor": plan.index, "rooms": [a, b], "outside": a == OUTSIDE or b == OUTSIDE,
                    "doors": doors, "door_states": [states[d] for d in doors],
                    "passable": any(states[d] == "open" for d in doors)})
    return out


def _stair_edge(stair: Stair) -> dict[str, Any]:
    return {"floor": stair.floors[0], "to_floor": stair.floors[1], "rooms": list(stair.rooms),
            "outside": False, "doors": [], "door_states": [], "passable": True, "stair": stair.id}


def _flight(flight: Flight) -> dict[str, Any]:
    return {"start": list(flight.start), "direction": list(flight.direction),
            "width": flight.width, "base_y": flight.base_y, "risers": flight.risers,
            "rise": flight.rise, "going": flight.going, "polygon": _polygon(flight.polygon())}


def _stair(stair: Stair, node_paths: set[str]) -> dict[str, Any]:
    path = f"floor{stair.floors[0]}/stair{stair.id}"
    return {
        "id": stair.id,
        "kind": stair.kind,
        "floors": list(stair.floors),
        "rooms": list(stair.rooms),
        "polygon": _polygon(stair.polygon),
        "landings": [_polygon(p) for p in stair.landings],
        "landing_points": [list(p) for p in stair.landing_points],
        "steps": stair.risers,
        "treads": stair.treads,
        "rise": stair.rise,
        "going": stair.going,
        "width": stair.width,
        "bottom_y": stair.bottom_y,
        "top_y": stair.top_y,
        "flights": [_flight(f) for f in stair.flights],
        "node": path if path in node_paths else None,
    }


def _node(node: SceneNode) -> dict[str, Any]:
    bounds = np.asarray(node.mesh.bounds, dtype=float)
    return {
        "path": node.path,
        "kind": node.kind,
        "static": node.static,
        "bbox": {"min": bounds[0].tolist(), "max": bounds[1].tolist()},
        "convex_parts": _convex_parts(node),
        "materials": [m.name for m in node_materials(node)[0]],
    }


def _convex_parts(node: SceneNode) -> int:
    """How many convex solids stand for the node in physics: its parts when they are
    convex, else the V-HACD pieces the physics check used (read from the disk cache the
    check filled; made and cached here when the build ran without checks)."""
    if node.item is None or node.convex_parts:
        return len(node.parts)
    from cga.collision import collision_parts

    return len(collision_parts(node))


def _materials(nodes: Sequence[SceneNode]) -> list[dict[str, Any]]:
    """Every material of the nodes, once each, sorted by name."""
    found = {m.name: m for node in nodes for m in node_materials(node)[0]}
    return [{"name": m.name, "row": m.row, "surface": m.surface, "color": list(m.color),
             "roughness": m.roughness, "metallic": m.metallic, "alpha": m.alpha}
            for _, m in sorted(found.items())]


def _light(light: Light) -> dict[str, Any]:
    return {"name": light.name, "floor": light.floor, "room": light.room,
            "position": list(light.position), "lumens": light.lumens,
            "intensity": light.intensity, "temperature": light.temperature,
            "color": list(light.color)}


def _polygon(geometry: Polygon | MultiPolygon) -> dict[str, Any]:
    """A polygon as counter-clockwise (in x–z) exterior and clockwise hole rings."""
    if isinstance(geometry, MultiPolygon):
        # a room's interior can fall apart where a wall pinches it; keep the largest piece
        geometry = max(geometry.geoms, key=lambda g: g.area)
    if geometry.is_empty:
        return {"exterior": [], "holes": []}
    shaped = orient(geometry, sign=1.0)
    return {
        "exterior": [list(c) for c in shaped.exterior.coords[:-1]],
        "holes": [[list(c) for c in ring.coords[:-1]] for ring in shaped.interiors],
    }


class _Unfit(Exception):
    """A value :func:`_clean` cannot turn into JSON; ``path`` gathers the keys and
    indices leading to it, innermost first, as the error travels out."""

    def __init__(self, problem: str):
        super().__init__(problem)
        self.problem = problem
        self.path: list[str] = []

    def where(self) -> str:
        return "".join(reversed(self.path)).removeprefix(".") or "value"


def _clean(document: Any) -> Any:
    """Convert to JSON-ready types, rounding floats to 1e-6 (``-0.0`` → ``0.0``).

    Raises
    ------
    ExportError
        A value is not finite or has no JSON form; the message names where it sits
        (``checks.physics.max_penetration``).
    """
    try:
        return _cleaned(document)
    except _Unfit as unfit:
        raise ExportError(f"scene JSON: {unfit.where()} {unfit.problem}") from None


def _cleaned(value: Any) -> Any:
    kind = type(value)
    if kind is float:  # the common cases first, by exact type
        if not math.isfinite(value):
            raise _Unfit(f"is {value}, which JSON cannot hold; the stage that produced it "
                         f"must report a finite number")
        return round(value, _DIGITS) + 0.0
    if kind is str or kind is int or kind is bool or value is None:
        return value
    if kind is dict:
        return _cleaned_dict(value)
    if kind is list or kind is tuple:
        return _cleaned_list(value)
    if isinstance(value, (bool, str)):
        return value
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return _cleaned(float(value))
    if isinstance(value, np.ndarray):
        return _cleaned_list(value.tolist())
    if isinstance(value, Path):
        return value.as_posix()
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return _cleaned_dict(dataclasses.asdict(value))
    if isinstance(value, Mapping):
        return _cleaned_dict(value)
    if isinstance(value, (list, tuple)):
        return _cleaned_list(value)
    raise _Unfit(f"has type {type(value).__name__}, which has no JSON form")


def _cleaned_dict(values: Mapping[Any, Any]) -> dict[str, Any]:
    out = {}
    for key, item in values.items():
        try:
            out[key if type(key) is str else str(key)] = _cleaned(item)
        except _Unfit as unfit:
            unfit.path.append(f".{key}")
            raise
    return out


def _cleaned_list(values: Sequence[Any]) -> list[Any]:
    out = []
    for index, item in enumerate(values):
        try:
            out.append(_cleaned(item))
        except _Unfit as unfit:
            unfit.path.append(f"[{index}]")
            raise
    return out
