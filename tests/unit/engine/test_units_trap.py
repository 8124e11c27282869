"""Units a user cannot mix up (issue 20): ``--lot`` sizes state their unit, rule tables
declare theirs, and a build whose sizes look scaled by the wrong factor says so.

The failures first seen: under ``units = 10`` the shipped metre tables were multiplied
by 100 ("Livingroom needs ≥ 1400.0 m²"), and the thesis' floor ``--lot 2x2`` failed
deep in the typing ("no outer wall long enough for a 0.90 m front door") without naming
the unit mix-up.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from cga.cli import main
from cga.errors import RuleTableError
from cga.lot import read_lot
from cga.pipeline import build
from cga.operations.furniture.rules import parse_furniture_rules
from cga.operations.roomtyping.rules import parse_rule_table

ROOT = Path(__file__).resolve().parents[3]
RULES = ROOT / "rules"

# A storey at the thesis' scale: ten metres per grammar unit, 3 m high, thesis-sized
# walls, windows and door (0.09 units = a 0.9 m door).
TENTHS = """units = 10;
Rules:
Lot --> extrude(0.3) Storey
Storey --> make_floor(3, 0.02, 1>0.12>0.12, 0.09, 0.21) Floor
Floor --> type_rooms("{table}") Typed
"""


def grammar(tmp_path: Path, table: str) -> Path:
    path = tmp_path / "tenths.grammar"
    path.write_text(TENTHS.format(table=table))
    return path


def messages(scene) -> list[str]:
    return [d.message for d in scene.all_diagnostics()]


@pytest.mark.parametrize("text, unit, stated, bounds", [
    ("14x10", "m", False, (0, 0, 14, 10)),
    ("14x10m", "m", True, (0, 0, 14, 10)),
    ("14 x 10 M", "m", True, (0, 0, 14, 10)),
    ("1.4x1u", "grammar", True, (0, 0, 14, 10)),
    ("rectangle(1.4, 1)u", "grammar", True, (0, 0, 14, 10)),
    ("polygon((0,0),(1.4,0),(1.4,1),(0,1))u", "grammar", True, (0, 0, 14, 10)),
])
def test_lot_sizes_carry_their_unit(text, unit, stated, bounds):
    lot = read_lot(text, units=10)
    assert (lot.unit, lot.unit_stated) == (unit, stated)
    assert lot.polygon.bounds == pytest.approx(bounds)


def test_lot_help_says_metres_and_grammar_units(capsys):
    with pytest.raises(SystemExit):
        main(["build", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "14x10 (metres" in text and "1.4x1u (grammar units)" in text


def test_thesis_floor_in_metres_names_the_unit_mix_up(tmp_path, capsys):
    """The Fig. 6.5 grammar on the thesis' floor, 2 × 2 units, given as --lot 2x2:
    2 m × 2 m."""
    shutil.copy(ROOT / "tests" / "data" / "thesis" / "figure_6_5_typing.grammar", tmp_path)
    shutil.copy(RULES / "thesis_types.csv", tmp_path / "TestConfig.csv")
    status = main(["build", str(tmp_path / "figure_6_5_typing.grammar"), "--units", "10",
                   "--lot", "2x2", "--no-physics", "--quiet", "--out", str(tmp_path / "out")])
    err = " ".join(capsys.readouterr().err.split())
    assert status == 2
    # the failure first seen ...
    assert "no outer wall long enough for a 0.90 m front door" in err
    # ... now says how the table's sizes and the lot were read, and how to fix the lot
    assert "TestConfig.csv are read in grammar units² (× 100 m² each at units = 10)" in err
    assert "--lot '2x2' was read in metres (a 2 m × 2 m lot, 4 m²)" in err
    assert "units of 10 m" in err and "--lot 2x2u" in err and "--lot 2x2m" in err
    assert main(["build", str(tmp_path / "figure_6_5_typing.grammar"), "--units", "10",
                 "--lot", "2x2u", "--no-physics", "--quiet",
                 "--out", str(tmp_path / "out")]) == 0


def test_thesis_floor_in_grammar_units_builds(tmp_path):
    scene = build(grammar(tmp_path, "thesis_types.csv"), lot="2x2u", physics=False,
                  formats=(), quiet=True)
    (floor,) = scene.floors
    assert floor.footprint.area == pytest.approx(400)  # 20 m × 20 m
    assert not any("has no unit" in m for m in messages(scene))


def test_a_lot_without_unit_under_other_units_is_stated(tmp_path):
    scene = build(grammar(tmp_path, "house_types.csv"), lot="14x10", physics=False,
                  formats=(), quiet=True)
    assert any("--lot 14x10 has no unit, so it is metres (14 m × 10 m)" in m
               for m in messages(scene))
    quiet = build(grammar(tmp_path, "house_types.csv"), lot="14x10m", physics=False,
                  formats=(), quiet=True)
    assert not any("has no unit" in m for m in messages(quiet))


def test_shipped_metre_tables_work_under_any_units(tmp_path):
    """The shipped house table declares metres: under units = 10 a living room still
    needs 16 m², not 1,600 m²."""
    scene = build(grammar(tmp_path, "house_types.csv"), lot="1.4x1u", physics=False,
                  formats=(), quiet=True)
    (floor,) = scene.floors
    types = {room.type for room in floor.rooms}
    assert {"Hall", "Livingroom"} <= types
    living = next(room for room in floor.rooms if room.type == "Livingroom")
    assert living.area_range[0] == pytest.approx(16)  # the table's Size, as m²
    assert any("is in metres ('# units: m')" in m for m in messages(scene))


def test_a_metre_table_without_declaration_is_flagged(tmp_path):
    """The failure first seen: a metre table read in grammar units² at units = 10."""
    lines = (RULES / "house_types.csv").read_text().splitlines()
    (tmp_path / "my_types.csv").write_text("\n".join(lines[1:]) + "\n")  # no `# units: m`
    scene = build(grammar(tmp_path, "my_types.csv"), lot="1.4x1u", physics=False,
                  formats=(), quiet=True)
    text = " ".join(messages(scene))
    assert "has no '# units:' line, so its room sizes are read in grammar units" in text
    assert "look like m²" in text and "on a floor of 140.0 m²" in text
    assert "put the line '# units: m' above its header" in text


def test_thesis_tables_keep_grammar_units():
    table = parse_rule_table((RULES / "thesis_types.csv").read_text(), file="thesis_types.csv")
    assert table.unit is None and table.area_scale(10) == 100
    metres = parse_rule_table((RULES / "house_types.csv").read_text(), file="house_types.csv")
    assert metres.unit == "m" and metres.area_scale(10) == 1


@pytest.mark.parametrize("line, unit", [("# units: m", "m"), ("#UNITS = metres;;;", "m"),
                                        ("# units: grammar", "grammar"), ("# a note", None)])
def test_table_unit_lines(line, unit):
    text = f"{line}\nType;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom\n" \
           "Room;4;1;Room;1;1;0\n"
    table = parse_rule_table(text, file="t.csv")
    assert table.unit == unit and table.rules[0].row == 3


def test_an_unknown_table_unit_is_refused_at_its_row():
    text = "# units: feet\nType;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom\n"
    with pytest.raises(RuleTableError, match=r"t.csv, row 1: unknown unit 'feet'"):
        parse_rule_table(text, file="t.csv")


def test_furniture_distances_follow_the_table_unit():
    body = ("Room;Name;clearanceFront;minPairDistance\n"
            "Livingroom;sofa;0.4;0\n")
    grammar_units = parse_furniture_rules(body, file="f.csv").scaled(10)
    metres = parse_furniture_rules("# units: m\n" + body, file="f.csv").scaled(10)
    assert grammar_units.rules[0].clearance_front == pytest.approx(4.0)
    assert metres.rules[0].clearance_front == pytest.approx(0.4)


def test_scene_json_keeps_units_and_metres(tmp_path):
    scene_dir = tmp_path / "out"
    build(grammar(tmp_path, "house_types.csv"), lot="1.4x1u", physics=False,
          formats=("json",), out_dir=scene_dir, quiet=True)
    document = json.loads((scene_dir / "tenths.scene.json").read_text())
    assert document["units"] == 10 and document["frame"]["length_unit"] == "m"
    assert document["georeference"] is None
