"""Model files are parsed once per process and re-parsed when they change on disk."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from shapely.geometry import box

from cga.model import FloorPlan, FloorSettings, FurnitureItem, Room
from cga.meshing.items import item_node
from cga.operations.furniture.library import ModelLibrary


def _box_obj(path: Path, width: float, height: float, depth: float) -> Path:
    """An axis-aligned box model written by hand: 8 vertices, 12 triangles."""
    x, z = width / 2, depth / 2
    corners = [(sx * x, y, sz * z) for sx in (-1, 1) for y in (0, height) for sz in (-1, 1)]
    faces = [(1, 2, 4), (1, 4, 3), (5, 7, 8), (5, 8, 6), (1, 5, 6), (1, 6, 2),
             (3, 4, 8), (3, 8, 7), (1, 3, 7), (1, 7, 5), (2, 6, 8), (2, 8, 4)]
    lines = ["g body", *(f"v {a:g} {b:g} {c:g}" for a, b, c in corners),
             *(f"f {a} {b} {c}" for a, b, c in faces)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def test_two_libraries_share_the_parsed_geometry(tmp_path):
    _box_obj(tmp_path / "crate.obj", 1.0, 0.5, 0.8)
    first, second = ModelLibrary([tmp_path]).get("crate"), ModelLibrary([tmp_path]).get("crate")
    assert first is not second
    assert first.parts[0] is second.parts[0]
    assert first.size == pytest.approx((1.0, 0.5, 0.8))


def test_a_changed_file_is_parsed_again(tmp_path):
    path = _box_obj(tmp_path / "crate.obj", 1.0, 0.5, 0.8)
    assert ModelLibrary([tmp_path]).get("crate").size == pytest.approx((1.0, 0.5, 0.8))
    stamp = path.stat().st_mtime_ns
    _box_obj(path, 2.0, 0.5, 0.8)
    os.utime(path, ns=(stamp + 1_000_000, stamp + 1_000_000))
    assert ModelLibrary([tmp_path]).get("crate").size == pytest.approx((2.0, 0.5, 0.8))


@pytest.mark.parametrize("rotation, size", [(0, (1.0, 0.5, 0.8)), (1, (2.0, 1.5, 0.4)),
                                            (3, (0.5, 0.25, 3.0))])
def test_item_mass_is_the_posed_box_volume_times_density(tmp_path, rotation, size):
    _box_obj(tmp_path / "crate.obj", 1.0, 0.5, 0.8)
    library = ModelLibrary([tmp_path])
    square = box(0, 0, 10, 10)
    plan = FloorPlan(index=0, elevation=0.0, height=3.0, footprint=square,
                     settings=FloorSettings(), walls=(),
                     rooms=(Room(id=0, polygon=square, interior=square, type="Hall"),))
    item = FurnitureItem(name="crate", model="crate", room=0, position=(5.0, 5.0),
                         rotation=rotation, size=size)
    node = item_node(item, plan, library)
    assert node.item.mass == pytest.approx(np.prod(size) * node.item.density)
