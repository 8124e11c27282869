"""World (y up) ↔ ROS (z up) conversion: values, inverse, handedness, poses."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cga.export.frames import (WORLD_TO_ROS, plan_to_ros, pose_to_ros, ros_to_world,
                               world_to_ros, yaw_quaternion)
from cga.model import rotation_matrix


def test_axes_map_as_rep_103_says():
    # world +x stays +x, world up (+y) becomes ROS up (+z), world +z becomes ROS −y
    assert world_to_ros([1, 0, 0]).tolist() == [1, 0, 0]
    assert world_to_ros([0, 1, 0]).tolist() == [0, 0, 1]
    assert world_to_ros([0, 0, 1]).tolist() == [0, -1, 0]
    assert world_to_ros([2.0, 3.2, 3.0]).tolist() == [2.0, -3.0, 3.2]


def test_conversion_is_a_proper_rotation():
    assert np.allclose(WORLD_TO_ROS @ WORLD_TO_ROS.T, np.eye(3))
    assert np.linalg.det(WORLD_TO_ROS) == pytest.approx(1.0)


def test_inverse_and_batches():
    points = np.random.default_rng(3).normal(size=(5, 4, 3))
    converted = world_to_ros(points)
    assert converted.shape == points.shape
    assert np.allclose(ros_to_world(converted), points)


def test_bad_shape_is_refused():
    with pytest.raises(ValueError, match="3 coordinates"):
        world_to_ros([1.0, 2.0])


def test_plan_points_become_map_points():
    assert plan_to_ros(2.0, 3.0) == (2.0, -3.0)


@pytest.mark.parametrize("turns", [0, 1, 2, 3])
def test_quarter_turns_become_the_same_yaw(turns):
    pose = pose_to_ros([1.0, 0.0, 2.0], 90.0 * turns)
    assert pose.yaw == pytest.approx(math.radians(90 * turns))
    # the item's front (world −z at rotation 0) turned in the world frame, then
    # converted, equals the ROS front (world −z → ROS +y) turned by the ROS yaw
    front_world = rotation_matrix(turns) @ np.array([0.0, 0.0, -1.0])
    c, s = math.cos(pose.yaw), math.sin(pose.yaw)
    front_ros = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ np.array([0.0, 1.0, 0.0])
    assert np.allclose(world_to_ros(front_world), front_ros)


def test_yaw_quaternion_is_unit_and_about_z():
    x, y, z, w = yaw_quaternion(math.pi / 2)
    assert (x, y) == (0.0, 0.0)
    assert math.hypot(z, w) == pytest.approx(1.0)
    assert 2 * math.atan2(z, w) == pytest.approx(math.pi / 2)
    assert pose_to_ros([0, 0, 0], 180).quaternion_xyzw == pytest.approx((0, 0, 1, 0), abs=1e-12)
