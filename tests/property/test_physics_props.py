"""The physics check at scale: many storeys, big footprints, far from the origin.

Issue 19 reported bookshelves that "fell through the floor" on storeys 8–13 of a
15-storey, 100 m × 60 m building. These scenes are built by hand (slabs, walls and box
furniture, independent of the meshing code): up to 15 storeys, footprints up to
100 m × 60 m placed anywhere a lot may be (up to 100 km from the origin), tall thin
shelves flush against a wall and free-standing boxes on random storeys. One box is
dropped beside the building so that, as in a big scene where something is still
moving, settling runs its full time instead of stopping early. The property: every
item in the building rests where it stands — no overlap, no motion, nothing through a
floor — on every storey.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cga.checks import check_physics
from cga.scene import Scene, SceneNode
from items import item_info

pytestmark = [pytest.mark.physics, pytest.mark.slow]

WALL = 0.2


def _box(extents, centre) -> trimesh.Trimesh:
    mesh = trimesh.creation.box(extents=extents)
    mesh.apply_translation(centre)
    return mesh


def _item(path: str, size, corner) -> SceneNode:
    """A box item of ``size`` (w, h, d) whose lowest corner is ``corner`` (x, y, z)."""
    mesh = _box(size, np.add(corner, np.divide(size, 2)))
    return SceneNode(path, "furniture", mesh, item=item_info(path.rsplit("/", 1)[-1]),
                     static=False, parts=(mesh,))


@st.composite
def buildings(draw):
    storeys = draw(st.integers(2, 15))
    width = draw(st.floats(8, 100))
    depth = draw(st.floats(6, 60))
    height = draw(st.floats(2.6, 4.0))
    slab = draw(st.floats(0.15, 0.35))
    x0, z0 = (draw(st.sampled_from([0.0, -37.5, 1234.5, 99_000.0])) for _ in range(2))
    nodes = []
    for floor in range(storeys):
        bottom = floor * height
        top = bottom + slab
        nodes.append(SceneNode(f"floor{floor}/slab", "slab", _box(
            (width, slab, depth), (x0 + width / 2, bottom + slab / 2, z0 + depth / 2))))
        nodes.append(SceneNode(f"floor{floor}/wall0", "wall", _box(
            (width, height - slab, WALL), (x0 + width / 2, top + (height - slab) / 2,
                                           z0 + WALL / 2))))
    furnished = draw(st.lists(st.integers(0, storeys - 1), min_size=1, max_size=4,
                              unique=True))
    for floor in furnished:
        top = floor * height + slab
        along = draw(st.floats(0.5, width - 1.5))
        shelf = (0.8, min(2.0, height - slab - 0.1), 0.35)
        nodes.append(_item(f"floor{floor}/room0/furniture/bookshelf",
                           shelf, (x0 + along, top, z0 + WALL)))  # flush against the wall
        free = (draw(st.floats(0.4, 1.6)), draw(st.floats(0.3, 1.2)), draw(st.floats(0.4, 1.0)))
        nodes.append(_item(f"floor{floor}/room0/furniture/table",
                           free, (x0 + width / 2, top, z0 + depth / 2)))
    nodes.append(_item("outside/furniture/dropped", (0.5, 0.5, 0.5),
                       (x0 - 20.0, 5.0, z0 - 20.0)))
    return nodes


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(nodes=buildings())
def test_furniture_rests_on_every_storey_of_a_big_building(nodes):
    report = check_physics(Scene(name="tower", seed=0, units=1.0, terminals=[]), nodes)
    assert report.simulated_seconds == report.settle_seconds  # the dropped box kept it going
    inside = [item for item in report.items if not item.path.startswith("outside/")]
    failed = [f"{item.path}: {', '.join(item.problems)}" for item in inside if not item.passed]
    assert not failed, failed
