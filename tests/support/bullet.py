"""A pybullet DIRECT client with gravity along ROS −z, for tests that load robot files."""

from __future__ import annotations

from collections.abc import Iterator

import pybullet
import pytest
from pybullet_utils.bullet_client import BulletClient


@pytest.fixture()
def client() -> Iterator[BulletClient]:
    """A fresh physics server per test, disconnected afterwards."""
    bullet = BulletClient(connection_mode=pybullet.DIRECT)
    bullet.setGravity(0, 0, -9.81)
    yield bullet
    bullet.disconnect()
