"""ROS maps: map_server format, and occupied cells where the scene JSON puts walls and
furniture (checked from the JSON data and the map files alone)."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from PIL import Image
from shapely.geometry import Point, Polygon

from cga.export.rosmap import export_rosmap
from cga.export.scene_json import export_scene_json


@pytest.fixture(scope="module")
def exported(small_scene, tmp_path_factory):
    scene, nodes = small_scene
    out = tmp_path_factory.mktemp("maps")
    export_rosmap(scene, nodes, out, "house")
    export_scene_json(scene, nodes, out, "house")
    return out, json.loads((out / "house.scene.json").read_text())


class RosMap:
    """A map read back from its YAML and PGM the way map_server reads them."""

    def __init__(self, yaml_path):
        fields = dict(re.findall(r"^(\w+):\s*(.+)$", yaml_path.read_text(), re.MULTILINE))
        self.fields = fields
        self.resolution = float(fields["resolution"])
        self.origin = [float(v) for v in fields["origin"].strip("[]").split(",")]
        self.pixels = np.asarray(Image.open(yaml_path.parent / fields["image"]))

    def at_world(self, x, z):
        """Pixel value at world plan point (x, z), i.e. ROS (x, −z)."""
        x_ros, y_ros = x, -z
        col = math.floor((x_ros - self.origin[0]) / self.resolution)
        row = self.pixels.shape[0] - 1 - math.floor((y_ros - self.origin[1]) / self.resolution)
        return int(self.pixels[row, col])


def _map(out, floor):
    return RosMap(out / f"house.floor{floor}.yaml")


def test_map_server_fields(exported):
    out, _ = exported
    for floor in (0, 1):
        ros_map = _map(out, floor)
        assert ros_map.fields["image"] == f"house.floor{floor}.pgm"
        assert ros_map.resolution == 0.05
        assert ros_map.fields["negate"] == "0"
        assert float(ros_map.fields["occupied_thresh"]) == 0.65
        assert float(ros_map.fields["free_thresh"]) == 0.196
        assert len(ros_map.origin) == 3 and ros_map.origin[2] == 0.0
        assert set(np.unique(ros_map.pixels)) == {0, 205, 254}
        assert (out / f"house.floor{floor}.pgm").read_bytes().startswith(b"P5\n")


def _wall_samples(wall, footprint):
    """Points on the middle of a wall's solid, away from its ends and door gaps."""
    start, end = np.array(wall["start"]), np.array(wall["end"])
    u = (end - start) / wall["length"]
    normal = np.array([-u[1], u[0]])
    if wall["outer"]:
        middle = (start + end) / 2
        inward = normal if footprint.contains(Point(*(middle + normal * 0.05))) else -normal
        offset = inward * wall["thickness"] / 2
    else:
        offset = np.zeros(2)
    gaps = [(o["center"] - o["width"] / 2 - 0.1, o["center"] + o["width"] / 2 + 0.1)
            for o in wall["openings"] if o["sill"] < 0.05]
    for s in np.arange(wall["thickness"], wall["length"] - wall["thickness"], 0.1):
        if not any(a <= s <= b for a, b in gaps):
            yield start + u * s + offset


@pytest.mark.parametrize("floor", [0, 1])
def test_occupied_cells_match_walls_and_furniture(exported, floor):
    out, doc = exported
    ros_map = _map(out, floor)
    level = doc["floors"][floor]
    footprint = Polygon(level["footprint"]["exterior"])
    walls = [w for w in doc["walls"] if w["floor"] == floor]
    for wall in walls:
        for x, z in _wall_samples(wall, footprint):
            assert ros_map.at_world(x, z) == 0, (wall["id"], x, z)
    for door in (d for d in doc["doors"] if d["floor"] == floor):
        assert ros_map.at_world(*door["position"]) == 254, door
    furniture = [f for f in doc["furniture"] if f["floor"] == floor]
    band = (level["floor_y"] + 0.05, level["floor_y"] + 1.2)
    for item in furniture:
        (x0, y0, z0), (x1, y1, z1) = item["bbox"]["min"], item["bbox"]["max"]
        solid = not (item["is_detail"] or item["non_collision"])
        if solid and y0 < band[1] and y1 > band[0]:
            for x, z in [((x0 + x1) / 2, (z0 + z1) / 2), (x0 + 0.1, z0 + 0.1), (x1 - 0.1, z1 - 0.1)]:
                assert ros_map.at_world(x, z) == 0, item["name"]
    # free floor: inside room interiors, away from every item's box
    boxes = [Polygon.from_bounds(f["bbox"]["min"][0], f["bbox"]["min"][2], f["bbox"]["max"][0],
                                 f["bbox"]["max"][2]).buffer(0.1) for f in furniture]
    checked = 0
    for room in (r for r in doc["rooms"] if r["floor"] == floor):
        interior = Polygon(room["interior"]["exterior"]).buffer(-0.1)
        min_x, min_z, max_x, max_z = interior.bounds
        for x in np.arange(min_x, max_x, 0.25):
            for z in np.arange(min_z, max_z, 0.25):
                point = Point(x, z)
                if interior.contains(point) and not any(b.contains(point) for b in boxes):
                    assert ros_map.at_world(x, z) == 254, (room["id"], x, z)
                    checked += 1
    assert checked > 200
    # outside the footprint: unknown
    min_x, min_z, max_x, max_z = footprint.bounds
    for x, z in [(min_x - 0.3, (min_z + max_z) / 2), ((min_x + max_x) / 2, max_z + 0.3)]:
        assert ros_map.at_world(x, z) == 205


def test_known_position_is_occupied_on_its_floor_only(exported):
    out, _ = exported
    # the bed stands at world x = 2, z = 3 on floor 1: ROS map point (2, −3)
    assert _map(out, 1).at_world(2.0, 3.0) == 0
    assert _map(out, 0).at_world(2.0, 3.0) == 254  # a rug lies there on floor 0
