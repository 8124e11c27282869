"""A neutral palette's part looks are shared by every build of a material table: they
must be the looks each part gets on its own, whatever the seed and room, and a model's
answer must follow its parts (a grammar's own "chair" is another model)."""

from __future__ import annotations

from pathlib import Path

from cga.appearance.library import load_material_library
from cga.appearance.palette import Palette

TABLE = Path(__file__).resolve().parents[3] / "rules" / "materials.csv"

CHAIR = [("part_0_wood", (0.7, 0.5, 0.3)), ("part_1_fabric", (0.2, 0.2, 0.25)),
         ("part_2_metal", (0.6, 0.6, 0.6)), ("part_3_wood", (0.7, 0.5, 0.3))]


def test_neutral_part_looks_are_each_part_s_own_whatever_the_seed_and_room():
    library = load_material_library(TABLE)
    expected = [Palette(library, 0, "neutral").part("chair", name, color)
                for name, color in CHAIR]
    for seed, key in [(1, ("floor0", "room1")), (7, ("floor2", "room9")), (7, ())]:
        assert Palette(library, seed, "neutral").parts("chair", CHAIR, key=key) == expected


def test_a_model_s_neutral_answer_follows_its_parts():
    library = load_material_library(TABLE)
    palette = Palette(library, 3, "neutral")
    shipped = palette.parts("chair", CHAIR)
    own = [("seat_fabric", (0.9, 0.1, 0.1))]
    assert palette.parts("chair", own) == [palette.part("chair", "seat_fabric", (0.9, 0.1, 0.1))]
    assert Palette(library, 4, "neutral").parts("chair", CHAIR) == shipped


def test_random_part_looks_still_depend_on_the_room():
    library = load_material_library(TABLE)
    palette = Palette(library, 5, "random")
    looks = {tuple(m.name for m in palette.parts("chair", CHAIR, key=("floor0", f"room{k}")))
             for k in range(12)}
    assert len(looks) > 1
