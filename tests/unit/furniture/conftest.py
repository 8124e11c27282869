"""Fixtures for the furniture tests: hand-built one-room floors and the shipped models.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from shapely.geometry import box

from cga.model import OUTSIDE, Door, FloorPlan, FloorSettings, Room, Wall, Window
from cga.operations.furniture.library import ModelLibrary, default_library


RULES_DIR = Path(__file__).resolve().parents[3] / "rules"


def build_room(width: float = 5.0, depth: float = 4.0, *, thickness: float = 0.2,
               room_type: str | None = "Livingroom", doors: tuple = ((0, 0.3, "start"),),
               windows: tuple = ((2, 0.5),)) -> FloorPlan:
    """A one-room floor ``width`` × ``depth`` m (outer walls inside the footprint).

    Walls run counter-clockwise from (0, 0): 0 along z = 0, 1 along x = width, 2 along
    z = depth, 3 along x = 0. ``doors`` are ``(wall, fraction along it, hinge)`` front
    doors swinging in; ``windows`` are ``(wall, fraction along it)``, 1.2 m wide.
    """
    corners = [(0.0, 0.0), (width, 0.0), (width, depth), (0.0, depth)]
    walls = tuple(Wall(i, corners[i], corners[(i + 1) % 4], True, (0, OUTSIDE), thickness)
                  for i in range(4))
    room = Room(0, box(0, 0, width, depth),
                box(thickness, thickness, width - thickness, depth - thickness), room_type)
    door_records = tuple(
        Door(k, wall, (0, OUTSIDE), walls[wall].point_at(walls[wall].length * at), 0.9, 2.1, 0,
             hinge, k == 0, "front")
        for k, (wall, at, hinge) in enumerate(doors))
    window_records = tuple(
        Window(k, wall, 0, walls[wall].point_at(walls[wall].length * at), 1.2, 1.2, 0.9)
        for k, (wall, at) in enumerate(windows))
    return FloorPlan(0, 0.0, 3.0, box(0, 0, width, depth), FloorSettings(wall_thickness=thickness),
                     (room,), walls, doors=door_records, windows=window_records)


@pytest.fixture
def room_plan():
    """Factory of one-room floors (see :func:`build_room`)."""
    return build_room


@pytest.fixture(scope="session")
def library() -> ModelLibrary:
    """The shipped models (loaded once per test session)."""
    return default_library()


@pytest.fixture(scope="session")
def rules_dir() -> Path:
    """The shipped rule tables."""
    return RULES_DIR
