"""ROS occupancy maps, ``<name>.floor{N}.pgm`` + ``.yaml`` (``map_server`` format).

One map per floor, drawn from the same occupancy grid the navigability check uses
(:func:`cga.checks.occupancy.occupancy_grid`: walls and solid furniture in the robot's
height band above the floor, 0.05 m cells), so what the check passed is what a robot
gets. Pixels: occupied 0 (black), free 254, unknown 205 outside the building's
footprint. With ``negate: 0`` map_server reads a pixel as occupancy (255 − v) / 255, so
0 → 1.0 (> occupied_thresh 0.65), 254 → 0.004 (< free_thresh 0.196) and 205 → 0.196
(neither: unknown).

The map frame is the ROS frame of the SDF world and the URDFs (:mod:`cga.export.frames`):
``origin`` is the ROS ``(x, y)`` of the lower-left pixel's corner, yaw 0, so a map
coordinate is a world ``(x, −z)``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from cga.checks.occupancy import OccupancyGrid, occupancy_grid
from cga.fsutil import atomic_write
from cga.model import FloorPlan
from cga.scene import Scene, SceneNode

from .bodies import numbers_text

__all__ = ["OCCUPIED", "FREE", "UNKNOWN", "RESOLUTION", "map_pixels", "pgm_bytes",
           "map_yaml", "export_rosmap"]

OCCUPIED, FREE, UNKNOWN = 0, 254, 205
"""Pixel values of the PGM."""

RESOLUTION = 0.05
"""Cell size in metres."""


def map_pixels(grid: OccupancyGrid) -> np.ndarray:
    """``uint8[rows, cols]`` image of a grid: row 0 is the top (largest ROS ``y``)."""
    pixels = np.full(grid.shape, UNKNOWN, dtype=np.uint8)
    pixels[grid.free_mask] = FREE
    pixels[grid.occupied] = OCCUPIED
    return pixels


def pgm_bytes(pixels: np.ndarray) -> bytes:
    """A binary (P5) 8-bit PGM of ``pixels``."""
    rows, cols = pixels.shape
    return f"P5\n{cols} {rows}\n255\n".encode("ascii") + np.ascontiguousarray(
        pixels, dtype=np.uint8).tobytes()


def map_yaml(image: str, grid: OccupancyGrid, plan: FloorPlan) -> str:
    """The map_server YAML of a floor's map."""
    band_lo, band_hi = (h - plan.floor_y for h in grid.band)
    return (
        f"# cga occupancy map, floor {plan.index}: walking surface at z = "
        f"{plan.floor_y:.3f} m (ROS frame), obstacles between {band_lo:.2f} m and "
        f"{band_hi:.2f} m above it\n"
        f"image: {image}\n"
        f"mode: trinary\n"
        f"resolution: {numbers_text([grid.resolution])}\n"
        f"origin: [{numbers_text(grid.origin).replace(' ', ', ')}, 0.0]\n"
        f"negate: 0\n"
        f"occupied_thresh: 0.65\n"
        f"free_thresh: 0.196\n"
    )


def export_rosmap(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path,
                  name: str) -> list[Path]:
    """Write ``<name>.floor{N}.pgm`` and ``<name>.floor{N}.yaml`` for every floor."""
    out = Path(out_dir)
    written = []
    for plan in scene.floors:
        grid = occupancy_grid(plan, nodes, resolution=RESOLUTION)
        stem = f"{name}.floor{plan.index}"
        written.append(atomic_write(out / f"{stem}.pgm", pgm_bytes(map_pixels(grid))))
        written.append(atomic_write(out / f"{stem}.yaml", map_yaml(f"{stem}.pgm", grid, plan)))
    return written
