"""3D walls and slabs: paths, watertightness, no overlaps, openings cut, joints."""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np
import pytest
import shapely
import trimesh
from shapely.geometry import box

from cga.model import FloorSettings, Opening
from cga.operations.floorplan import plan_from_rectangles
from cga.meshing.solids import floor_nodes, wall_footprints

SETTINGS = FloorSettings(windows_per_wall=1, window_width=1.2, window_height=1.2, window_sill=0.9)
RECTS = [(0, 0, 6, 10), (6, 0, 14, 5), (6, 5, 14, 10)]


def three_rooms(**changes):
    plan = plan_from_rectangles(RECTS, settings=SETTINGS, index=1, elevation=3.0, height=3.0)
    return plan.with_changes(**changes)


def walls(nodes):
    return [n for n in nodes if n.kind == "wall"]


def test_node_paths_kinds_and_extras():
    plan = three_rooms()
    nodes = floor_nodes(plan)
    assert [n.path for n in nodes if n.kind != "wall"] == ["floor1/slab"]
    by_id = {n.extras["wall_id"]: n for n in walls(nodes)}
    assert sorted(by_id) == [w.id for w in plan.walls]
    for w in plan.walls:
        node = by_id[w.id]
        rooms = [r for r in w.rooms if r >= 0]
        assert node.path == f"floor1/room{min(rooms)}/wall{w.id}"
        assert node.extras == {"wall_id": w.id, "outer": w.outer, "rooms": rooms,
                               "openings": len(w.openings)}


def test_typed_rooms_name_the_path_and_top_floor_gets_a_roof():
    plan = three_rooms(is_top=True)
    plan = plan.with_changes(rooms=tuple(replace(r, type="Kitchen") if r.id == 2 else r for r in plan.rooms))
    nodes = floor_nodes(plan)
    paths = [n.path for n in nodes]
    assert "floor1/room2_Kitchen/wall9" in paths and "floor1/room0/wall0" in paths
    roof = next(n for n in nodes if n.kind == "roof")
    assert roof.path == "floor1/roof"
    # the roof takes the top of the storey (where a next floor's slab would be): the
    # building stays within the mass, and the walls stop under the roof
    assert roof.mesh.bounds.ravel() == pytest.approx([0, 5.8, 0, 14, 6.0, 10])
    slab = next(n for n in nodes if n.kind == "slab")
    assert slab.mesh.bounds.ravel() == pytest.approx([0, 3.0, 0, 14, 3.2, 10])
    assert max(n.mesh.bounds[1][1] for n in walls(nodes)) == pytest.approx(5.8)


def test_walls_are_watertight_fill_the_wall_region_and_do_not_overlap():
    plan = three_rooms()
    nodes = walls(floor_nodes(plan))
    wall_height = 3.0 - 0.2
    region = box(0, 0, 14, 10).difference(shapely.union_all([r.interior for r in plan.rooms]))
    window = 1.2 * 1.2 * 0.2
    expected = region.area * wall_height - window * len(plan.windows)
    for n in nodes:
        assert n.mesh.is_watertight and n.mesh.is_winding_consistent and n.mesh.volume > 0
        lo, hi = n.mesh.bounds
        assert lo[1] == pytest.approx(3.2) and hi[1] == pytest.approx(6.0)
    assert sum(n.mesh.volume for n in nodes) == pytest.approx(expected, rel=1e-6)
    union = trimesh.boolean.union([n.mesh for n in nodes], engine="manifold")
    assert union.volume == pytest.approx(expected, rel=1e-6)  # no volume counted twice


def test_openings_are_cut_through_the_wall():
    plan = three_rooms()
    inner = next(w for w in plan.walls if not w.outer and w.rooms == (1, 2))
    door = Opening("door", inner.length / 2, 0.9, 2.1)
    plan = plan.with_changes(walls=tuple(w.with_opening(door) if w is inner else w for w in plan.walls))
    node = next(n for n in floor_nodes(plan) if n.extras["wall_id"] == inner.id)
    assert node.extras["openings"] == 1 and node.mesh.is_watertight
    full = wall_footprints(plan)[inner.id].area * 2.8
    assert node.mesh.volume == pytest.approx(full - 0.9 * 2.1 * 0.2, rel=1e-6)
    # horizontal sections: the door takes 0.9 x 0.2 m out at 1 m above the floor, the
    # window 1.2 x 0.2 m at mid-height, and nothing below its sill
    assert section_area(node.mesh, 3.2 + 1.0) == pytest.approx(full / 2.8 - 0.9 * 0.2, rel=1e-6)
    window_wall = next(w for w in plan.walls if w.outer and w.openings)
    window_node = next(n for n in floor_nodes(plan) if n.extras["wall_id"] == window_wall.id)
    plain = wall_footprints(plan)[window_wall.id].area
    assert section_area(window_node.mesh, 3.2 + 1.5) == pytest.approx(plain - 1.2 * 0.2, rel=1e-6)
    assert section_area(window_node.mesh, 3.2 + 0.5) == pytest.approx(plain, rel=1e-6)


def section_area(mesh, y):
    """Area of the mesh's horizontal cross-section at height ``y`` (plan x, z)."""
    lines = trimesh.intersections.mesh_plane(mesh, plane_normal=[0, 1, 0], plane_origin=[0, y, 0])
    lines = np.round(lines, 9)  # ends computed from neighbouring triangles must meet exactly
    segments = shapely.MultiLineString([[(a[0], a[2]), (b[0], b[2])] for a, b in lines])
    return sum(p.area for p in shapely.polygonize([shapely.union_all(segments)]).geoms)


def test_joints_belong_to_the_wall_running_through():
    plan = three_rooms()
    footprints = wall_footprints(plan)
    for a, b in itertools.combinations(footprints.values(), 2):
        assert a.intersection(b).area < 1e-12
    stem = next(w for w in plan.walls if w.rooms == (1, 2))  # (14, 5) -> (6, 5) meets x = 6
    assert footprints[stem.id].bounds == pytest.approx((6.1, 4.9, 13.8, 5.1))
    through = [w for w in plan.walls if w.rooms in ((0, 1), (0, 2))]
    assert np.ravel([footprints[w.id].bounds for w in through]) == pytest.approx(
        [5.9, 0.2, 6.1, 5.0, 5.9, 5.0, 6.1, 9.8])
    # outer walls stay inside the footprint and own the corners
    south = next(w for w in plan.walls if w.start == (0.0, 0.0))
    west = next(w for w in plan.walls if w.end == (0.0, 0.0))
    corner = box(0, 0, 0.2, 0.2)
    owners = [w.id for w in (south, west) if footprints[w.id].contains(corner)]
    assert len(owners) == 1


def test_the_walking_surface_is_cut_room_by_room():
    # every upward triangle of the slab lies in one room's interior or in none (the
    # walls' footprint), so each room can have its own floor; the slab stays watertight
    plan = three_rooms()
    slab = next(n for n in floor_nodes(plan) if n.kind == "slab")
    assert slab.mesh.is_watertight
    up = slab.mesh.face_normals[:, 1] > 0.5
    triangles = [shapely.Polygon(t[:, [0, 2]]) for t in slab.mesh.triangles[up]]
    interiors = [r.interior for r in plan.rooms]
    for triangle in triangles:
        inside = [room.covers(triangle.buffer(-1e-9)) for room in interiors]
        overlapping = [room.intersection(triangle).area > 1e-9 for room in interiors]
        assert sum(inside) == sum(overlapping) <= 1
    # the rooms' floors together are the rooms' interiors
    covered = sum(t.area for t in triangles if any(r.covers(t.buffer(-1e-9)) for r in interiors))
    assert covered == pytest.approx(sum(r.area for r in interiors))
