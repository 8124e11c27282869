"""The thesis' typing grammar (Fig. 6.5) builds as printed, at the thesis' 1:10 scale.

Its rule table is named by an absolute Windows path from the author's machine; the
table itself, saved as ``TestConfig.csv`` beside the grammar, is found by file name.
The table's sizes are in grammar units² (a living room of 1 unit² is 100 m² at
``units = 10``), so the lot must be large: 30 m × 20 m.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from cga.pipeline import build

ROOT = Path(__file__).resolve().parents[2]


def test_figure_6_5_grammar_builds_with_its_table_beside_it(tmp_path):
    grammar = tmp_path / "thesis.grammar"
    shutil.copy(ROOT / "tests" / "data" / "thesis" / "figure_6_5_typing.grammar", grammar)
    shutil.copy(ROOT / "rules" / "thesis_types.csv", tmp_path / "TestConfig.csv")
    scene = build(grammar, seed=1, units=10, lot="30x20", physics=False, formats=("json",),
                  out_dir=tmp_path / "out", quiet=True)
    assert len(scene.floors) == 1  # 0.8 units high, floors of 0.8: one storey of 8 m
    (plan,) = scene.floors
    assert len(plan.rooms) == 5  # split = 4
    types = {room.type for room in plan.rooms}
    assert {"Kitchen", "Livingroom", "Bedroom", "Bathroom"} <= types
    assert plan.front_door() is not None
    assert (tmp_path / "out" / "thesis.scene.json").is_file()


def _thesis_floors(tmp_path, seeds, cut_range=None):
    """The typed floors of the Fig. 6.5 grammar on the thesis' own floor: 2 × 2 units at
    ``units = 10`` (a 20 m × 20 m lot), derived without exporting."""
    from cga.evaluator import Evaluator
    from cga.lot import parse_lot
    from cga.parser import parse
    from cga.scene import Scene

    text = (ROOT / "tests" / "data" / "thesis" / "figure_6_5_typing.grammar").read_text()
    if cut_range is not None:
        text = text.replace("doorWidth,doorHeight) Floor1",
                            f"doorWidth,doorHeight, cut_range = {cut_range}) Floor1")
    shutil.copy(ROOT / "rules" / "thesis_types.csv", tmp_path / "TestConfig.csv")
    grammar = parse(text, "thesis.grammar")
    for seed in seeds:
        derivation = Evaluator(grammar, seed=seed, units=10, base_dir=tmp_path).derive(
            parse_lot("20x20"))
        yield from Scene(name="thesis", seed=seed, units=10,
                         terminals=derivation.terminals).floors


def test_thesis_table_types_the_thesis_floor_on_every_seed(tmp_path):
    # The random cuts rarely leave two 100 m² rooms; the floor is re-drawn with cuts
    # aimed at the table's areas until it types (scripts/plan_quality.py: 200 seeds).
    for plan in _thesis_floors(tmp_path, range(25)):
        types = [room.type for room in plan.rooms]
        assert {"Kitchen", "Livingroom", "Bedroom", "Bathroom"} <= set(types)
        living = next(r for r in plan.rooms if r.type == "Livingroom")
        bedroom = next(r for r in plan.rooms if r.type == "Bedroom")
        assert living.area >= 100 and bedroom.area >= 100


def test_thesis_mode_reproduces_the_mid_cut_partition(tmp_path):
    for plan in _thesis_floors(tmp_path, range(5), cut_range="(0.5, 0.5)"):
        rooms = sorted((r.polygon.bounds for r in plan.rooms))
        assert rooms == [(0.0, 0.0, 10.0, 10.0), (0.0, 10.0, 10.0, 15.0), (0.0, 15.0, 10.0, 20.0),
                         (10.0, 0.0, 20.0, 10.0), (10.0, 10.0, 20.0, 20.0)]
        assert {"Kitchen", "Livingroom", "Bedroom", "Bathroom"} <= {r.type for r in plan.rooms}
