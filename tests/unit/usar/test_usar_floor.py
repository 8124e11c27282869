"""usar_floor as a grammar operation: a typed floor with bare doorways, every room
reachable; clear errors for footprints and values it cannot take."""

from __future__ import annotations

import networkx as nx
import pytest
from shapely.geometry import Point

from cga.errors import DerivationError
from cga.model import OUTSIDE
from cga.pipeline import build

GRAMMAR = """\
Lot: rectangle({w}, {d})
Variables:
  difficulty = 5;
Rules:
Lot --> extrude(3) Storey
Storey --> usar_floor(difficulty, "usar_rooms.csv", 0.15, 0.9, 2.1{extra}) Grid
"""


def _floor(tmp_path, w=19.2, d=14.4, extra="", **overrides):
    path = tmp_path / "grid.grammar"
    path.write_text(GRAMMAR.format(w=w, d=d, extra=extra))
    scene = build(path, formats=(), physics=False, quiet=True, overrides=overrides or None)
    return scene.floors[0]


@pytest.mark.parametrize("difficulty", ["0", "5", "10"])
def test_floor_is_typed_with_bare_doorways_and_reachable(tmp_path, difficulty):
    plan = _floor(tmp_path, difficulty=difficulty)
    assert all(room.type for room in plan.rooms)
    assert {r.type for r in plan.rooms if r.circulation} <= {"Hallway", "OpenArea"}
    front = [d for d in plan.doors if d.is_front]
    assert len(front) == 1 and front[0].leaf and OUTSIDE in front[0].rooms
    assert all(not d.leaf and d.passable for d in plan.doors if not d.is_front)
    graph = nx.Graph(d.rooms for d in plan.doors)
    graph.add_nodes_from(r.id for r in plan.rooms)
    assert nx.is_connected(graph)
    assert plan.entry in front[0].rooms
    # every opening lies in a wall between the rooms it joins, inside the wall
    for door in plan.doors:
        wall = plan.wall(door.wall)
        assert set(door.rooms) == set(wall.rooms)
        assert any(abs(o.center - wall.segment().project(Point(door.position))) < 1e-6
                   and o.width == pytest.approx(door.width) for o in wall.openings)


def test_cells_fill_the_footprint(tmp_path):
    plan = _floor(tmp_path, w=20, d=15, extra=", cell = 2.5")
    assert sum(r.polygon.area for r in plan.rooms) == pytest.approx(300)


@pytest.mark.parametrize("w, d, extra, message", [
    (7, 20, "", "4 to 40 cells per side"),
    (19.2, 14.4, ", cell = 1", "cell must be at least 1.2"),
    (19.2, 14.4, ", cell = 1.1", "cell must be at least"),
])
def test_refusals(tmp_path, w, d, extra, message):
    with pytest.raises(DerivationError, match=message):
        _floor(tmp_path, w=w, d=d, extra=extra)


def test_difficulty_outside_the_range(tmp_path):
    with pytest.raises(DerivationError, match="from 0 to 10"):
        _floor(tmp_path, difficulty="10.5")


def test_footprint_must_be_a_rectangle(tmp_path):
    path = tmp_path / "l.grammar"
    path.write_text(GRAMMAR.format(w=19.2, d=14.4, extra="").replace(
        "Lot: rectangle(19.2, 14.4)", "Lot: polygon((0,0),(20,0),(20,10),(10,10),(10,20),(0,20))"))
    with pytest.raises(DerivationError, match="rectangular footprint"):
        build(path, formats=(), physics=False, quiet=True)
