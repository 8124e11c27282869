"""The material table: the shipped one loads and names every shipped model's parts;
bad tables fail naming the row and column."""

from __future__ import annotations

import colorsys
import csv
from pathlib import Path

import pytest

from cga.appearance.library import (FALLBACK_PART, STRUCTURE_SURFACES, load_material_library,
                                    parse_material_library, part_class)
from cga.errors import RuleTableError
from cga.operations.furniture.library import default_library

ROOT = Path(__file__).resolve().parents[3]
TABLE = ROOT / "rules" / "materials.csv"
HEADER = "Material;Surface;Color;Roughness;Metallic;Alpha;Value;Weight;Models;Parts;Rooms"


def _minimal(extra: str = "") -> str:
    rows = [f"{s}_n;{s};#808080;0.5;0;1;;0;;;" for s in (*STRUCTURE_SURFACES, FALLBACK_PART)]
    return "\n".join([HEADER, *rows, *([extra] if extra else [])]) + "\n"


def test_the_shipped_table_loads_with_a_neutral_row_per_class():
    library = load_material_library(TABLE)
    for surface in {r.surface for r in library.rows}:
        first = library.candidates(surface)[0]
        assert not first.restricted, surface
    assert {"wood", "fabric", "metal", "plastic", "ceramic", "glass"} <= set(library.part_classes)
    glass = library.candidates("glass")[0]
    assert glass.alpha < 1  # window glass is see-through


def test_every_shipped_model_part_names_a_class_of_the_table():
    library = load_material_library(TABLE)
    models = default_library()
    for name in models.names():
        model = models.get(name)
        assert len(model.part_names) == len(model.parts)
        for part in model.part_names:
            # independent reading of the convention: the word after the part number
            word = part.split("_")[-1]
            assert word in library.part_classes, (name, part)
            assert part_class(part, library.part_classes) == word


def test_a_group_name_without_a_class_falls_back():
    classes = ("fabric", "wood")
    assert part_class("Seat.Fabric", classes) == "fabric"
    assert part_class("part_0", classes) == FALLBACK_PART


def test_the_structure_colours_of_the_neutral_look_are_today_s():
    # read the CSV independently: the neutral wall is the palette's old wall colour
    with TABLE.open(encoding="utf-8") as handle:
        rows = [r for r in csv.reader(handle, delimiter=";") if r and not r[0].startswith("#")]
    header, data = rows[0], rows[1:]
    first = {}
    for row in data:
        record = dict(zip(header, row))
        first.setdefault(record["Surface"], record)
    assert first["wall"]["Color"] == "#e8e4dc"
    assert first["floor"]["Weight"] == "0"


@pytest.mark.parametrize("row, column", [
    ("bad;wood;#12345;0.5;0;1;;1;;;", "Color"),
    ("bad;wood;#123456;1.5;0;1;;1;;;", "Roughness"),
    ("bad;wood;#123456;0.7..0.2;0;1;;1;;;", "Roughness"),
    ("bad;wood;#123456;0.5;2;1;;1;;;", "Metallic"),
    ("bad;wood;#123456;0.5;0;1;;-1;;;", "Weight"),
    ("bad;wood;#123456;0.5;0;1;x..2;1;;;", "Value"),
    ("wall_n;wall;#123456;0.5;0;1;;1;;;", "Material"),
    ("9lives;wood;#123456;0.5;0;1;;1;;;", "Material"),
    ("bad;wo od;#123456;0.5;0;1;;1;;;", "Surface"),
])
def test_a_bad_cell_names_its_row_and_column(row, column):
    text = _minimal(row)
    with pytest.raises(RuleTableError) as info:
        parse_material_library(text, file="m.csv")
    last = len(text.splitlines())
    assert info.value.row == last and info.value.column == column
    assert f"m.csv, row {last}, column '{column}'" in str(info.value)


def test_a_table_missing_a_structure_class_is_refused():
    text = "\n".join(line for line in _minimal().splitlines() if not line.startswith("roof_n"))
    with pytest.raises(RuleTableError, match="roof"):
        parse_material_library(text, file="m.csv")


def test_an_unknown_column_is_refused_with_its_name():
    with pytest.raises(RuleTableError, match="unknown column") as info:
        parse_material_library(HEADER + ";Shine\n", file="m.csv")
    assert info.value.column == "shine"


def test_a_class_whose_rows_are_all_restricted_is_refused():
    text = _minimal("oak;wood;#b88c5c;0.5;0;1;;1;chair;;")
    with pytest.raises(RuleTableError, match="restricted"):
        parse_material_library(text, file="m.csv")


def test_the_wood_rows_share_a_hue_band():
    library = load_material_library(TABLE)
    hues = [colorsys.rgb_to_hsv(*r.color)[0] for r in library.candidates("wood")]
    assert max(hues) - min(hues) < 0.1  # oak, walnut, birch, cherry: browns
