"""Checks a built scene must pass to be a valid world for a robot simulator (docs/checks.md).

* :func:`check_physics`: furniture at rest, nothing interpenetrating (pybullet).
* :func:`check_navigability`: every room reachable from the front door by a round robot
  (occupancy grid per floor, :func:`occupancy_grid`, also used for ROS maps).

Both take a :class:`cga.scene.Scene` and check its nodes (``scene.nodes``, meshed once
per scene) or the nodes passed to them. Their reports have ``passed``
and ``to_dict()`` for the scene file's ``checks`` section. See ``docs/checks.md``.
"""

from __future__ import annotations

from .navigability import (Bottleneck, FloorReach, NavigabilityReport, RoomReach,
                           check_floor_navigability, check_navigability)
from .occupancy import Obstacle, OccupancyGrid, band_footprint, occupancy_grid
from .physics import ItemPhysics, PhysicsReport, check_physics

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
