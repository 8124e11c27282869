"""Cameras: intrinsics, extrinsics, the ray of every pixel, and the camera JSON.

Conventions (docs/render.md). The world is the scene's: metres, y up (the scene JSON and
the glb). A camera's pose is stored in the **OpenCV** convention, camera axes x right,
y down, z forward, as ``camera_to_world`` (4×4, maps camera coordinates to world
coordinates). Pixel ``(u, v)`` is column ``u``, row ``v``, its centre at integer
coordinates (OpenCV): a perspective camera sees the camera point ``(X, Y, Z)`` at
``u = fx·X/Z + cx``, ``v = fy·Y/Z + cy``; an orthographic one at ``u = fx·X + cx``,
``v = fy·Y + cy`` (``fx = fy`` = pixels per metre). Depth is ``Z``, the distance along
the optical axis (not along the ray), in both cases.

The **glTF** camera is the same pose with y up and z backwards (the camera looks along
its −z): ``camera_to_world_gltf = camera_to_world · diag(1, −1, −1, 1)``, which is the
matrix of a glTF camera node placed in the scene's root frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["Camera", "perspective", "orthographic_down", "look_level", "OPENCV_TO_GLTF"]

OPENCV_TO_GLTF = np.diag([1.0, -1.0, -1.0, 1.0])
"""Right-multiplied with an OpenCV ``camera_to_world`` gives the glTF camera's matrix."""


@dataclass(frozen=True)
class Camera:
    """A pinhole (or orthographic) camera with its image size and pose (module notes).

    ``name`` names the view's files; ``floor`` and ``room`` say where it stands (``room``
    is None for a floor's top-down view).
    """

    name: str
    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float
    camera_to_world: np.ndarray = field(repr=False)
    orthographic: bool = False
    floor: int = 0
    room: int | None = None

    @property
    def K(self) -> np.ndarray:
        """The 3×3 intrinsic matrix."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    @property
    def position(self) -> np.ndarray:
        return self.camera_to_world[:3, 3].copy()

    @property
    def forward(self) -> np.ndarray:
        """The optical axis in the world (camera +z)."""
        return self.camera_to_world[:3, 2].copy()

    def rays(self) -> tuple[np.ndarray, np.ndarray]:
        """World ``(origins, directions)`` of every pixel centre, row by row (``v`` major).

        ``origins`` is ``float[n, 3]``, or ``float[1, 3]`` for a perspective camera, whose
        rays all start at its centre. Directions are scaled so that their component along
        the optical axis is 1: a hit at ray parameter ``t`` has depth ``t``.
        """
        u = (np.arange(self.width, dtype=np.float64) - self.cx) / self.fx
        v = (np.arange(self.height, dtype=np.float64) - self.cy) / self.fy
        rotation = self.camera_to_world[:3, :3]
        across = u[None, :, None] * rotation[:, 0] + v[:, None, None] * rotation[:, 1]
        centre = self.camera_to_world[:3, 3]
        if self.orthographic:
            origins = (across + centre).reshape(-1, 3)
            directions = np.broadcast_to(rotation[:, 2], origins.shape).copy()
            return origins, directions
        return centre[None, :].copy(), (across + rotation[:, 2]).reshape(-1, 3)

    def to_dict(self, near: float, far: float) -> dict[str, Any]:
        """The camera JSON (docs/render.md): intrinsics, OpenCV and glTF extrinsics.

        ``near`` and ``far`` bound the depths the view can hold (glTF ``znear``/``zfar``).
        """
        to_world = self.camera_to_world
        gltf: dict[str, Any]
        if self.orthographic:
            gltf = {"type": "orthographic",
                    "orthographic": {"xmag": self.width / self.fx / 2, "ymag": self.height / self.fy / 2,
                                     "znear": near, "zfar": far}}
        else:
            gltf = {"type": "perspective",
                    "perspective": {"yfov": 2 * math.atan(self.height / 2 / self.fy),
                                    "aspectRatio": self.width / self.height,
                                    "znear": near, "zfar": far}}
        gltf["camera_to_world"] = (to_world @ OPENCV_TO_GLTF).tolist()
        return {
            "name": self.name,
            "projection": "orthographic" if self.orthographic else "perspective",
            "floor": self.floor,
            "room": self.room,
            "width": self.width,
            "height": self.height,
            "intrinsics": {"fx": self.fx, "fy": self.fy, "cx": self.cx, "cy": self.cy,
                           "K": self.K.tolist()},
            "opencv": {"camera_to_world": to_world.tolist(),
                       "world_to_camera": np.linalg.inv(to_world).tolist()},
            "gltf": gltf,
            "world_frame": {"length_unit": "m", "up": "+y"},
        }


def look_level(position: np.ndarray, yaw: float, pitch: float = 0.0) -> np.ndarray:
    """OpenCV ``camera_to_world`` of a camera at ``position`` turned ``yaw`` radians about
    +y from looking along −z (the furniture front convention), tilted ``pitch`` radians
    up."""
    forward = np.array([-math.sin(yaw) * math.cos(pitch), math.sin(pitch),
                        -math.cos(yaw) * math.cos(pitch)])
    right = np.array([math.cos(yaw), 0.0, -math.sin(yaw)])
    down = np.cross(forward, right)
    matrix = np.eye(4)
    matrix[:3, :3] = np.column_stack([right, down, forward])
    matrix[:3, 3] = position
    return matrix


def perspective(name: str, width: int, height: int, hfov_degrees: float,
                camera_to_world: np.ndarray, *, floor: int, room: int | None) -> Camera:
    """A perspective camera with square pixels and the principal point at the image
    centre, whose horizontal field of view is ``hfov_degrees``.

    Raises
    ------
    ValueError
        A size is not positive or the field of view is not in (0, 180) degrees.
    """
    if width < 1 or height < 1:
        raise ValueError(f"image size {width}x{height} must be positive")
    if not 0 < hfov_degrees < 180:
        raise ValueError(f"field of view {hfov_degrees} must be between 0 and 180 degrees")
    f = (width / 2) / math.tan(math.radians(hfov_degrees) / 2)
    return Camera(name, width, height, f, f, (width - 1) / 2, (height - 1) / 2,
                  camera_to_world, floor=floor, room=room)


def orthographic_down(name: str, x_min: float, z_min: float, cols: int, rows: int,
                      pixel: float, y: float, *, floor: int) -> Camera:
    """An orthographic camera at height ``y`` looking straight down at the plan area
    ``[x_min, x_min + cols·pixel] × [z_min, z_min + rows·pixel]``: column ``u`` runs along
    world +x, row ``v`` along +z, so the image lies like a ROS map of the same area
    (row 0 at the smallest z, the map's top)."""
    matrix = np.eye(4)
    # camera x = world +x, y = world +z, z (forward) = world −y: a proper rotation
    matrix[:3, :3] = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
    matrix[:3, 3] = (x_min + cols * pixel / 2, y, z_min + rows * pixel / 2)
    scale = 1.0 / pixel
    return Camera(name, cols, rows, scale, scale, (cols - 1) / 2, (rows - 1) / 2, matrix,
                  orthographic=True, floor=floor, room=None)
