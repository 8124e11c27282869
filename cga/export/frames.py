"""The one place where world coordinates become robot (ROS) coordinates.

cga's world frame (docs/architecture.md, "Units and frames") is y-up with floor plans in
the x–z plane, like glTF and OBJ. Robot formats (URDF, SDF, ROS occupancy maps) use the ROS
convention of REP 103: z up, x forward, right-handed. The change of frame is the rotation
by +90° about x::

    (x, y, z)_ros = (x, −z, y)_world

It is a proper rotation (determinant +1), so handedness and mesh winding survive it. A
rotation about world +y by an angle maps to a rotation about ROS +z by the same angle,
so a furniture item's quarter turns become its yaw unchanged.

Every exporter that writes robot coordinates converts through this module; the
conversion is tested once, with an object at a known position, in pybullet and in the
occupancy map.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "WORLD_TO_ROS",
    "RosPose",
    "world_to_ros",
    "ros_to_world",
    "plan_to_ros",
    "pose_to_ros",
    "yaw_quaternion",
]

WORLD_TO_ROS = np.array([[1.0, 0.0, 0.0],
                         [0.0, 0.0, -1.0],
                         [0.0, 1.0, 0.0]])
"""Rotation matrix taking world (y-up) vectors to ROS (z-up) vectors."""


@dataclass(frozen=True)
class RosPose:
    """A pose in the ROS frame: ``position`` (x, y, z) in metres and ``yaw`` in radians
    about +z (roll and pitch are always 0 for cga's bodies)."""

    position: tuple[float, float, float]
    yaw: float

    @property
    def quaternion_xyzw(self) -> tuple[float, float, float, float]:
        """The orientation as a unit quaternion (x, y, z, w), pybullet's order."""
        return yaw_quaternion(self.yaw)

    @property
    def rpy(self) -> tuple[float, float, float]:
        """Roll, pitch, yaw in radians (URDF ``origin rpy`` / SDF ``pose`` order)."""
        return (0.0, 0.0, self.yaw)


def world_to_ros(points: ArrayLike) -> np.ndarray:
    """Convert points or vectors from the world frame (y up) to the ROS frame (z up).

    Parameters
    ----------
    points:
        One point ``(3,)`` or an array ``(..., 3)`` in world coordinates (metres).

    Returns
    -------
    numpy.ndarray
        The same shape, ``(x, −z, y)`` for every input ``(x, y, z)``.

    Raises
    ------
    ValueError
        If the last axis does not have length 3.
    """
    arr = np.asarray(points, dtype=float)
    if arr.shape[-1:] != (3,):
        raise ValueError(f"expected points with 3 coordinates, got shape {arr.shape}")
    return arr @ WORLD_TO_ROS.T


def ros_to_world(points: ArrayLike) -> np.ndarray:
    """The inverse of :func:`world_to_ros`: ``(x, y, z)_ros`` → ``(x, z, −y)_world``."""
    arr = np.asarray(points, dtype=float)
    if arr.shape[-1:] != (3,):
        raise ValueError(f"expected points with 3 coordinates, got shape {arr.shape}")
    return arr @ WORLD_TO_ROS


def plan_to_ros(x: float, z: float) -> tuple[float, float]:
    """A plan point ``(x, z)`` as ROS map coordinates ``(x, −z)``."""
    return (float(x), float(-z))


def pose_to_ros(position: ArrayLike, yaw_degrees: float = 0.0) -> RosPose:
    """Convert a world pose (position, rotation about world +y) to a ROS pose.

    Parameters
    ----------
    position:
        World position ``(x, y, z)`` in metres.
    yaw_degrees:
        Right-handed rotation about world +y in degrees (a furniture item's quarter
        turns × 90).

    Returns
    -------
    RosPose
        Position ``(x, −z, y)`` and the same angle as yaw about ROS +z, in radians.
    """
    x, y, z = (float(v) for v in world_to_ros(position))
    return RosPose(position=(x, y, z), yaw=math.radians(yaw_degrees))


def yaw_quaternion(yaw: float) -> tuple[float, float, float, float]:
    """The unit quaternion (x, y, z, w) of a rotation by ``yaw`` radians about +z."""
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))
