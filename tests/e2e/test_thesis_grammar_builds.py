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
