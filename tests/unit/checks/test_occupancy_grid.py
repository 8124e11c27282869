"""Occupancy grids: ROS map frame, the robot's height band, door gaps, closed windows."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
import trimesh
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from shapely.geometry import box

from cga.checks import band_footprint, occupancy_grid
from cga.checks.occupancy import band_footprints
from cga.scene import SceneNode

RES = 0.05


def _cells_of(grid, x0, z0, x1, z1):
    """Rows and columns whose centres lie strictly inside the world box (independent
    of the grid's own helpers: plain arithmetic on the ROS map convention)."""
    rows, cols = grid.occupied.shape
    ros_y_top = grid.origin[1] + rows * grid.resolution
    r = [i for i in range(rows) if z0 < -(ros_y_top - (i + 0.5) * grid.resolution) < z1]
    c = [j for j in range(cols) if x0 < grid.origin[0] + (j + 0.5) * grid.resolution < x1]
    return slice(r[0], r[-1] + 1), slice(c[0], c[-1] + 1)


def test_ros_map_frame(kit, two_rooms):
    grid = occupancy_grid(two_rooms, [], resolution=RES, margin=0.5)
    rows, cols = grid.shape
    assert (rows, cols) == (round(5.0 / RES), round(9.0 / RES))
    # origin: ROS (x, y) of the lower-left corner = world (min x, -(max z)) of the grid.
    assert grid.origin == pytest.approx((-0.5, -4.5))
    # Row 0 is the largest ROS y = the smallest world z.
    assert grid.world_to_cell(-0.49, -0.49) == (0, 0)
    assert grid.world_to_cell(8.49, 4.49) == (rows - 1, cols - 1)
    x, z = grid.cell_to_world(0, 0)
    assert (x, -z) == pytest.approx((grid.origin[0] + RES / 2, grid.origin[1] + (rows - 0.5) * RES))


def test_free_mask_is_the_footprint(kit, two_rooms):
    grid = occupancy_grid(two_rooms, [], resolution=RES, margin=0.5)
    inside = _cells_of(grid, 0.05, 0.05, 7.95, 3.95)
    assert grid.free_mask[inside].all()
    assert not grid.free_mask[:5].any() and not grid.free_mask[:, -5:].any()
    assert grid.free_mask.sum() == pytest.approx(8 * 4 / RES**2, rel=0.06)


def test_obstacle_lands_in_its_cells(kit, two_rooms):
    item = kit.box_item("box", (1.0, 0.8, 0.6), (2.5, 3.0))
    grid = occupancy_grid(two_rooms, [item], resolution=RES)
    core = _cells_of(grid, 2.0, 2.7, 3.0, 3.3)
    assert grid.occupied[core].all()
    # Nothing but the item: it covers its 20 x 12 cells, plus at most one outline cell.
    assert 20 * 12 <= grid.occupied.sum() <= 22 * 14
    row, col = grid.world_to_cell(2.5, 3.0)
    assert grid.occupied[row, col]
    assert not grid.occupied[grid.world_to_cell(2.5, 2.0)]


def test_band_filters_by_height(kit, two_rooms):
    low = kit.box_item("rug", (1.0, 0.02, 1.0), (1.0, 1.0))            # below 0.05 m
    high = kit.box_item("shelf", (1.0, 0.3, 0.4), (3.0, 1.0), lift=1.5)  # above 1.2 m
    table_top = kit.box_item("top", (1.0, 0.05, 1.0), (5.0, 1.0), lift=0.7)
    static = kit.box_item("door", (0.9, 2.0, 0.05), (6.5, 3.0), static=True)
    grid = occupancy_grid(two_rooms, [low, high, table_top, static], resolution=RES)
    assert [o.path for o in grid.obstacles] == [table_top.path]
    lower = occupancy_grid(two_rooms, [table_top], resolution=RES, band=(0.05, 0.5))
    assert not lower.occupied.any()


def test_structure_only(kit, two_rooms):
    nodes = kit.structure(two_rooms) + [kit.box_item("box", (1, 1, 1), (2.0, 2.0))]
    bare = occupancy_grid(two_rooms, nodes, include_furniture=False)
    full = occupancy_grid(two_rooms, nodes)
    assert all(o.kind != "furniture" for o in bare.obstacles)
    assert full.occupied[full.world_to_cell(2.0, 2.0)]
    assert not bare.occupied[bare.world_to_cell(2.0, 2.0)]


def test_door_gap_stays_free_and_window_stays_closed(kit):
    settings = kit.FloorSettings(windows_per_wall=1, window_sill=0.9)
    plan = kit.plan_from_rectangles([(0, 0, 4, 4), (4, 0, 8, 4)], settings=settings)
    plan = kit.add_door(plan, kit.find_wall(plan, (0, 1)), width=0.9)
    grid = occupancy_grid(plan, kit.structure(plan), resolution=RES)
    door = plan.doors[0]
    # The inner wall x in [3.9, 4.1]; the door gap z in [1.55, 2.45].
    gap = _cells_of(grid, 3.9, 1.6, 4.1, 2.4)
    assert not grid.occupied[gap].any()
    solid = _cells_of(grid, 3.9, 0.3, 4.1, 1.5)
    assert grid.occupied[solid].all()
    assert door.position == pytest.approx((4.0, 2.0))
    # Every window sits above the wall below its sill, which is in the band.
    for window in plan.windows:
        row, col = grid.world_to_cell(*window.position)
        wall = plan.wall(window.wall)
        normal = np.array([-wall.direction[1], wall.direction[0]])
        inward = [grid.world_to_cell(*(np.asarray(window.position) + normal * s * 0.1))
                  for s in (-1, 1)]
        assert any(grid.occupied[rc] for rc in inward)


def test_wall_ring_keeps_its_room_free(kit):
    plan = kit.plan_from_rectangles([(0, 0, 4, 4)])
    outer = box(0, 0, 4, 4)
    inner = box(0.2, 0.2, 3.8, 3.8)
    ring = trimesh.creation.extrude_polygon(outer.difference(inner), 2.5)
    # (px, py, e) -> (px, 0.2 + e, py); trimesh keeps the winding outward for mirrors.
    ring.apply_transform(np.array([[1, 0, 0, 0], [0, 0, 1, 0.2], [0, 1, 0, 0], [0, 0, 0, 1.0]]))
    assert ring.is_volume
    node = SceneNode("floor0/walls", "wall", ring)
    footprint = band_footprint(node, 0.25, 1.4)
    assert footprint.area == pytest.approx(outer.area - inner.area, rel=1e-6)
    grid = occupancy_grid(plan, [node], resolution=RES)
    assert not grid.occupied[_cells_of(grid, 0.3, 0.3, 3.7, 3.7)].any()
    assert grid.occupied[_cells_of(grid, 0.0, 0.0, 4.0, 0.2)].all()


def test_open_mesh_falls_back_on_its_hull(kit, two_rooms):
    panel = trimesh.Trimesh(vertices=[[1, 0.2, 1], [2, 0.2, 1], [2, 1.2, 1], [1, 1.2, 1]],
                            faces=[[0, 1, 2], [0, 2, 3]])
    node = SceneNode("floor0/panel", "wall", panel)
    grid = occupancy_grid(two_rooms, [node], resolution=RES)
    row, col = grid.world_to_cell(1.5, 1.0)
    assert grid.occupied[row - 1:row + 1, col].any()


def test_invalid_arguments(kit, two_rooms):
    with pytest.raises(ValueError, match="resolution"):
        occupancy_grid(two_rooms, [], resolution=0)
    with pytest.raises(ValueError, match="band"):
        occupancy_grid(two_rooms, [], band=(1.0, 0.5))


def test_upper_floor_uses_its_own_band(kit):
    ground = kit.plan_from_rectangles([(0, 0, 4, 4)], index=0, elevation=0.0)
    upper = kit.plan_from_rectangles([(0, 0, 4, 4)], index=1, elevation=3.0)
    downstairs = kit.box_item("sofa", (1, 0.8, 1), (2, 2), floor_y=ground.floor_y)
    upstairs = kit.box_item("bed", (1, 0.5, 2), (1, 1), floor_y=upper.floor_y, floor=1)
    grid = occupancy_grid(upper, [downstairs, upstairs], resolution=RES)
    assert [o.path for o in grid.obstacles] == [upstairs.path]
    assert grid.band == pytest.approx((upper.floor_y + 0.05, upper.floor_y + 1.2))
    assert math.isclose(grid.band[0], 3.25)


def test_occupied_by_is_the_same_when_asked_again(kit, two_rooms):
    """occupied_by keeps each obstacle's cells from its first rasterisation; asking again
    (in another mix) gives exactly the cells of a grid that rasterises them anew."""
    nodes = kit.structure(two_rooms) + [
        kit.box_item("table", (1.2, 0.75, 0.8), (2.0, 2.0)),
        kit.box_item("sofa", (2.0, 0.8, 0.9), (6.0, 1.0))]
    grid = occupancy_grid(two_rooms, nodes)
    paths = [o.path for o in grid.obstacles]
    first = grid.occupied_by(paths)
    for chosen in (paths[::2], paths[-1:], paths):
        fresh = occupancy_grid(two_rooms, nodes).occupied_by(chosen)
        assert np.array_equal(grid.occupied_by(chosen), fresh)
    assert np.array_equal(first, grid.occupied_by(paths))
    assert first.any()


def _convex_node(name: str, clouds) -> SceneNode:
    """A furniture node whose parts are the convex hulls of point clouds."""
    parts = tuple(trimesh.convex.convex_hull(np.asarray(c, dtype=float)) for c in clouds)
    mesh = trimesh.util.concatenate(parts)
    return SceneNode(f"floor0/room0/furniture/{name}", "furniture", mesh, parts=parts)


def _clipped_shadow(part: trimesh.Trimesh, y0: float, y1: float):
    """The straightforward shadow of a convex part's slice: cut by the two planes with
    trimesh, then the plan hull of what is left (an independent computation)."""
    piece = trimesh.intersections.slice_mesh_plane(part, (0, 1, 0), (0, y0, 0), cap=True)
    if len(piece.faces):
        piece = trimesh.intersections.slice_mesh_plane(piece, (0, -1, 0), (0, y1, 0), cap=True)
    if not len(piece.faces):
        return box(0, 0, 0, 0)
    return shapely.MultiPoint(np.asarray(piece.vertices)[:, [0, 2]]).convex_hull


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), nodes=st.integers(1, 6),
       band=st.tuples(st.floats(0.0, 1.0), st.floats(0.05, 1.5)))
def test_convex_shadows_of_many_nodes_match_each_part_clipped_alone(seed, nodes, band):
    """All nodes' convex parts are sliced and hulled in one vectorised pass: each node's
    shadow is exactly what it gets alone, and it matches the union of its parts clipped
    one by one with trimesh."""
    rng = np.random.default_rng(seed)
    y0, y1 = band[0], band[0] + band[1]
    made = [_convex_node(f"item{k}", [rng.uniform(-1, 1, (8, 3)) * rng.uniform(0.1, 1.0, 3)
                                      + rng.uniform([-3, 0.6, -3], [3, 1.5, 3])
                                      for _ in range(int(rng.integers(1, 5)))])
            for k in range(nodes)]
    together = band_footprints(made, y0, y1)
    for node, shadow in zip(made, together):
        alone = band_footprint(node, y0, y1)
        assert shapely.to_wkb(shadow) == shapely.to_wkb(alone)
        expected = shapely.union_all([_clipped_shadow(p, y0, y1) for p in node.parts])
        assert shadow.symmetric_difference(expected).area <= 1e-9


@settings(max_examples=25, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])  # fixtures: plain data
@given(corners=st.lists(st.tuples(st.integers(10, 300), st.integers(10, 140),
                                  st.integers(2, 40), st.integers(2, 40)), min_size=1, max_size=6),
       margin=st.sampled_from([0.5, 0.55, 0.6, 0.7333]))
def test_cells_kept_from_the_build_are_those_of_the_grids_own_frame(kit, two_rooms, corners,
                                                                   margin):
    """The grid keeps the cells it drew each obstacle with for occupied_by only where
    they are the cells of the grid's own frame: items with edges on (or a round-off
    away from) cell boundaries get exactly what a fresh rasterisation gives."""
    nodes = [kit.box_item(f"box{k}", (w * 0.025, 0.5, d * 0.025),
                         (x * 0.025 + w * 0.0125, z * 0.025 + d * 0.0125))
             for k, (x, z, w, d) in enumerate(corners)]
    grid = occupancy_grid(two_rooms, nodes, margin=margin)
    for obstacle in grid.obstacles:
        fresh = grid.rasterise(obstacle.footprint)
        assert np.array_equal(grid.occupied_by([obstacle.path]), fresh)
