"""Independent checks of a ROS occupancy map against the scene JSON.

Reads the map the way map_server does (YAML fields, PGM pixels, origin at the lower-left
pixel corner) and the walls, doors, furniture and rooms from ``<name>.scene.json``, and
converts world plan points to map points by the rule of docs/architecture.md ("Units and
frames") written out here, ``(x, y)_map = (x, −z)_world``, so nothing of the exporter's
code is reused.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
from PIL import Image
from shapely.geometry import Point, Polygon

OCCUPIED, FREE, UNKNOWN = 0, 254, 205


class RosMap:
    """A map read back from its YAML and PGM."""

    def __init__(self, yaml_path: Path):
        self.fields = dict(re.findall(r"^(\w+):\s*(.+)$", Path(yaml_path).read_text(),
                                      re.MULTILINE))
        self.resolution = float(self.fields["resolution"])
        self.origin = [float(v) for v in self.fields["origin"].strip("[]").split(",")]
        self.pixels = np.asarray(Image.open(Path(yaml_path).parent / self.fields["image"]))

    def at_world(self, x: float, z: float) -> int:
        """Pixel value at world plan point (x, z), i.e. map point (x, −z)."""
        x_map, y_map = x, -z
        col = math.floor((x_map - self.origin[0]) / self.resolution)
        row = self.pixels.shape[0] - 1 - math.floor((y_map - self.origin[1]) / self.resolution)
        return int(self.pixels[row, col])


def _wall_line(wall: dict, footprint: Polygon) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(start, unit direction, offset to the middle of the wall's solid): inner walls are
    centred on their segment, outer walls lie inside the footprint."""
    start, end = np.array(wall["start"]), np.array(wall["end"])
    u = (end - start) / wall["length"]
    normal = np.array([-u[1], u[0]])
    offset = np.zeros(2)
    if wall["outer"]:
        middle = (start + end) / 2
        inward = normal if footprint.contains(Point(*(middle + normal * 0.05))) else -normal
        offset = inward * wall["thickness"] / 2
    return start, u, offset


def _wall_samples(wall: dict, footprint: Polygon):
    """Points on the middle of a wall's solid, away from its ends and door gaps."""
    start, u, offset = _wall_line(wall, footprint)
    gaps = [(o["center"] - o["width"] / 2 - 0.1, o["center"] + o["width"] / 2 + 0.1)
            for o in wall["openings"] if o["sill"] < 0.05]
    for s in np.arange(wall["thickness"], wall["length"] - wall["thickness"], 0.1):
        if not any(a <= s <= b for a, b in gaps):
            yield start + u * s + offset


def _grid(area: Polygon, step: float = 0.25):
    """Points every ``step`` metres inside ``area``."""
    if area.is_empty:
        return
    min_x, min_z, max_x, max_z = area.bounds
    for x in np.arange(min_x, max_x, step):
        for z in np.arange(min_z, max_z, step):
            if area.contains(Point(x, z)):
                yield x, z


def check_map_against_scene(ros_map: RosMap, doc: dict, floor: int, *,
                            band: tuple[float, float] = (0.05, 1.2)) -> dict[str, int]:
    """Assert walls, solid furniture and stairs (flights, half landings, stairwells) are
    occupied, open doors' centres, open floor and stair landings free, closed doors shut,
    the outside unknown. Returns how many points of each kind were checked."""
    level = next(f for f in doc["floors"] if f["index"] == floor)
    footprint = Polygon(level["footprint"]["exterior"])
    counts = {"wall": 0, "door": 0, "furniture": 0, "free": 0, "outside": 0, "stair": 0}
    stairs = [s for s in doc.get("stairs", []) if floor in s["floors"]]
    wells = [Polygon(s["polygon"]["exterior"]) for s in stairs]
    for well in wells:
        for x, z in _grid(well.buffer(-0.1)):
            assert ros_map.at_world(x, z) == OCCUPIED, ("stair", floor, x, z)
            counts["stair"] += 1
    for wall in (w for w in doc["walls"] if w["floor"] == floor):
        for x, z in _wall_samples(wall, footprint):
            assert ros_map.at_world(x, z) == OCCUPIED, ("wall", floor, wall["id"], x, z)
            counts["wall"] += 1
    walls = {w["id"]: w for w in doc["walls"] if w["floor"] == floor}
    for door in (d for d in doc["doors"] if d["floor"] == floor):
        wall = walls[door["wall"]]
        _, u, offset = _wall_line(wall, footprint)
        centre = np.array(door["position"]) + offset
        if door["state"] == "open":  # the doorway is free
            assert ros_map.at_world(*centre) == FREE, ("door", floor, door["id"])
        else:  # a closed leaf shuts the doorway somewhere across the wall's thickness
            normal = np.array([-u[1], u[0]])
            across = [ros_map.at_world(*(centre + normal * s))
                      for s in np.linspace(-wall["thickness"] / 2, wall["thickness"] / 2, 9)]
            if door["state"] == "closed":
                assert OCCUPIED in across, ("closed door", floor, door["id"])
        counts["door"] += 1
    furniture = [f for f in doc["furniture"] if f["floor"] == floor]
    lo, hi = level["floor_y"] + band[0], level["floor_y"] + band[1]
    for item in furniture:
        (x0, y0, z0), (x1, y1, z1) = item["bbox"]["min"], item["bbox"]["max"]
        if item["is_detail"] or item["non_collision"] or y1 <= lo or y0 >= hi:
            continue
        assert ros_map.at_world((x0 + x1) / 2, (z0 + z1) / 2) == OCCUPIED, ("item", item["name"])
        if (x1 - x0) * (z1 - z0) >= 0.25:  # small items (lamps, plants) may be a thin stem
            inside = [ros_map.at_world(x, z) for x in np.arange(x0 + 0.03, x1, 0.05)
                      for z in np.arange(z0 + 0.03, z1, 0.05)]
            assert np.mean(np.equal(inside, OCCUPIED)) >= 0.6, ("item cover", item["name"])
        counts["furniture"] += 1
    boxes = [Polygon.from_bounds(f["bbox"]["min"][0], f["bbox"]["min"][2], f["bbox"]["max"][0],
                                 f["bbox"]["max"][2]).buffer(0.1) for f in furniture]
    boxes += [well.buffer(0.1) for well in wells]  # stairs are obstacles, checked above
    for room in (r for r in doc["rooms"] if r["floor"] == floor):
        interior = Polygon(room["interior"]["exterior"]).buffer(-0.1)
        if interior.is_empty:
            continue
        min_x, min_z, max_x, max_z = interior.bounds
        for x in np.arange(min_x, max_x, 0.25):
            for z in np.arange(min_z, max_z, 0.25):
                point = Point(x, z)
                if interior.contains(point) and not any(b.contains(point) for b in boxes):
                    assert ros_map.at_world(x, z) == FREE, ("free", floor, room["id"], x, z)
                    counts["free"] += 1
    min_x, min_z, max_x, max_z = footprint.bounds
    for x, z in [(min_x - 0.3, (min_z + max_z) / 2), ((min_x + max_x) / 2, max_z + 0.3)]:
        if not footprint.buffer(0.05).contains(Point(x, z)):
            assert ros_map.at_world(x, z) == UNKNOWN, ("outside", x, z)
            counts["outside"] += 1
    return counts
