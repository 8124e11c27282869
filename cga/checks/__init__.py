"""Checks a built scene must pass to be a valid world for a robot simulator (docs/checks.md).

* :func:`check_physics`: furniture at rest, nothing interpenetrating (pybullet).
* :func:`check_navigability`: every room reachable from the front door by a round robot
  (occupancy grid per floor, :func:`occupancy_grid`, also used for ROS maps).

Both take a :class:`cga.scene.Scene` and check its nodes (``scene.nodes``, meshed once
per scene) or the nodes passed to them. Their reports have ``passed``
and ``to_dict()`` for the scene file's ``checks`` section. See ``docs/checks.md``.

The names below are imported from their modules on first use (PEP 562), so importing
one check (``cga.checks.occupancy`` for a ROS map) does not load the others' libraries
(pybullet, SciPy).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # pragma: no cover
    from .navigability import (Bottleneck, FloorReach, NavigabilityReport, RoomReach,
                               check_floor_navigability, check_navigability)
    from .occupancy import Obstacle, OccupancyGrid, band_footprint, occupancy_grid
    from .physics import ItemPhysics, PhysicsReport, check_physics

_MODULES = {
    **dict.fromkeys(["Bottleneck", "FloorReach", "NavigabilityReport", "RoomReach",
                     "check_floor_navigability", "check_navigability"], "navigability"),
    **dict.fromkeys(["Obstacle", "OccupancyGrid", "band_footprint", "occupancy_grid"],
                    "occupancy"),
    **dict.fromkeys(["ItemPhysics", "PhysicsReport", "check_physics"], "physics"),
}
"""Public name → the submodule defining it."""

__all__ = [
    "Bottleneck",
    "FloorReach",
    "ItemPhysics",
    "NavigabilityReport",
    "Obstacle",
    "OccupancyGrid",
    "PhysicsReport",
    "RoomReach",
    "band_footprint",
    "check_floor_navigability",
    "check_navigability",
    "check_physics",
    "occupancy_grid",
]


def __getattr__(name: str) -> object:
    """Import a public name from its submodule the first time it is used (PEP 562)."""
    module = _MODULES.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{module}"), name)
