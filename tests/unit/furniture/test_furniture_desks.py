"""Office desk layouts (``layout`` = ``perimeter``, MSU): hand-computed desk counts for
fixture rooms, the brute force only for rooms of at most four walls, no desk in a door
swing, copies named and checked like any item."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from shapely.geometry import Polygon
from shapely.geometry.polygon import orient

from cga.authoring import furnish_floor
from cga.errors import RuleTableError
from cga.model import OUTSIDE, Door, FloorPlan, FloorSettings, Room, Wall
from cga.operations.furniture import desks, solver
from cga.operations.furniture.clearance import door_strips
from cga.operations.furniture.library import ModelLibrary, default_library
from cga.operations.furniture.placement import room_edges
from cga.operations.furniture.rules import parse_furniture_rules

from furniture_checks import furniture_violations

DESK_ONLY = ("Room;Name;isAlongWall;clearanceFront;layout\n"
             "Office;desk;true;0.6;perimeter\n")
"""A desk 1.2 m wide and 0.6 m deep (the box model below) with 0.6 m free in front."""


def box_obj(path: Path, width: float, height: float, depth: float) -> None:
    x, z = width / 2, depth / 2
    corners = [(sx * x, y, sz * z) for sx in (-1, 1) for y in (0, height) for sz in (-1, 1)]
    faces = [(1, 2, 4), (1, 4, 3), (5, 7, 8), (5, 8, 6), (1, 5, 6), (1, 6, 2),
             (3, 4, 8), (3, 8, 7), (1, 3, 7), (1, 7, 5), (2, 6, 8), (2, 8, 4)]
    path.write_text("\n".join(["g body", *(f"v {a:g} {b:g} {c:g}" for a, b, c in corners),
                               *(f"f {a} {b} {c}" for a, b, c in faces)]) + "\n",
                    encoding="utf-8")


@pytest.fixture
def desk_library(tmp_path) -> ModelLibrary:
    box_obj(tmp_path / "desk.obj", 1.2, 0.75, 0.6)
    return default_library([tmp_path])  # the door leaf's model is the shipped one


@pytest.fixture
def desk_table(tmp_path) -> Path:
    path = tmp_path / "desks.csv"
    path.write_text(DESK_ONLY, encoding="utf-8")
    return path


@pytest.fixture
def office(room_plan):
    def make(width: float, depth: float, wall: int, at: float = 0.5) -> FloorPlan:
        """An office whose free floor is ``width`` × ``depth`` m (0.2 m walls), with a
        bare 0.9 m opening in ``wall`` (0 bottom, 1 right, 2 top, 3 left) at ``at`` of
        its length: its keep-out is a 0.9 m square in front of it."""
        plan = room_plan(width + 0.4, depth + 0.4, room_type="Office",
                         doors=((wall, at, "start"),), windows=())
        return plan.with_changes(doors=tuple(replace(d, leaf=False) for d in plan.doors))

    return make


def desk_count(plan: FloorPlan, table: Path, library: ModelLibrary) -> int:
    furnished = furnish_floor(plan, table, seed=0, library=library)
    assert furniture_violations(furnished, table, passage_width=0) == []
    return sum(1 for item in furnished.furniture if item.model == "desk")


# Hand counts. A desk with its front clearance is 1.2 m square; bodies may not stand in
# another desk's clearance or in the door's keep-out square.
#
# 6.0 x 1.3, door in the left wall: too shallow for two rows (1.3 < 2 x 1.2), and the
#   keep-out (0.9 m deep, 0.2..1.1 across) leaves no desk left of x = 0.9. Every desk
#   takes 1.2 m of the 5.1 m beyond: at most 4; a row along a long wall holds 4.
# 3.0 x 1.5, door in the right wall: a row desk must stay left of the keep-out
#   (x < 2.1), so rows give 1 (two rows would stand in each other's clearance); a
#   back-to-back bank from the bottom wall (desks turned, backs meeting at x = 1.2,
#   0.6..1.8) holds 2: only the brute force finds it.
# 2.6 x 1.3, door in the left wall: 1.7 m beyond the keep-out, one desk.
# 4.0 x 1.3, door in the middle of the bottom wall: no desk fits above the keep-out
#   (x 1.55..2.45, 0.9 deep, 0.4 m left), and the 1.55 m on each side take one desk
#   each (any desk takes 1.2 m of x in a room this shallow): 2.
@pytest.mark.parametrize("width, depth, wall, expected", [
    (6.0, 1.3, 3, 4),
    (3.0, 1.5, 1, 2),
    (2.6, 1.3, 3, 1),
    (4.0, 1.3, 0, 2),
])
def test_hand_computed_desk_counts(width, depth, wall, expected, office, desk_table,
                                   desk_library):
    assert desk_count(office(width, depth, wall), desk_table, desk_library) == expected


def test_the_bank_beats_the_rows_only_through_the_brute_force(office, desk_table,
                                                              desk_library, monkeypatch):
    monkeypatch.setattr(desks, "brute_force_strategies", lambda *args: [])
    assert desk_count(office(3.0, 1.5, 1), desk_table, desk_library) == 1


def l_office() -> FloorPlan:
    """An L-shaped office of six walls: 6 x 5 m with the 3 x 2.5 m top-right corner cut."""
    outline = [(0.0, 0.0), (6.0, 0.0), (6.0, 2.5), (3.0, 2.5), (3.0, 5.0), (0.0, 5.0)]
    walls = tuple(Wall(i, outline[i], outline[(i + 1) % 6], True, (0, OUTSIDE), 0.2)
                  for i in range(6))
    polygon = Polygon(outline)
    interior = polygon.buffer(-0.2, join_style="mitre")
    door = Door(0, 0, (0, OUTSIDE), walls[0].point_at(1.5), 0.9, 2.1, 0, "start", True, "front")
    return FloorPlan(0, 0.0, 3.0, polygon, FloorSettings(wall_thickness=0.2),
                     (Room(0, polygon, interior, "Office"),), walls, doors=(door,))


def test_brute_force_runs_only_for_rooms_of_four_walls_or_fewer(office, desk_table,
                                                                desk_library, monkeypatch):
    calls: list[int] = []
    real = desks.brute_force_strategies

    def spy(edges, door, width):
        calls.append(len(edges))
        return real(edges, door, width)

    monkeypatch.setattr(desks, "brute_force_strategies", spy)
    assert desk_count(l_office(), desk_table, desk_library) > 0
    assert calls == []
    desk_count(office(4.0, 3.0, 0), desk_table, desk_library)
    assert calls and set(calls) == {4}
    with pytest.raises(ValueError, match="at most 4 walls"):
        real(room_edges(l_office().room(0).interior), None, 1.2)


def test_shipped_office_desks_never_stand_in_a_door_swing(room_plan, rules_dir, library,
                                                          tmp_path):
    table = tmp_path / "office.csv"
    table.write_text((rules_dir / "furniture_office.csv").read_text(encoding="utf-8"),
                     encoding="utf-8")
    for width, depth, doors in [(4.0, 3.0, ((0, 0.3, "start"),)),
                                (5.0, 4.0, ((0, 0.5, "end"), (1, 0.7, "start"))),
                                (6.5, 3.5, ((3, 0.4, "start"),)),
                                (3.2, 5.0, ((2, 0.5, "end"),))]:
        plan = room_plan(width, depth, room_type="Office", doors=doors, windows=((2, 0.3),))
        for seed in range(3):
            furnished = furnish_floor(plan, table, seed=seed, library=library)
            names = [i.name for i in furnished.furniture if i.model == "desk"]
            assert names, (width, depth, seed)
            assert furniture_violations(furnished, table) == [], (width, depth, seed)


def test_copies_are_named_and_seated_with_their_children(room_plan, rules_dir, library):
    plan = room_plan(6.0, 5.0, room_type="Office", windows=())
    furnished = furnish_floor(plan, rules_dir / "furniture_office.csv", seed=1,
                              library=library)
    items = {i.name: i for i in furnished.furniture if not i.is_detail}
    desks_ = sorted(n for n in items if n.split("#")[0] == "desk")
    assert desks_[:2] == ["desk", "desk#2"] and len(desks_) >= 4
    for name in desks_:
        chair = items[name.replace("desk", "officechair")]
        assert chair.parent == name
    assert not [d for d in furnished.diagnostics if "desk" in d.message]


def test_a_perimeter_row_must_be_a_free_parent():
    text = ("Room;Name;isAlongWall;hasPair;PairWith;layout\n"
            "Office;desk;true;true;;\n"
            "Office;chair;false;true;desk;perimeter\n")
    with pytest.raises(RuleTableError, match="row 3, column 'layout'"):
        parse_furniture_rules(text, file="t.csv")


def side(edge) -> str:
    """Which wall of a rectangular room an edge is, by its inward normal."""
    return {(0, 1): "bottom", (-1, 0): "right", (0, -1): "top", (1, 0): "left"}[
        tuple(int(round(v)) for v in edge.normal)]


def test_the_walks_start_at_the_door_wall(office):
    """Free floor 3.6 x 2.6 from (0.2, 0.2); the door in the bottom wall at x = 1.0."""
    plan = office(3.6, 2.6, 0, at=0.25)
    edges = room_edges(plan.room(0).interior)
    (strip,) = door_strips(plan, 0)
    by_name = {s.name: s for s in desks.perimeter_strategies(edges, strip, 1.2)}
    order = {name: [side(r.edge) for r in s.runs] for name, s in by_name.items()}
    assert order["clockwise"] == ["left", "top", "right", "bottom"]
    assert all(r.from_end for r in by_name["clockwise"].runs)
    assert order["counter-clockwise"] == ["right", "top", "left", "bottom"]
    assert not any(r.from_end for r in by_name["counter-clockwise"].runs)
    # equal lengths keep the counter-clockwise walk's order
    assert order["longest first"] == ["top", "bottom", "right", "left"]
    # the line through the door (x = 1.0) leaves only the left wall's middle on its left
    assert order["left-right strict"] == ["left", "right", "top", "bottom"]
    # bottom up: each wall from its end nearest the door's wall, then nearest the line
    starts = {side(r.edge): (r.edge.end if r.from_end else r.edge.start)
              for r in by_name["left-right strict"].runs}
    assert starts == {"left": (0.2, 0.2), "right": (3.8, 0.2), "top": (0.2, 2.8),
                      "bottom": (0.2, 0.2)}
    assert not any(r.descending for r in by_name["left-right strict"].runs)  # low x, z first
    # clockwise, the walk comes up the left wall: the top wall is filled from x = 0.2
    (top,) = [r for r in by_name["clockwise"].runs if side(r.edge) == "top"]
    assert top.edge.end == (0.2, 2.8) and top.from_end and not top.descending
    assert not any(r.overhang for r in by_name["left-right strict"].runs)
    assert all(r.overhang for r in by_name["left-right relaxed"].runs)


def test_relaxed_walls_include_the_short_ones(office):
    plan = office(3.6, 1.0, 0)  # the side walls (1.0 m) are shorter than a desk
    edges = room_edges(plan.room(0).interior)
    by_name = {s.name: s for s in desks.perimeter_strategies(edges, None, 1.2)}
    assert {side(r.edge) for r in by_name["left-right strict"].runs} == {"bottom", "top"}
    assert {side(r.edge) for r in by_name["left-right relaxed"].runs} == {
        "bottom", "top", "left", "right"}
    assert len(desks.brute_force_strategies(edges, None, 1.2)) == 3 ** 2 - 1


def pilaster_office() -> FloorPlan:
    """A 4.0 x 1.15 m office whose long walls have three pilasters each (0.3 wide, 0.15
    deep, at x 1.0, 2.2 and 3.1): no straight piece of wall is as long as a desk, and
    the side walls (1.15 m) are shorter too. A bare opening in the left wall keeps
    x < 0.9 free."""
    bottom = [(0.0, 0.0)]
    for x0, x1 in ((1.0, 1.3), (2.2, 2.5), (3.1, 3.4)):
        bottom += [(x0, 0.0), (x0, 0.15), (x1, 0.15), (x1, 0.0)]
    bottom.append((4.0, 0.0))
    top = [(x, 1.15 - z) for x, z in reversed(bottom)]
    interior = Polygon(bottom + top)
    polygon = orient(interior.buffer(0.2, join_style="mitre"))  # walls counter-clockwise
    ring = list(polygon.exterior.coords)[:-1]
    walls = tuple(Wall(i, ring[i], ring[(i + 1) % len(ring)], True, (0, OUTSIDE), 0.2)
                  for i in range(len(ring)))
    left = next(w for w in walls if w.start[0] == w.end[0] == -0.2)
    door = Door(0, left.id, (0, OUTSIDE), left.point_at(left.length / 2), 0.9, 2.1, 0,
                "start", True, "front", leaf=False)
    return FloorPlan(0, 0.0, 3.0, polygon, FloorSettings(wall_thickness=0.2),
                     (Room(0, polygon, interior, "Office"),), walls, doors=(door,))


def test_the_relaxed_layout_hangs_desks_over_short_walls(desk_library, tmp_path, monkeypatch):
    """Strictly, no wall takes a desk; relaxed, a desk backs onto a pilaster and hangs
    past both its ends (not by the door: its keep-out): two desks, side by side on the
    pilasters at x 2.2..2.5 and 3.1..3.4 of one long wall (a desk on the other wall
    would stand in their clearance)."""
    table = tmp_path / "shallow.csv"
    table.write_text(DESK_ONLY.replace("0.6;perimeter", "0.25;perimeter"), encoding="utf-8")
    # 1.15 m deep: a robot's passage past the desks is not the point here
    furnished = furnish_floor(pilaster_office(), table, seed=0, passage_width=0,
                              library=desk_library)
    assert furniture_violations(furnished, table, passage_width=0) == []
    placed = [i.footprint().bounds for i in furnished.furniture if i.model == "desk"]
    assert len(placed) == 2
    for minx, minz, maxx, maxz in placed:
        assert minz == pytest.approx(0.15) or maxz == pytest.approx(1.0)  # on a pilaster
    real = desks.perimeter_strategies
    monkeypatch.setattr(desks, "perimeter_strategies",
                        lambda *a: [s for s in real(*a) if s.name != "left-right relaxed"])
    strict = furnish_floor(pilaster_office(), table, seed=0, passage_width=0,
                           library=desk_library)
    assert not [i for i in strict.furniture if i.model == "desk"]
    assert any("no wall long enough for desk" in d.message for d in strict.diagnostics)


def poses(plan: FloorPlan, table: Path, library: ModelLibrary, seed: int = 0) -> list:
    furnished = furnish_floor(plan, table, seed=seed, library=library)
    return sorted((i.name, i.model, tuple(round(v, 9) for v in i.footprint().bounds))
                  for i in furnished.furniture)


@pytest.mark.parametrize("width, depth, doors", [
    (4.0, 3.0, ((0, 0.3, "start"),)),
    (6.0, 5.0, ((0, 0.5, "end"), (1, 0.7, "start"))),
    (3.0, 1.5, ((1, 0.5, "start"),)),
    (9.0, 7.0, ((3, 0.4, "start"),)),
])
def test_pruning_keeps_the_full_search_result(width, depth, doors, room_plan, rules_dir,
                                              library, monkeypatch):
    """Skipping strategies that cannot win changes nothing: the same furniture as with
    every strategy laid out (no wall bounded but by the number of copies)."""
    plan = room_plan(width, depth, room_type="Office", doors=doors, windows=((2, 0.3),))
    table = rules_dir / "furniture_office.csv"
    pruned = poses(plan, table, library)
    monkeypatch.setattr(desks, "capacity", lambda *args: desks.MAX_COPIES)
    assert poses(plan, table, library) == pruned


def test_a_room_holding_every_copy_stops_after_the_first_strategy(room_plan, rules_dir,
                                                                   library, monkeypatch):
    """A 40 x 30 m office seats all MAX_COPIES desks along its first walk: no other
    strategy can seat more, so none is laid out."""
    laid: list[str] = []
    real = desks._Filler.run

    def spy(self, strategy):
        laid.append(strategy.name)
        return real(self, strategy)

    monkeypatch.setattr(desks._Filler, "run", spy)
    furnished = furnish_floor(room_plan(40.0, 30.0, room_type="Office"),
                              rules_dir / "furniture_office.csv", seed=0, library=library)
    assert sum(1 for i in furnished.furniture if i.model == "desk") == desks.MAX_COPIES
    assert laid == ["clockwise"]


def test_capacity_bounds_what_a_wall_seats(office, desk_table, desk_library, monkeypatch):
    """Every strategy laid out seats no more desks than its walls' capacities allow."""
    seen: list[tuple[int, int]] = []
    real = desks._Filler.run

    def spy(self, strategy):
        count, placed = real(self, strategy)
        edges = self.placer.edges
        seen.append((count, sum(desks.capacity(r, self.desk, edges) for r in strategy.runs)))
        return count, placed

    monkeypatch.setattr(desks._Filler, "run", spy)
    for width, depth, wall in [(6.0, 1.3, 3), (3.0, 1.5, 1), (5.0, 4.0, 0)]:
        desk_count(office(width, depth, wall), desk_table, desk_library)
    assert seen and all(count <= bound for count, bound in seen)
    assert any(count == bound for count, bound in seen)  # the bound is tight on some wall


def test_a_hall_sized_office_stops_the_search_at_the_test_budget(room_plan, rules_dir,
                                                                  library, monkeypatch):
    """A 15 x 12 m office seats about fifty desks but not every copy, so every strategy
    could win: the search stops after MAX_TESTS tested poses per layout, keeps its best
    layout (checked like any) and says so."""
    tests: list[int] = []
    real_lay, real_seat = desks.lay_out_desks, desks.Placer.seat_family

    def counting_lay(*args):
        tests.append(0)
        return real_lay(*args)

    def counting_seat(self, *args):
        if tests:
            tests[-1] += 1
        return real_seat(self, *args)

    monkeypatch.setattr(solver, "lay_out_desks", counting_lay)
    monkeypatch.setattr(desks.Placer, "seat_family", counting_seat)
    table = rules_dir / "furniture_office.csv"
    furnished = furnish_floor(room_plan(15.0, 12.0, room_type="Office"), table, seed=0,
                              library=library)
    assert tests and max(tests) <= desks.MAX_TESTS
    assert 40 <= sum(1 for i in furnished.furniture if i.model == "desk") < desks.MAX_COPIES
    assert furniture_violations(furnished, table) == []
    assert [d.level for d in furnished.diagnostics
            if "desk layout search stopped" in d.message] == ["info"]
