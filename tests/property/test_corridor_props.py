"""Properties of make_floor's corridors over many seeds and footprints (docs/architecture.md).

For rectangle, L, U and T storeys with a spine, hall or centre-line corridor: either the
footprint is refused with a message saying why (too shallow for corridor and rooms), or
the half-edge invariants hold and the faces tile the footprint (independent validator),
there is exactly one circulation room, the corridor is at least its width wide
everywhere (raster opening), every other room keeps enough wall on the corridor for a
door with its margins, and rooms between corridor and shell are at least
``min_room_depth`` deep where they meet the corridor. Spines on rectangles up to 30 m
deep: no band of rooms deeper than ``max_room_depth``, parallel spines only where one
would leave deeper bands.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, example, given, settings, strategies as st

from cga.errors import DerivationError

from dcel_checks import narrowest_room_violation, validate_plan
from floor_runs import run_make_floor
from footprint_strategies import winged_footprints

EXAMPLES_PER_KIND = 130  # 4 kinds: 520 storeys
DOOR, WALL, MARGIN = 0.9, 0.2, 0.1


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["rectangle", "L", "U", "T"])
@settings(max_examples=EXAMPLES_PER_KIND, deadline=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_corridor_properties(kind, data):
    footprint = data.draw(winged_footprints(kind), label="footprint")
    mode = data.draw(st.sampled_from(["spine", "hall", "centre_line"] if kind != "rectangle"
                                     else ["spine", "hall"]), label="mode")
    width = data.draw(st.sampled_from([1.2, 1.5, 2.0]), label="corridor_width")
    split = data.draw(st.integers(0, 10), label="split")
    seed = data.draw(st.integers(0, 2**32 - 1), label="seed")

    try:
        child, reports = run_make_floor(
            footprint, floor=0, seed=seed, split=split, wallWidth=WALL, windows=(2, 1.2, 1.2),
            doorWidth=DOOR, doorHeight=2.1, corridor=mode, corridor_width=width)
    except DerivationError as error:
        assert "cannot carve" in str(error)
        return
    plan = child.plan
    validate_plan(plan)
    corridors = [r for r in plan.rooms if r.circulation]
    assert len(corridors) == 1
    corridor = corridors[0].polygon
    assert narrowest_room_violation(corridor, width) == 0.0
    assert corridor.boundary.intersection(plan.footprint.boundary).length > 0  # reaches a wall
    if not reports:
        assert len(plan.rooms) - 1 >= split + 1 or mode == "centre_line"
    free = plan.footprint.difference(corridor)
    for part in getattr(free, "geoms", [free]):
        assert narrowest_room_violation(part, 2.5) == 0.0, "a room is shallower than min_room_depth"
    for room in plan.rooms:
        if room.circulation:
            continue
        shared = room.polygon.boundary.intersection(corridor.boundary).length
        assert shared >= DOOR + 2 * (MARGIN + WALL) - 1e-9, f"room {room.id} has no door to the corridor"


@pytest.mark.slow
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(length=st.floats(12, 40), depth=st.floats(6, 30), width=st.sampled_from([1.2, 1.6, 2.0]),
       deepest=st.sampled_from([5.0, 7.5, 10.0]), split=st.integers(4, 14),
       seed=st.integers(0, 2**32 - 1))
@example(length=12.0, depth=6.0234375, width=1.2, deepest=5.0, split=4, seed=0)  # a rounded
# corridor flush with the outer wall stopped 0.5 µm short of it: a sliver for a room
def test_spines_keep_every_band_of_rooms_within_max_room_depth(length, depth, width, deepest,
                                                               split, seed):
    """A spine on a rectangle of any depth: one corridor that reaches the outer wall and
    is its width wide everywhere, every room on it with a door's length of wall, and no
    band of rooms between corridors and shell deeper than max_room_depth, and one spine
    wherever one keeps the bands within it."""
    from shapely.geometry import box

    long_x = length >= depth
    try:
        child, _ = run_make_floor(
            box(0, 0, length, depth), floor=0, seed=seed, split=split, wallWidth=WALL,
            windows=(2, 1.2, 1.2), doorWidth=DOOR, doorHeight=2.1, corridor="spine",
            corridor_width=width, max_room_depth=deepest)
    except DerivationError as error:
        assert "cannot carve" in str(error)
        return
    plan = child.plan
    validate_plan(plan)
    (corridor,) = [r.polygon for r in plan.rooms if r.circulation]
    assert narrowest_room_violation(corridor, width) == 0.0
    assert corridor.boundary.intersection(plan.footprint.boundary).length > 0
    along, across = max(length, depth), min(length, depth)
    if (across - width) / 2 <= deepest:
        assert corridor.area == pytest.approx(width * along)  # one straight spine
    free = plan.footprint.difference(corridor)
    for part in getattr(free, "geoms", [free]):
        x0, z0, x1, z1 = part.bounds
        assert ((z1 - z0) if long_x else (x1 - x0)) <= deepest + 1e-6
        assert narrowest_room_violation(part, 2.5) == 0.0
    for room in plan.rooms:
        if not room.circulation:
            shared = room.polygon.boundary.intersection(corridor.boundary).length
            assert shared >= DOOR + 2 * (MARGIN + WALL) - 1e-9, f"room {room.id} has no door"
