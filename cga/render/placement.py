"""Where the cameras stand: seeded poses in the reachable free space of every room.

A robot's camera can only be where the robot can drive. Per floor this takes the
navigability check's occupancy grid (:func:`cga.checks.occupancy.occupancy_grid`: walls,
solid furniture and door leaves in the robot's height band), finds the largest piece of
the floor a robot that opens doors can drive through (cells at least the robot's radius
from any obstacle but the door leaves) and keeps its cells that are that far from the
door leaves too, where the build leaves them: the space a robot that entered the floor
can reach. A room's candidate cells are that space within the
room's interior; each camera stands at a cell drawn from them (its point drawn uniformly
in the cell), at eye height above the walking surface, level, turned into the open
(:func:`open_yaw`: a random direction among those with a long free run, not the wall
beside the camera).

Draws come from the build's random streams (:func:`cga.randomness.stream`) keyed by
floor and room, so the same seed gives the same poses and a room's poses do not
depend on the other rooms.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from scipy import ndimage

from cga.checks.occupancy import OccupancyGrid, occupancy_grid
from cga.export.rosmap import RESOLUTION
from cga.pipeline import MAX_ROBOT_RADIUS
from cga.randomness import stream

from .cameras import Camera, look_level, orthographic_down, perspective
from .inputs import FloorOutline, RenderInputs

__all__ = ["MAX_PIXELS", "MAX_VIEWS_PER_ROOM", "RenderOptions", "open_yaw", "floor_grid", "reachable_cells", "room_cameras", "top_camera",
           "cell_centres", "room_map"]


MAX_PIXELS = 16_000_000
"""Most pixels of one view (docs/limits.md)."""

MAX_VIEWS_PER_ROOM = 100
"""Most camera views per room (docs/limits.md)."""


@dataclass(frozen=True)
class RenderOptions:
    """How views are made (the ``cga render`` options; docs/render.md).

    ``views_per_room`` perspective cameras of ``width`` × ``height`` pixels and horizontal
    field of view ``fov`` degrees stand at ``eye_height`` m above the walking surface,
    level, at least ``robot_radius`` m from obstacles. The top-down view's pixels are
    ``map_resolution / top_oversample`` m, on the grid of the ROS map
    (``map_resolution``).
    """

    width: int = 640
    height: int = 480
    fov: float = 90.0
    eye_height: float = 1.0
    views_per_room: int = 1
    robot_radius: float = 0.25
    map_resolution: float = RESOLUTION
    top_oversample: int = 2

    def __post_init__(self) -> None:
        if self.width < 1 or self.height < 1 or self.width * self.height > MAX_PIXELS:
            raise ValueError(f"image size {self.width}x{self.height} must be positive and "
                             f"at most {MAX_PIXELS:,} pixels")
        if not 1.0 <= self.fov <= 179.0:
            raise ValueError(f"field of view {self.fov} must be between 1 and 179 degrees")
        if not self.eye_height > 0:
            raise ValueError(f"eye height {self.eye_height} must be positive")
        if not 0 <= self.views_per_room <= MAX_VIEWS_PER_ROOM:
            raise ValueError(f"views per room {self.views_per_room} must be between 0 and "
                             f"{MAX_VIEWS_PER_ROOM}")
        if not 0 < self.robot_radius <= MAX_ROBOT_RADIUS:
            raise ValueError(f"robot radius {self.robot_radius} must be more than 0 and at "
                             f"most {MAX_ROBOT_RADIUS} m")
        if not self.map_resolution > 0 or self.top_oversample < 1:
            raise ValueError("map resolution must be positive and the oversampling at least 1")


def floor_grid(floor: FloorOutline, inputs: RenderInputs, options: RenderOptions) -> OccupancyGrid:
    """The floor's occupancy grid, the ROS map's (:mod:`cga.export.rosmap`: the same
    margin, so with the default resolution the same origin, cells and size; door leaves
    where the build leaves them)."""
    return occupancy_grid(floor, inputs.nodes, resolution=options.map_resolution)


def _clear(blocked: np.ndarray, resolution: float, radius: float) -> np.ndarray:
    """Cells whose centre is at least ``radius`` from every blocked cell's edge."""
    if not blocked.any():
        return np.ones(blocked.shape, dtype=bool)
    return ndimage.distance_transform_edt(~blocked) * resolution - resolution / 2 >= radius


def reachable_cells(grid: OccupancyGrid, radius: float) -> np.ndarray:
    """``bool[rows, cols]``: cells inside the footprint at least ``radius`` from every
    obstacle (door leaves included, where they stand), in the largest piece of the floor
    a robot that opens doors can drive through."""
    outside = ~grid.free_mask
    doors_open = grid.occupied_by(o.path for o in grid.obstacles if o.door is None)
    drivable = _clear(doors_open | outside, grid.resolution, radius)
    labels, count = ndimage.label(drivable)
    if count == 0:
        return drivable
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    return (labels == int(np.argmax(sizes))) & _clear(grid.occupied | outside, grid.resolution,
                                                        radius)


def room_cameras(floor: FloorOutline, grid: OccupancyGrid, reachable: np.ndarray,
                 seed: int, options: RenderOptions) -> tuple[list[Camera], list[int]]:
    """The perspective cameras of every room of a floor, and the ids of the rooms that
    got none (no reachable free cell inside them)."""
    cameras: list[Camera] = []
    without: list[int] = []
    if options.views_per_room == 0:
        return cameras, without
    xs, zs = cell_centres(grid)
    for room in floor.rooms:
        cells = np.argwhere(reachable & shapely.contains_xy(room.interior, xs, zs))
        if len(cells) == 0:
            without.append(room.id)
            continue
        rng = stream(seed, ("render", f"floor{floor.index}", f"room{room.id}"))
        picks = rng.choice(len(cells), size=options.views_per_room,
                           replace=len(cells) < options.views_per_room)
        for k, pick in enumerate(picks):
            row, col = cells[pick]
            jitter = rng.uniform(-0.5, 0.5, size=2) * grid.resolution
            x, z = grid.cell_to_world(row, col)
            position = np.array([x + jitter[0], floor.floor_y + options.eye_height, z + jitter[1]])
            yaw = open_yaw(grid, position[0], position[2], rng)
            cameras.append(perspective(f"floor{floor.index}_room{room.id}_{k}", options.width,
                                       options.height, options.fov, look_level(position, yaw),
                                       floor=floor.index, room=room.id))
    return cameras, without


_YAW_CANDIDATES = 16
_REACH = 15.0
"""How far (m) :func:`open_yaw` looks along a direction."""


def open_yaw(grid: OccupancyGrid, x: float, z: float, rng: np.random.Generator) -> float:
    """A yaw (radians, as :func:`cga.render.cameras.look_level` takes it) that looks into
    the open: of :data:`_YAW_CANDIDATES` evenly spaced directions at a random offset, one
    drawn among those whose free run on the grid (to the first obstacle or the
    footprint's edge) is at least half the longest, so a camera does not stare at the
    wall beside it."""
    spacing = 2 * math.pi / _YAW_CANDIDATES
    yaws = rng.uniform(0.0, 2 * math.pi) + np.arange(_YAW_CANDIDATES) * spacing
    steps = np.arange(1, int(_REACH / (grid.resolution / 2)) + 1) * (grid.resolution / 2)
    # look_level's forward at yaw θ is (−sin θ, −cos θ) in plan (x, z)
    px = x - np.sin(yaws)[:, None] * steps
    pz = z - np.cos(yaws)[:, None] * steps
    rows = np.floor((pz - grid.z_min) / grid.resolution).astype(int)
    cols = np.floor((px - grid.x_min) / grid.resolution).astype(int)
    inside = (rows >= 0) & (rows < grid.shape[0]) & (cols >= 0) & (cols < grid.shape[1])
    rows, cols = np.clip(rows, 0, grid.shape[0] - 1), np.clip(cols, 0, grid.shape[1] - 1)
    stop = ~inside | grid.occupied[rows, cols] | ~grid.free_mask[rows, cols]
    first = np.where(stop.any(axis=1), stop.argmax(axis=1), len(steps))
    free = first * (grid.resolution / 2)
    open_enough = np.flatnonzero(free >= free.max() / 2)
    return float(yaws[open_enough[rng.integers(len(open_enough))]] % (2 * math.pi))


def top_camera(floor: FloorOutline, grid: OccupancyGrid, oversample: int, name: str) -> Camera:
    """The floor's orthographic view from above its walls, on the grid's cells split
    ``oversample`` times along each axis."""
    rows, cols = grid.shape
    pixel = grid.resolution / oversample
    return orthographic_down(name, grid.x_min, grid.z_min, cols * oversample, rows * oversample,
                             pixel, floor.top + 1.0, floor=floor.index)


def cell_centres(grid: OccupancyGrid) -> tuple[np.ndarray, np.ndarray]:
    """World ``(x, z)`` of every cell centre, ``float[rows, cols]`` each."""
    rows, cols = grid.shape
    xs = grid.x_min + (np.arange(cols)[None, :] + 0.5) * grid.resolution
    zs = grid.z_min + (np.arange(rows)[:, None] + 0.5) * grid.resolution
    return np.broadcast_to(xs, grid.shape), np.broadcast_to(zs, grid.shape)


def room_map(floor: FloorOutline, grid: OccupancyGrid, classes: Sequence[int]) -> np.ndarray:
    """``uint16[rows, cols]``: the class in ``classes`` (one per room, in room order) of the
    room whose interior holds each cell centre, 0 elsewhere."""
    xs, zs = cell_centres(grid)
    out = np.zeros(grid.shape, dtype=np.uint16)
    for room, cls in zip(floor.rooms, classes):
        out[shapely.contains_xy(room.interior, xs, zs)] = cls
    return out
