"""Difficulty metrics (cga.difficulty, docs/difficulty.md): each on a hand-built plan whose
value is known from the plan itself (rectangles, doors and boxes placed by hand; the
grids come from the navigability check on hand-built wall solids, see conftest)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cga.checks import check_navigability
from cga.difficulty import measure_floor
from cga.difficulty.exploration import exploration_path
from cga.difficulty.metrics import (MAX_WIDTH, WIDTH_STEP, _radii, corridor_length,
                                    cycle_rank, dead_ends, doors_per_room, items_per_m2,
                                    local_width)
from cga.model import FurnitureItem

T = 0.2  # FloorSettings' default wall thickness


def _ring(kit, *, second_door: bool = False):
    """Four 4 m rooms in a square, doors all round (0-1, 1-3, 3-2, 2-0), a front door."""
    plan = kit.plan_from_rectangles([(0, 0, 4, 4), (4, 0, 8, 4), (0, 4, 4, 8), (4, 4, 8, 8)],
                                    settings=kit.FloorSettings(windows_per_wall=0))
    plan = kit.add_door(plan, kit.find_wall(plan, (0, kit.OUTSIDE)), front=True)
    for pair in ((0, 1), (1, 3), (3, 2), (2, 0)):
        plan = kit.add_door(plan, kit.find_wall(plan, pair))
    if second_door:
        plan = kit.add_door(plan, kit.find_wall(plan, (0, 1)), at=0.8)
    return plan


def _chain(kit, *, last_door: float = 0.9):
    """Three 4 m rooms in a row along x; a front door in room 0's west wall, doors
    0-1 and 1-2 centred on z = 2, so every room lies straight ahead of the start."""
    plan = kit.plan_from_rectangles([(0, 0, 4, 4), (4, 0, 8, 4), (8, 0, 12, 4)],
                                    settings=kit.FloorSettings(windows_per_wall=0))
    west = next(w.id for w in plan.walls if w.outer and w.start[0] == 0 and w.end[0] == 0)
    plan = kit.add_door(plan, west, front=True)
    plan = kit.add_door(plan, kit.find_wall(plan, (0, 1)))
    return kit.add_door(plan, kit.find_wall(plan, (1, 2)), width=last_door)


def _measured(kit, plan, items=()):
    scene = kit.scene_of(plan)
    report = check_navigability(scene, [*kit.structure(plan), *items])
    return measure_floor(plan, report.floors[0], report.radius)


def test_cycle_rank_counts_independent_loops(kit):
    assert cycle_rank(_ring(kit)) == 1  # E 4 - V 4 + C 1
    assert cycle_rank(_ring(kit, second_door=True)) == 2
    assert cycle_rank(_chain(kit)) == 0


def test_doors_per_room_and_dead_ends(kit):
    assert doors_per_room(_ring(kit)) == pytest.approx(9 / 4)  # 3 + 2 + 2 + 2
    assert dead_ends(_ring(kit)) == 0
    chain = _chain(kit)
    assert doors_per_room(chain) == pytest.approx(5 / 3)  # 2 + 2 + 1
    assert dead_ends(chain) == 1  # room 2


def test_corridor_length_is_the_corridors_inner_length(kit):
    plan = kit.plan_from_rectangles([(0, 0, 10, 2), (0, 2, 10, 6)], circulation=[0])
    assert corridor_length(plan) == pytest.approx(10 - 2 * T)
    assert corridor_length(kit.plan_from_rectangles([(0, 0, 10, 2), (0, 2, 10, 6)])) == 0.0


def test_items_per_square_metre_of_free_floor(kit):
    plan = _chain(kit)
    items = tuple(FurnitureItem(f"box{k}", "box", k, (2.0 + 4 * k, 2.0), 0, (1, 1, 1))
                  for k in range(3))
    detail = FurnitureItem("door0", "door", 0, (0.0, 2.0), 0, (0.9, 2.1, 0.2), is_detail=True)
    plan = plan.with_changes(furniture=items + (detail,))
    # interiors: rooms 0 and 2 (an outer and an inner wall across x) are (4 - 1.5 T) x
    # (4 - 2 T), room 1 (two inner walls) (4 - T) x (4 - 2 T)
    area = 2 * (4 - 1.5 * T) * (4 - 2 * T) + (4 - T) * (4 - 2 * T)
    assert items_per_m2(plan) == pytest.approx(3 / area)


def test_free_area_share_leaves_out_the_furniture(kit):
    plan = _chain(kit)
    box = kit.box_item("crate", (2.0, 1.0, 2.0), (10.0, 2.0), room=2)
    floor = _measured(kit, plan, [box])
    area = 2 * (4 - 1.5 * T) * (4 - 2 * T) + (4 - T) * (4 - 2 * T)
    assert floor.free_area_share == pytest.approx(1 - 4.0 / area, abs=0.01)


def test_reachable_share_drops_by_the_room_cut_off(kit):
    open_floor = _measured(kit, _chain(kit))
    assert open_floor.reachable_share == pytest.approx(1.0, abs=0.01)
    closed = _measured(kit, _chain(kit, last_door=0.3))  # narrower than the robot
    area = 2 * (4 - 1.5 * T) * (4 - 2 * T) + (4 - T) * (4 - 2 * T)
    reached = (4 - 1.5 * T) * (4 - 2 * T) + (4 - T) * (4 - 2 * T)  # rooms 0 and 1
    assert closed.reachable_share == pytest.approx(reached / area, abs=0.01)


def test_mean_free_width_of_a_corridor_is_its_width(kit):
    plan = kit.plan_from_rectangles([(0, 0, 16, 2)], settings=kit.FloorSettings(windows_per_wall=0))
    west = next(w.id for w in plan.walls if w.outer and w.start[0] == 0 and w.end[0] == 0)
    floor = _measured(kit, kit.add_door(plan, west, front=True))
    # 1.6 m between the walls, measured as the check measures passages (2 x the clearance
    # of cell centres, walls occupying every cell they touch): up to two 5 cm cells and a
    # 5 cm radius step less; the corners at the ends take a little off the mean
    assert 2 - 2 * T - 0.25 <= floor.mean_free_width_m <= 2 - 2 * T


def test_mean_free_width_of_a_square_room(kit):
    # a disc as wide as the room covers all but the corners: the corner cells lie in
    # smaller discs, so the mean is below the room's width, above the disc's share of it
    floor = _measured(kit, _chain(kit))
    assert 0.8 * (4 - 2 * T) < floor.mean_free_width_m < 4 - 2 * T


def test_narrowest_free_width_is_the_narrowest_door(kit):
    floor = _measured(kit, _chain(kit, last_door=0.7))
    # the tightest passage is the 0.7 m door (2 x clearance, to one 5 cm cell)
    assert 0.6 <= floor.narrowest_free_width_m <= 0.7


def test_tortuosity_of_rooms_straight_ahead_is_one(kit):
    floor = _measured(kit, _chain(kit))
    assert floor.tortuosity == pytest.approx(1.0, abs=0.02)


def test_tortuosity_of_a_room_round_a_corner(kit):
    # room 2 sits above room 1: the path turns a corner, so it is longer than the line
    plan = kit.plan_from_rectangles([(0, 0, 4, 4), (4, 0, 8, 4), (4, 4, 8, 8)],
                                    settings=kit.FloorSettings(windows_per_wall=0))
    west = next(w.id for w in plan.walls if w.outer and w.start[0] == 0 and w.end[0] == 0)
    plan = kit.add_door(plan, west, front=True)
    plan = kit.add_door(plan, kit.find_wall(plan, (0, 1)))
    plan = kit.add_door(plan, kit.find_wall(plan, (1, 2)))
    assert _measured(kit, plan).tortuosity > 1.05


def test_grid_metrics_are_none_without_the_check(kit):
    floor = measure_floor(_chain(kit))
    assert floor.cycle_rank == 0
    assert floor.tortuosity is None and floor.exploration_path_m is None


def _corridor(length_m: float, res: float = 0.05):
    """A 1 m wide free corridor along x, walls round it."""
    cols, rows = round(length_m / res) + 2, round(1.0 / res) + 2
    free = np.zeros((rows, cols), dtype=bool)
    free[1:-1, 1:-1] = True
    return free, ~free


def test_exploration_of_a_room_seen_at_once_is_zero():
    free, blocked = _corridor(4.0)
    start = (free.shape[0] // 2, free.shape[1] // 2)
    assert exploration_path(free, blocked, free, start, 0.05) == 0.0


def test_exploration_of_a_long_corridor():
    # 20 m corridor, 5 m sensor: each frontier lies at the edge of what the robot saw,
    # 5 m on; to see 95 % (19 m) it stands at 5, 10, then 15 m: 15 m driven
    free, blocked = _corridor(20.0)
    start = (free.shape[0] // 2, 1)
    assert exploration_path(free, blocked, free, start, 0.05) == pytest.approx(15.0, abs=0.3)


def _local_width_by_definition(clearance, resolution):
    """The local width as docs/difficulty.md defines it, computed the straightforward
    way: for every radius, scipy's distance transform of the whole grid to the cells
    whose clearance admits a disc of that radius."""
    from scipy import ndimage

    width = np.zeros(clearance.shape)
    radius = WIDTH_STEP / 2
    while radius <= MAX_WIDTH / 2:
        centres = clearance >= radius
        if not centres.any():
            break
        width[ndimage.distance_transform_edt(~centres) * resolution <= radius] = 2 * radius
        radius += WIDTH_STEP / 2
    return width


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(3, 90), cols=st.integers(3, 90),
       boxes=st.integers(0, 6), resolution=st.sampled_from([0.05, 0.1, 0.04]))
def test_local_width_is_the_per_radius_definition(seed, rows, cols, boxes, resolution):
    """local_width (eight radii per pass in the bit planes of a byte grid, cropped to
    the centres) gives the very numbers of the definition on rooms with random
    furniture."""
    from scipy import ndimage

    rng = np.random.default_rng(seed)
    blocked = np.zeros((rows, cols), dtype=bool)
    blocked[[0, -1], :] = blocked[:, [0, -1]] = True
    for _ in range(boxes):
        r, c = rng.integers(0, rows), rng.integers(0, cols)
        blocked[r:r + rng.integers(1, 12), c:c + rng.integers(1, 12)] = True
    clearance = ndimage.distance_transform_edt(~blocked) * resolution - resolution / 2
    assert np.array_equal(local_width(clearance, resolution),
                          _local_width_by_definition(clearance, resolution))




def test_local_width_of_a_hall_wider_than_the_largest_disc():
    """A 9.5 m × 10.5 m hall with a pillar: every radius up to :data:`MAX_WIDTH`'s half
    admits centres (all eight-radius passes, the last one short), and the widest discs
    stop at 6 m."""
    from scipy import ndimage

    blocked = np.zeros((190, 210), dtype=bool)
    blocked[[0, -1], :] = blocked[:, [0, -1]] = True
    blocked[30:36, 150:158] = True
    clearance = ndimage.distance_transform_edt(~blocked) * 0.05 - 0.025
    width = local_width(clearance, 0.05)
    assert width.max() == 2 * max(r for r in _radii())
    assert np.array_equal(width, _local_width_by_definition(clearance, 0.05))

@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), rows=st.integers(1, 12), cols=st.integers(1, 12))
def test_grid_graph_joins_each_drivable_cell_to_its_eight_neighbours(seed, rows, cols):
    """The search graph, built row by row, is the 8-neighbour grid graph, both ways,
    weighted by the centre-to-centre distance."""
    from cga.difficulty.exploration import _grid_graph

    drivable = np.random.default_rng(seed).random((rows, cols)) < 0.6
    graph, index = _grid_graph(drivable, 0.25)
    expected = np.zeros(graph.shape)
    for (r, c) in zip(*np.nonzero(drivable)):
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                rr, cc = r + dr, c + dc
                if (dr or dc) and 0 <= rr < rows and 0 <= cc < cols and drivable[rr, cc]:
                    expected[index[r, c], index[rr, cc]] = 0.25 * np.hypot(dr, dc)
    assert graph.has_sorted_indices
    assert np.array_equal(graph.toarray(), expected)
