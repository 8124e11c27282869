"""Properties of make_floor over many seeds and footprints (rectangle, L, U, T).

For every drawn storey: the half-edge invariants hold and the rooms tile the footprint
(independent validator in ``tests/support/dcel_checks.py``); the room count is
``split + 1`` unless a diagnostic says how many were made; every room is at least
``min_room_width`` wide everywhere (exact for rectangles, by a raster opening
otherwise) and ``min_room_area`` large; every vertex lies on the 1 cm grid; windows keep
their clearances. On about one storey in ten the solids are built too: every wall solid
is watertight with positive volume and the walls fill the wall region exactly once.
"""

from __future__ import annotations

import itertools
import math

import pytest
import shapely
from hypothesis import HealthCheck, given, settings, strategies as st

from cga.meshing.solids import floor_nodes

from dcel_checks import narrowest_room_violation, validate_plan
from floor_runs import run_make_floor
from footprint_strategies import footprints

MIN_WIDTH, MIN_AREA = 2.4, 6.0
EXAMPLES_PER_KIND = 130  # 4 kinds: 520 storeys
_EXAMPLES = itertools.count()  # solids on every tenth storey


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["rectangle", "L", "U", "T"])
@settings(max_examples=EXAMPLES_PER_KIND, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_make_floor_properties(kind, data):
    footprint = data.draw(footprints(kind), label="footprint")
    split = data.draw(st.integers(0, 12), label="split")
    seed = data.draw(st.integers(0, 2**32 - 1), label="seed")
    with_solids = next(_EXAMPLES) % 10 == 0

    child, reports = run_make_floor(
        footprint, floor=1, seed=seed, split=split, wallWidth=0.2, windows=(2, 1.2, 1.2),
        doorWidth=0.9, doorHeight=2.1, min_room_width=MIN_WIDTH, min_room_area=MIN_AREA,
        cut_range=(0.35, 0.65), same_layout=False, window_sill=0.9)
    plan = child.plan

    validate_plan(plan)
    assert plan.footprint.equals(footprint)
    n = len(plan.rooms)
    # besides the room count, make_floor may only say how many windows fit
    assert all(r.message.startswith(("made ", "placed ", "no window fits")) for r in reports)
    shortfall = [r for r in reports if r.message.startswith("made ")]
    if shortfall:
        [report] = shortfall
        assert report.stage == "make_floor" and report.level == "warning"
        assert report.message.startswith(f"made {n} rooms instead of {split + 1}")
        assert n < split + 1
    else:
        assert n == split + 1

    for v in plan.dcel.vertices:
        assert abs(v.x * 100 - round(v.x * 100)) < 1e-6 and abs(v.z * 100 - round(v.z * 100)) < 1e-6
    for room in plan.rooms if n > 1 else ():  # a single room is the footprint as drawn
        assert room.area >= MIN_AREA - 1e-9
        outline = shapely.simplify(room.polygon, 0.0)
        if len(outline.exterior.coords) == 5:  # a rectangle: its shorter side
            minx, minz, maxx, maxz = outline.bounds
            assert min(maxx - minx, maxz - minz) >= MIN_WIDTH - 1e-9, f"room {room.id} too narrow"
        else:
            assert narrowest_room_violation(room.polygon, MIN_WIDTH) == 0.0, f"room {room.id} too narrow"

    if with_solids:
        nodes = floor_nodes(plan.with_changes(is_top=True))
        walls = [node for node in nodes if node.kind == "wall"]
        assert {node.extras["wall_id"] for node in walls} <= {w.id for w in plan.walls}
        for node in nodes:
            assert node.mesh.is_watertight and node.mesh.volume > 0, node.path
        region = plan.footprint.difference(shapely.union_all([r.interior for r in plan.rooms]))
        openings = sum(o.width * o.height * 0.2 for w in plan.walls for o in w.openings)
        # the top storey's walls stand between its floor slab and its roof slab
        expected = region.area * (3.0 - 0.2 - 0.2) - openings
        assert math.isclose(sum(node.mesh.volume for node in walls), expected, rel_tol=1e-6)
