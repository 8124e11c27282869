"""End to end: a storey split into wings, make_floor on each (issue 20).

Seen first: ``split("x")`` into two wings and ``make_floor`` on each failed with "two
scene nodes are both named 'floor0/slab'". Now the wings of a storey are one plan: node
names are unique, the footprint is the union, no window looks into the neighbouring
wing, the wings are joined inside (the room graph is connected without the outside),
the stair still joins the storeys and both checks pass. Checked with shapely and
networkx on the built scene.
"""

from __future__ import annotations

import csv
from collections import Counter
from pathlib import Path

import networkx as nx
import pytest
from shapely.geometry import LineString, Point

from cga.cli import main
from cga.model import OUTSIDE
from cga.pipeline import build

WINGS = """\
units = 1;
Lot: rectangle(24, 10)
Rules:
Lot --> extrude(6) Body
Body --> repeated_split("Y", 3){Storey}
Storey --> split("x"){ ~1 : Wing | ~1 : Wing }
Wing --> make_floor(5, 0.2, 2>1.2>1.2, 0.9, 2.1, corridor = "spine", corridor_width = 1.6, corridor_position = 0.42, min_room_width = 2, min_room_area = 4) Floor
Floor --> case floor == 0 : type_rooms("house_types.csv") Typed
        | else : type_rooms("house_upper_types.csv") Typed
Typed --> add_furniture("furniture_house.csv", 0.2>1.2>1.2, 0.9, 2.1, 10, 20) Furnished
"""
PARTY = LineString([(12, 0), (12, 10)])
RULES = Path(__file__).resolve().parents[2] / "rules"


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    grammar = tmp_path_factory.mktemp("wings") / "wings.grammar"
    grammar.write_text(WINGS, encoding="utf-8")
    return build(grammar, seed=0, formats=(), quiet=True)


def test_node_names_are_unique(scene):
    counts = Counter(n.path for n in scene.nodes)
    assert not [path for path, k in counts.items() if k > 1]


def test_one_plan_per_storey_over_both_wings(scene):
    assert [p.index for p in scene.floors] == [0, 1]
    for plan in scene.floors:
        assert plan.footprint.area == pytest.approx(240.0)
        assert sum(r.polygon.area for r in plan.rooms) == pytest.approx(240.0)
        assert len({r.id for r in plan.rooms}) == len(plan.rooms)
        assert all(Point(w.position).distance(PARTY) > 0.05 for w in plan.windows)
    assert len(scene.floors[0].stairs) == 1  # the stair still joins the storeys


def test_the_wings_are_one_building_inside(scene):
    for plan in scene.floors:
        graph = nx.Graph()
        graph.add_nodes_from(r.id for r in plan.rooms)
        graph.add_edges_from(d.rooms for d in plan.doors if OUTSIDE not in d.rooms)
        assert nx.is_connected(graph), plan.index
        assert any(d.rooms[0] != OUTSIDE and d.rooms[1] != OUTSIDE
                   and Point(d.position).distance(PARTY) < 1e-6 for d in plan.doors)
    assert scene.floors[0].front_door() is not None


def test_every_door_is_in_the_wall_between_its_rooms(scene):
    """Where the wings meet, the two party walls back to back are one wall between the
    rooms on either side: the doorway joining the wings names a wall between the rooms
    it joins, and every door opening in a wall is a door of that wall (checked on the
    walls' segments and openings, not on how the join records them)."""
    for plan in scene.floors:
        walls = {w.id: w for w in plan.walls}
        for door in plan.doors:
            wall = walls[door.wall]
            assert sorted(wall.rooms) == sorted(door.rooms), (plan.index, door.id)
            assert wall.segment().distance(Point(door.position)) < 1e-6
        for wall in plan.walls:
            for opening in (o for o in wall.openings if o.kind == "door"):
                at = Point(wall.point_at(opening.center))
                assert any(d.wall == wall.id and at.distance(Point(d.position)) < 0.02
                           for d in plan.doors), (plan.index, wall.id, opening)
        on_party = [w for w in plan.walls if PARTY.buffer(1e-6).covers(w.segment())]
        assert on_party and all(not w.outer and OUTSIDE not in w.rooms for w in on_party)
        assert sum(w.length for w in on_party) == pytest.approx(PARTY.length)


def test_both_checks_pass(scene):
    assert scene.checks["physics"].passed, scene.checks["physics"].summary()
    assert scene.checks["navigability"].passed, scene.checks["navigability"].summary()


def test_wings_that_do_not_touch_are_refused(tmp_path, capsys):
    grammar = tmp_path / "apart.grammar"
    grammar.write_text('Lot: rectangle(26, 10)\nRules:\nLot --> extrude(3) Storey\n'
                       'Storey --> split("x"){ ~1 : Wing | 2 : Yard | ~1 : Wing }\n'
                       'Wing --> make_floor(3, 0.2, 2>1.2>1.2, 0.9, 2.1) Floor\n',
                       encoding="utf-8")
    assert main(["build", str(grammar), "--no-physics", "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "do not touch" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()


OFFICE_WINGS = """\
units = 1;
Lot: rectangle(28, 10)
Rules:
Lot --> extrude(6.6) Body
Body --> repeated_split("Y", 3.3){Storey}
Storey --> split("x"){ ~1 : WingA | ~1 : WingB }
WingA --> make_floor(6, 0.15, 3>1.5>1.5, 1.0, 2.2, corridor = "spine", corridor_width = 1.8, min_room_width = 2, min_room_area = 4) Floor
WingB --> make_floor(6, 0.15, 3>1.5>1.5, 1.0, 2.2, corridor = "spine", corridor_width = 1.8, min_room_width = 2, min_room_area = 4, stair = "none") Floor
Floor --> type_rooms("office_types.csv") Typed
"""


def test_front_doors_face_to_face_make_one_doorway_with_one_opening(tmp_path):
    """Both wings put their front doors in the party wall, face to face: they become one
    doorway, with one opening in the wall the two party walls make there (the second
    door's own opening used to stay beside the one cut for the first)."""
    grammar = tmp_path / "office_wings.grammar"
    grammar.write_text(OFFICE_WINGS, encoding="utf-8")
    party = LineString([(14, 0), (14, 10)])
    for seed in range(3):
        scene = build(grammar, seed=seed, formats=(), physics=False, quiet=True)
        for plan in scene.floors:
            for wall in plan.walls:
                spans = sorted((o.center - o.width / 2, o.center + o.width / 2)
                               for o in wall.openings)
                assert all(hi <= lo + 1e-6 for (_, hi), (lo, _) in zip(spans, spans[1:])), \
                    f"seed {seed}, floor {plan.index}: openings overlap on wall {wall.id}"
            on_party = [w for w in plan.walls if party.buffer(1e-6).covers(w.segment())]
            cuts = sorted(round(w.point_at(o.center)[1], 6) for w in on_party
                          for o in w.openings if o.kind == "door")
            doorways = [d for d in plan.doors if OUTSIDE not in d.rooms
                        and Point(d.position).distance(party) < 1e-6]
            assert doorways and len(cuts) == len(doorways), (seed, plan.index, cuts)
            assert cuts == sorted(round(d.position[1], 6) for d in doorways), (seed, cuts)


FRONT_AND_BACK = """\
units = 1;
Lot: rectangle(14, 16)
Rules:
Lot --> extrude(6) Body
Body --> repeated_split("Y", 3){Storey}
Storey --> split("z"){ ~1 : Front | ~1 : Back }
Front --> make_floor(5, 0.2, 2>1.2>1.3, 0.9, 2.1, corridor = "spine", corridor_width = 1.6, min_room_width = 2, min_room_area = 4) Floor
Back --> make_floor(5, 0.2, 2>1.2>1.3, 0.9, 2.1, corridor = "spine", corridor_width = 1.6, min_room_width = 2, min_room_area = 4, stair = "none") Floor
Floor --> case floor == 0 : type_rooms("house_types.csv") Typed
        | else : type_rooms("house_upper_types.csv") Typed
Typed --> add_furniture("furniture_house.csv", 0.2>1.2>1.3, 0.9, 2.1, 10, 20) Furnished
"""


NEEDS_WINDOW = {row["Type"] for table in ("house_types.csv", "house_upper_types.csv")
                for row in csv.DictReader(
                    [line for line in (RULES / table).read_text(encoding="utf-8").splitlines()
                     if not line.startswith("#")], delimiter=";")
                if row["needsWindow"].strip().lower() in ("1", "true")}
"""The types the house tables say need a window, read with the csv module."""


def _building_graph(scene) -> nx.Graph:
    """Rooms of every floor as ``(floor, room)``, joined by the doors and the stairs."""
    graph = nx.Graph()
    for plan in scene.floors:
        graph.add_nodes_from((plan.index, r.id) for r in plan.rooms)
        graph.add_edges_from(((plan.index, a), (plan.index, b)) for a, b in
                             (d.rooms for d in plan.doors) if OUTSIDE not in (a, b))
        for stair in plan.stairs:
            graph.add_edge(*zip(stair.floors, stair.rooms))
    return graph


def test_wings_whose_corridors_do_not_face_are_joined_on_every_floor(tmp_path):
    """Two wings front to back whose spines run parallel to the wall they share: no
    corridor faces the other wing. Each floor used to stay two parts inside, joined only
    through the ground floor's front doors, so the back wing's upper rooms could not be
    reached at all. Now a doorway joins them on every floor: every room of the building is
    reached from the front doors through doors and the stair. A private room is the way
    into others only above the ground floor, where no other room lines the wall the wings
    share, and then a warning names it."""
    grammar = tmp_path / "front_and_back.grammar"
    grammar.write_text(FRONT_AND_BACK, encoding="utf-8")
    for seed in range(3):
        scene = build(grammar, seed=seed, formats=(), physics=False, quiet=True)
        graph = _building_graph(scene)
        graph.add_edges_from(((0, r), "outside") for d in scene.floors[0].doors if d.is_front
                             for r in d.rooms if r != OUTSIDE)
        assert nx.is_connected(graph), seed
        warned = {d.floor for d in scene.all_diagnostics()
                  if d.level == "warning" and "are joined through" in d.message}
        for plan in scene.floors:
            for room in (r for r in plan.rooms if r.private):
                rest = graph.subgraph(set(graph.nodes) - {(plan.index, room.id)})
                if not nx.is_connected(rest):
                    assert plan.index > 0 and plan.index in warned, (seed, plan.index, room.id)
            lit = {w.room for w in plan.windows}
            said = " ".join(d.message for d in plan.diagnostics if d.level == "warning")
            for room in plan.rooms:  # a room left without a window is named in a warning
                if room.type in NEEDS_WINDOW and room.id not in lit:
                    assert room.label in said or f"room {room.id} ({room.type})" in said, \
                        (seed, plan.index, room.label)


def test_two_storeys_with_one_number_are_refused_with_the_reason(tmp_path, capsys):
    """A tall ground floor cut off with split("y") is floor 0, and so is the first storey
    of the repeated_split above it: the error says why, not that wings stand at different
    heights (none were made)."""
    grammar = tmp_path / "tall_ground.grammar"
    grammar.write_text(
        'Lot: rectangle(16, 11)\nRules:\nLot --> extrude(10) Mass\n'
        'Mass --> split("y"){ 4 : Ground | ~1 : Uppers }\n'
        'Uppers --> repeated_split("Y", 3){ Storey }\n'
        'Ground --> make_floor(5, 0.2, 2>1.2>1.3, 0.9, 2.1) Floor\n'
        'Storey --> make_floor(5, 0.2, 2>1.2>1.3, 0.9, 2.1) Floor\n', encoding="utf-8")
    assert main(["build", str(grammar), "--no-physics", "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "two storeys, one above the other, are both floor 0 (0–4 m and 4–7 m)" in err
    assert "wings" not in err and "Traceback" not in err
