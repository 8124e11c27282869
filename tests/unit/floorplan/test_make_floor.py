"""The make_floor operation: arguments, the plan it attaches, diagnostics, errors."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon, box

from cga.errors import DerivationError
from cga.evaluator import derive
from cga.registry import OperationRegistry
from cga.operation import OperationContext
from cga.meshing.solids import floor_nodes
from cga.operations.make_floor import MakeFloor
from cga.parser import parse
from cga.shape import Face, Mass, Shape
from dcel_checks import validate_plan

def storey(footprint=box(0, 0, 14, 10), base=3.0, height=3.0, floor=1, symbol="UpperFloor", path=None):
    mass = Mass(footprint, base, height)
    return Shape(symbol, path or ("Lot", "Body", f"{symbol}[{floor}]"), mass.scope(), mass,
                 {"floor": floor, "index": floor})


def args(split=4, wall=0.2, windows=(2, 1.2, 1.2), door=(0.9, 2.1), **kw):
    out = {"split": split, "wallWidth": wall, "windows": windows, "doorWidth": door[0],
           "doorHeight": door[1]}
    defaults = {p.name: p.default for p in MakeFloor.params if not p.required}
    return defaults | out | kw


def context(seed=0, rng_seed=0):
    reports = []
    ctx = OperationContext(rng=np.random.default_rng(rng_seed), units=1.0,
                           resolve=lambda p, k="rules": p, report=reports.append, span=None,
                           successor_count=1, seed=seed)
    return ctx, reports


def test_registry_entry_is_make_floor():
    assert isinstance(OperationRegistry()["make_floor"], MakeFloor)


def test_apply_attaches_a_plan_and_keeps_the_shape():
    shape = storey()
    ctx, reports = context()
    [child] = MakeFloor().apply(shape, args(), ctx)
    assert child.successor == 0 and child.geometry is shape.geometry and child.scope == shape.scope
    plan = child.plan
    validate_plan(plan)
    assert (plan.index, plan.elevation, plan.height, plan.is_top) == (1, 3.0, 3.0, False)
    assert len(plan.rooms) == 5
    # short wall segments take fewer windows than asked: said, as an info, nothing more
    assert all(r.level == "info" and "windows" in r.message for r in reports)
    s = plan.settings
    assert (s.wall_thickness, s.windows_per_wall, s.window_width, s.window_height, s.window_sill,
            s.door_width, s.door_height) == (0.2, 2, 1.2, 1.2, 0.9, 0.9, 2.1)
    assert plan.footprint.equals(box(0, 0, 14, 10))
    assert plan.doors == () and len(plan.windows) > 0
    assert all(o.kind == "window" for w in plan.walls for o in w.openings)


def test_keyword_options_reach_the_partition():
    ctx, _ = context()
    [child] = MakeFloor().apply(storey(), args(split=3, min_room_width=4.0, min_room_area=20.0,
                                               cut_range=(0.49, 0.51), window_sill=1.0), ctx)
    plan = child.plan
    assert all(r.area >= 20.0 for r in plan.rooms)
    assert all(min(b[2] - b[0], b[3] - b[1]) >= 4.0 for b in (r.polygon.bounds for r in plan.rooms))
    assert {w.sill for w in plan.windows} == {1.0}
    assert any(abs(w.start[0] - 7.0) <= 0.07 for w in plan.walls if not w.outer)  # first cut


def test_cut_range_one_half_is_the_thesis_partition():
    ctx, reports = context()
    [child] = MakeFloor().apply(storey(), args(split=4, cut_range=(0.5, 0.5)), ctx)
    rooms = sorted(r.polygon.bounds for r in child.plan.rooms)
    # Algorithm 8: z = 5 first, then x = 7 in one half, z = 7.5 in a quarter, x = 7 in the
    # other half: leaves in the order they were made, each across its maker's axis
    assert rooms == [(0, 0, 7, 5), (0, 5, 7, 7.5), (0, 7.5, 7, 10), (7, 0, 14, 5), (7, 5, 14, 10)]
    assert child.plan.layout is None  # nothing to re-draw
    assert not [r for r in reports if r.level != "info"]


def test_each_floor_its_own_layout_unless_same_layout():
    def layout(shape, seed, rng_seed, same):
        ctx, _ = context(seed=seed, rng_seed=rng_seed)
        [child] = MakeFloor().apply(shape, args(split=5, same_layout=same), ctx)
        return sorted(round(r.area, 6) for r in child.plan.rooms)

    first, second = storey(floor=1), storey(floor=2, base=6.0)
    assert layout(first, 0, 1, False) != layout(second, 0, 2, False)
    assert layout(first, 0, 1, True) == layout(second, 0, 2, True)
    assert layout(first, 0, 1, True) != layout(first, 1, 1, True)  # still follows the seed
    other_rule = storey(floor=2, base=6.0, symbol="GroundFloor")
    assert layout(first, 0, 1, True) != layout(other_rule, 0, 1, True)


def test_unreachable_split_is_reported():
    ctx, reports = context()
    [child] = MakeFloor().apply(storey(box(0, 0, 6, 5), floor=2), args(split=6), ctx)
    n = len(child.plan.rooms)
    assert n < 7
    [d] = [r for r in reports if r.level != "info"]
    assert (d.level, d.stage, d.floor) == ("warning", "make_floor", 2)
    assert d.message.startswith(f"made {n} rooms instead of 7: ")
    assert "narrower than 2.40 m" in d.message


def test_l_shaped_storey_and_collinear_footprint_vertices():
    footprint = Polygon([(0, 0), (7, 0), (14, 0), (14, 6), (8, 6), (8, 10), (0, 10)])
    ctx, _ = context()
    [child] = MakeFloor().apply(storey(footprint), args(split=5), ctx)
    validate_plan(child.plan)
    assert (7.0, 0.0) not in [v.point for v in child.plan.dcel.vertices[:6]]
    assert child.plan.footprint.equals(footprint)


@pytest.mark.parametrize("shape, kwargs, message", [
    (storey(height=2.5), {"windows": (1, 1.2, 1.5)}, "windows do not fit"),
    (storey(height=2.2), {"windows": (0, 1.2, 1.2)}, "doorHeight 2.1 does not fit"),
    (storey(), {"wall": 0.0}, "wallWidth must be positive"),
    (storey(), {"windows": (1, 0.0, 1.2)}, "windowWidth must be positive"),
    (storey(), {"wall": 1.5}, "more than twice wallWidth"),
    (storey(), {"cut_range": (0.6, 0.4)}, "cut_range"),
    (storey(), {"min_room_area": -1.0}, "min_room_area"),
    (storey(box(0, 0, 10, 10).difference(box(4, 4, 6, 6))), {}, "without holes"),
    (storey(box(0, 0, 1e-9, 1e-9)), {}, "cannot cut this footprint into rooms"),
    (storey(Polygon([(0, 0), (14, 0), (14, 10), (7.00000001, 10.5), (7, 10.5), (0, 10)])), {},
     "cannot cut this footprint into rooms"),
])
def test_user_mistakes_raise_derivation_errors(shape, kwargs, message):
    ctx, _ = context()
    a = args(**{k: v for k, v in kwargs.items() if k in ("wall", "windows")})
    a |= {k: v for k, v in kwargs.items() if k not in ("wall", "windows")}
    with pytest.raises(DerivationError, match=message):
        MakeFloor().apply(shape, a, ctx)


def test_faces_are_refused():
    face = Face(((0, 0, 0), (1, 0, 0), (1, 0, 1)), "top")
    shape = Shape("F", ("F",), storey().scope, face)
    with pytest.raises(DerivationError, match="storey"):
        MakeFloor().apply(shape, args(), context()[0])


TWO_STOREYS = """
Lot: rectangle(14, 10)
Variables:
  wallWidth = 0.2;
Rules:
Lot --> extrude(6) Body
Body --> repeated_split("Y", 3){GroundFloor, UpperFloor}
GroundFloor --> make_floor(5, wallWidth, 2>1.2>1.2, 0.9, 2.1) Floor
UpperFloor --> make_floor(4, wallWidth, 2>1.2>1.2, 0.9, 2.1, min_room_area = 8, same_layout = true) Floor
"""


def test_storeys_through_the_evaluator():
    grammar = parse(TWO_STOREYS, "two_storeys.grammar")
    for seed in range(6):
        result = derive(grammar, seed=seed)
        plans = sorted((s.plan for s in result.terminals), key=lambda p: p.index)
        assert [(p.index, p.elevation, p.height) for p in plans] == [(0, 0.0, 3.0), (1, 3.0, 3.0)]
        # split + 1 rooms, plus the stair core reserved in the same place on both storeys
        assert [len(p.rooms) for p in plans] == [7, 6]
        cores = [p.room(p.core_room) for p in plans]
        assert [(c.type, c.circulation) for c in cores] == [("Stair", True)] * 2
        assert cores[0].polygon.symmetric_difference(cores[1].polygon).area < 1e-9
        assert [d for d in result.diagnostics if d.level != "info"] == []
        for p in plans:
            validate_plan(p)


@pytest.mark.parametrize("footprint", [
    Polygon([(0, 0), (14, 0), (11, 10), (3, 10)]),                     # trapezoid
    Polygon([(3, 0), (11, 0), (14, 5), (11, 10), (3, 10), (0, 5)]),    # hexagon
])
def test_convex_footprints_with_slanted_walls(footprint):
    for seed in range(3):
        ctx, _ = context(rng_seed=seed)
        [child] = MakeFloor().apply(storey(footprint), args(split=5), ctx)
        plan = child.plan
        validate_plan(plan)
        walls = [n for n in floor_nodes(plan) if n.kind == "wall"]
        assert len(walls) == len(plan.walls)
        assert all(n.mesh.is_watertight and n.mesh.volume > 0 for n in walls)
        region = footprint.difference(shapely.union_all([r.interior for r in plan.rooms]))
        openings = sum(o.width * o.height * 0.2 for w in plan.walls for o in w.openings)
        assert sum(n.mesh.volume for n in walls) == pytest.approx(region.area * 2.8 - openings, rel=1e-6)


@pytest.mark.parametrize("mode, footprint", [
    ("spine", box(0, 0, 20, 12)),
    ("hall", box(0, 0, 14, 10)),
    ("centre_line", Polygon([(0, 0), (20, 0), (20, 7), (9, 7), (9, 16), (0, 16)])),
])
def test_corridor_modes_carve_one_circulation_room_and_split_plus_one_rooms(mode, footprint):
    for seed in range(5):
        ctx, reports = context(rng_seed=seed)
        [child] = MakeFloor().apply(storey(footprint), args(split=5, corridor=mode), ctx)
        plan = child.plan
        validate_plan(plan)
        circulation = [r for r in plan.rooms if r.circulation]
        assert len(circulation) == 1 and circulation[0].id == 0
        assert len(plan.rooms) - 1 == 6 and not [r for r in reports if r.level != "info"]
        hall = circulation[0].polygon
        for room in plan.rooms[1:]:  # every room keeps a door's length of wall on it
            assert room.polygon.boundary.intersection(hall.boundary).length >= 0.9 + 2 * 0.3 - 1e-9


def test_a_spine_too_shallow_for_two_sides_runs_along_one_wall_with_a_warning():
    # 6 m deep: a 1.2 m spine and 2.5 m rooms on both sides need 6.2 m
    ctx, reports = context()
    [child] = MakeFloor().apply(storey(box(0, 0, 16, 6)),
                                args(split=4, corridor="spine", corridor_position=0.7), ctx)
    plan = child.plan
    validate_plan(plan)
    (hall,) = [r.polygon for r in plan.rooms if r.circulation]
    assert hall.equals(box(0, 4.8, 16, 6))  # along the far wall: position leans that way
    assert all(r.polygon.bounds[3] <= 4.8 + 1e-9 for r in plan.rooms if not r.circulation)
    assert any("single-loaded" in r.message and r.level == "warning" for r in reports)


def test_rooms_per_side_make_equal_offices():
    ctx, _ = context()
    [child] = MakeFloor().apply(storey(box(0, 0, 20, 12)),
                                args(split=7, corridor="spine", n_left=4, n_right=4), ctx)
    areas = sorted(round(r.area, 6) for r in child.plan.rooms if not r.circulation)
    assert areas == [27.0] * 8


@pytest.mark.parametrize("kw, message", [
    ({"corridor": "ring"}, "corridor must be one of"),
    ({"corridor": "spine", "corridor_width": 1.0}, "at least 1.2"),
    ({"corridor": "spine", "corridor_position": 1.5}, "between 0 and 1"),
    ({"corridor": "hall", "n_left": 2}, "n_left and n_right"),
    ({"corridor": "spine", "min_room_depth": 11}, "cannot carve a spine corridor"),
])
def test_bad_corridor_options_are_derivation_errors(kw, message):
    ctx, _ = context()
    with pytest.raises(DerivationError, match=message) as info:
        MakeFloor().apply(storey(box(0, 0, 20, 12)), args(**kw), ctx)
    # a corridor that does not fit is no matter of micrometre corners
    assert "micrometre" not in str(info.value)


def test_only_partition_errors_become_user_errors(monkeypatch):
    import cga.operations.floorplan.bsp as bsp  # make_floor imports it in apply
    from cga.operations.floorplan.errors import PartitionError

    def refuses(*args, **kwargs):
        raise PartitionError("the region's boundary touches itself")

    monkeypatch.setattr(bsp, "partition", refuses)
    with pytest.raises(DerivationError, match="cannot cut this footprint.*touches itself"):
        MakeFloor().apply(storey(), args(), context()[0])

    def buggy(*args, **kwargs):
        raise ValueError("operands could not be broadcast together")

    monkeypatch.setattr(bsp, "partition", buggy)
    with pytest.raises(ValueError, match="broadcast") as caught:
        MakeFloor().apply(storey(), args(), context()[0])
    assert not isinstance(caught.value, DerivationError)


def test_shortfall_counts_rooms_without_the_hall():
    """``split + 1`` rooms besides the circulation: the warning counts them the same way."""
    ctx, reports = context(seed=6, rng_seed=6)  # a seed that falls one room short
    [child] = MakeFloor().apply(storey(box(0, 0, 14, 10)), args(
        split=9, min_room_width=2.0, min_room_area=4.0, corridor="spine", corridor_width=1.6,
        corridor_position=0.42), ctx)
    rooms = sum(not r.circulation for r in child.plan.rooms)
    [d] = [r for r in reports if r.level == "warning"]
    assert rooms < 10 and d.message.startswith(f"made {rooms} rooms instead of 10: ")


def test_equal_rooms_on_both_sides_leave_the_stair_no_place_and_the_error_says_so(tmp_path):
    """n_left and n_right fill both sides of the spine with fixed rooms the stair core
    keeps clear of: the error names them, not only the lot and the stair's size."""
    from cga.errors import CGAError
    from cga.pipeline import build

    grammar = tmp_path / "equal.grammar"
    grammar.write_text(
        "units = 1;\nLot: rectangle(24, 11)\nRules:\nLot --> extrude(6.6) Body\n"
        "Body --> repeated_split(\"Y\", 3.3){Storey}\n"
        "Storey --> make_floor(9, 0.15, 3>1.5>1.5, 1.0, 2.2, corridor = \"spine\", "
        "corridor_width = 1.8, n_left = 5, n_right = 5) Floor\n", encoding="utf-8")
    with pytest.raises(CGAError, match="no place for a U stair core") as info:
        build(grammar, seed=0, formats=(), physics=False, quiet=True)
    assert "n_left and n_right fill both sides" in str(info.value)


def test_a_room_kept_whole_by_its_hall_contact_says_so():
    """A straight stair core along a short hall leaves the room beyond it a few metres
    of hall: it is large enough to halve, but not so that both halves keep their
    contact, and the shortfall says that rather than blaming width or area."""
    from cga.operations.floorplan.bsp import FixedFace, partition

    hall = [(4.0, 0.0), (5.6, 0.0), (5.6, 9.0), (4.0, 9.0)]
    core = [(5.6, 3.0), (7.0, 3.0), (7.0, 9.0), (5.6, 9.0)]  # beside the hall, not on it
    result = partition([(0, 0), (12, 0), (12, 9), (0, 9)], 8, np.random.default_rng(0),
                       fixed=[FixedFace(hall, circulation=True, kind="hall"),
                              FixedFace(core, kind="core")],
                       min_width=2.0, min_area=4.0, min_contact=1.5)
    assert result.shortfall is not None
    assert "keep 1.50 m of wall on a hall or corridor" in result.shortfall


def test_a_deep_floor_on_parallel_spines_is_noted_for_the_evaluator():
    """The evaluator derives a grammar once more without parallel spines when its rooms
    cannot be typed on them; make_floor notes where it laid them and obeys the switch."""
    from cga.operation import PARALLEL_SPINES_USED

    deep = storey(box(0, 0, 30, 20))
    corridors = {}
    for allowed in (True, False):
        ctx, _ = context()
        ctx.parallel_spines = allowed
        [child] = MakeFloor().apply(deep, args(split=12, corridor="spine"), ctx)
        validate_plan(child.plan)
        assert ctx.cache.get(PARALLEL_SPINES_USED, False) is allowed
        (corridors[allowed],) = [r.polygon for r in child.plan.rooms if r.circulation]
    assert not corridors[True].equals(corridors[True].envelope)  # two spines joined across
    assert corridors[False].equals(box(0, 9.4, 30, 10.6))  # one 1.2 m spine in the middle
    ctx, _ = context()
    MakeFloor().apply(storey(box(0, 0, 20, 12)), args(split=7, corridor="spine"), ctx)
    assert PARALLEL_SPINES_USED not in ctx.cache  # 12 m deep: one spine suffices
