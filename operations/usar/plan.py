"""A generated grid map (:class:`.generator.GridLayout`) as a typed floor plan.

Every region (room, vertical hallway, hallway segment, open-area rectangle) becomes a
room of the plan (:func:`~cga.operations.floorplan.rectangles.plan_from_rectangles`),
so walls stand between regions and every way through is a door record in a shared
wall. The paper's doorways are holes in the wall (no door leaf), so every link is a
bare opening (``Door.leaf`` False, always open): a room doorway is ``doorWidth`` wide, a
hallway opening as wide as the wall between the two regions allows. The front door is
an ordinary door in the outer wall of the first vertical hallway.

Room types: a catalogue room takes its ``Furniture`` type (the furniture table's rows
furnish it), hallways :data:`HALLWAY_TYPE`, open areas :data:`OPEN_AREA_TYPE`.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from shapely.geometry import Point

from cga.model import DOOR_OPEN_ANGLE, OUTSIDE, Diagnostic, Door, FloorPlan, FloorSettings, Wall

from ..floorplan.rectangles import plan_from_rectangles
from ..roomtyping.doors import (clear_windows, door_opening, door_spans, free_intervals,
                                front_door_site, make_door)
from ..roomtyping.room_graph import room_graph
from .generator import GridLayout, Link

__all__ = ["HALLWAY_TYPE", "OPEN_AREA_TYPE", "plan_from_layout"]

HALLWAY_TYPE = "Hallway"
OPEN_AREA_TYPE = "OpenArea"

_STAGE = "usar_floor"


def plan_from_layout(layout: GridLayout, origin: tuple[float, float], cell: tuple[float, float],
                     settings: FloorSettings, rng: np.random.Generator, *, index: int = 0,
                     elevation: float = 0.0, height: float = 3.0) -> FloorPlan:
    """The floor of ``layout`` with its lower corner at ``origin`` and cells of
    ``cell = (along x, along z)`` metres.

    Returns
    -------
    FloorPlan
        Typed, with doors, room graph and entry (the first vertical hallway); a front
        door on the ground floor (``index`` 0).
    """
    x0, z0 = origin
    cx, cz = cell
    rects = [(x0 + r.rect[0] * cx, z0 + r.rect[1] * cz, x0 + r.rect[2] * cx, z0 + r.rect[3] * cz)
             for r in layout.regions]
    circulation = [r.number for r in layout.regions if r.kind != "room"]
    plan = plan_from_rectangles(rects, settings=settings, index=index, elevation=elevation,
                                height=height, circulation=circulation)
    types = {p.index: p.room.furniture for p in layout.rooms}
    kinds = {r.number: r.kind for r in layout.regions}
    rooms = tuple(replace(room, type=types.get(room.id) or (
        OPEN_AREA_TYPE if kinds[room.id] == "open" else HALLWAY_TYPE)) for room in plan.rooms)
    plan = plan.with_changes(rooms=rooms)
    walls = {w.id: w for w in plan.walls}
    spans = door_spans(plan)
    doors: list[Door] = []
    notes: list[Diagnostic] = []
    windows = plan.windows
    if index == 0:
        windows = _front_door(plan, layout.entry, walls, spans, windows, doors, rng)
    for link in layout.links:
        at = (x0 + link.at[0] * cx, z0 + link.at[1] * cz)
        wall = _wall_through(walls, {link.a, link.b}, at)
        if wall is not None and any(d.wall == wall.id for d in doors):
            continue  # both rooms drew a doorway into their shared wall: one hole
        door = None if wall is None else _link_door(plan, link, at, wall, spans, len(doors))
        if door is None:
            notes.append(Diagnostic("warning", _STAGE, (
                f"no room for a {link.kind} between rooms {link.a} and {link.b} at "
                f"({at[0]:.2f}, {at[1]:.2f})"), floor=index, room=link.a))
            continue
        walls[door.wall] = walls[door.wall].with_opening(door_opening(door, plan))
        doors.append(door)
    notes.append(_describe(layout, index))
    result = plan.with_changes(walls=tuple(walls[w.id] for w in plan.walls), windows=windows,
                               doors=tuple(doors), diagnostics=plan.diagnostics + tuple(notes))
    return result.with_changes(room_graph=room_graph(result, doors), entry=layout.entry)


def _front_door(plan: FloorPlan, entry: int, walls: dict[int, Wall],
                spans: dict[int, tuple[float, float]], windows: tuple, doors: list[Door],
                rng: np.random.Generator) -> tuple:
    """Put the front door into the entry hallway's longest outer wall; returns the
    windows left."""
    width = plan.settings.door_width
    candidates = sorted(((w, spans[w.id]) for w in walls.values()
                         if w.outer and entry in w.rooms and spans[w.id][1] - spans[w.id][0] >= width),
                        key=lambda c: -(c[1][1] - c[1][0]))
    if not candidates:
        return windows
    wall, centre, replaces = front_door_site(candidates, width, rng, "center")
    if replaces:
        walls[wall.id], windows, _ = clear_windows(walls[wall.id], windows,
                                                   centre - width / 2, centre + width / 2)
    door = make_door(len(doors), walls[wall.id], centre, (entry, OUTSIDE), plan, reason="front")
    walls[wall.id] = walls[wall.id].with_opening(door_opening(door, plan))
    doors.append(door)
    return windows


def _wall_through(walls: dict[int, Wall], pair: set[int], at: tuple[float, float]) -> Wall | None:
    """The wall between the two rooms of ``pair`` that passes through ``at``."""
    point = Point(at)
    return next((w for w in walls.values() if set(w.rooms) == pair
                 and w.segment().distance(point) < 1e-6), None)


def _link_door(plan: FloorPlan, link: Link, at: tuple[float, float], wall: Wall,
               spans: dict[int, tuple[float, float]], door_id: int) -> Door | None:
    """A bare opening for ``link`` in ``wall`` near ``at``; None when the wall has no
    free stretch for it."""
    along = math.dist(wall.start, at)
    free = free_intervals(wall, spans[wall.id])
    if not free:
        return None
    lo, hi = min(free, key=lambda iv: 0.0 if iv[0] <= along <= iv[1]
                 else min(abs(iv[0] - along), abs(iv[1] - along)))
    width = hi - lo if link.kind == "opening" else plan.settings.door_width
    if hi - lo < width or width <= 0:
        return None
    centre = min(max(along, lo + width / 2), hi - width / 2)
    door = make_door(door_id, wall, centre, (link.a, link.b), plan,
                     reason="reachability" if link.kind == "repair" else "rule")
    return replace(door, width=width, state="open", angle=DOOR_OPEN_ANGLE, leaf=False)


def _describe(layout: GridLayout, index: int) -> Diagnostic:
    """One line on what the generator drew, for the summary."""
    draws = len(layout.doorways)
    opened = sum(d.opened for d in layout.doorways)
    repairs = sum(k.kind == "repair" for k in layout.links)
    mean = (sum(p.room.difficulty for p in layout.rooms) / len(layout.rooms)
            if layout.rooms else 0.0)
    return Diagnostic("info", _STAGE, (
        f"UvA grid {layout.columns} x {layout.rows} cells at difficulty {layout.difficulty:g}: "
        f"hallway spacing {layout.spacing[0]} x {layout.spacing[1]}, {len(layout.rooms)} rooms "
        f"(mean annotated difficulty {mean:.2f}), {opened}/{draws} doorways drawn open, "
        f"{repairs} added for reachability, cycle prevention "
        f"{'fired' if layout.cycle_prevention else 'not fired'}"
        f"{f' ({len(layout.removed)} hallway cells removed)' if layout.removed else ''}"),
        floor=index)
