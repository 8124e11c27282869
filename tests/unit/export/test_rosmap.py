"""ROS maps: map_server format, and occupied cells where the scene JSON puts walls and
furniture (checked from the JSON data and the map files alone)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from ros_map_checks import RosMap, check_map_against_scene

from cga.export.rosmap import export_rosmap
from cga.export.scene_json import export_scene_json


@pytest.fixture(scope="module")
def exported(small_scene, tmp_path_factory):
    scene, nodes = small_scene
    out = tmp_path_factory.mktemp("maps")
    export_rosmap(scene, nodes, out, "house")
    export_scene_json(scene, nodes, out, "house")
    return out, json.loads((out / "house.scene.json").read_text())


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


@pytest.mark.parametrize("floor", [0, 1])
def test_occupied_cells_match_walls_and_furniture(exported, floor):
    out, doc = exported
    counts = check_map_against_scene(_map(out, floor), doc, floor)
    assert counts["wall"] > 200 and counts["free"] > 200 and counts["outside"] == 2
    assert counts["door"] == (3 if floor == 0 else 2)
    assert counts["furniture"] == (3 if floor == 0 else 2)


def test_known_position_is_occupied_on_its_floor_only(exported):
    out, _ = exported
    # the bed stands at world x = 2, z = 3 on floor 1: ROS map point (2, −3)
    assert _map(out, 1).at_world(2.0, 3.0) == 0
    assert _map(out, 0).at_world(2.0, 3.0) == 254  # a rug lies there on floor 0
