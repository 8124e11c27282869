"""The palette: neutral is the first row; random draws vary with the seed, keep the hue,
respect restrictions, and repeat for the same seed."""

from __future__ import annotations

import colorsys
from pathlib import Path

import pytest

from cga.appearance.library import load_material_library, parse_material_library
from cga.appearance.palette import Palette

TABLE = Path(__file__).resolve().parents[3] / "rules" / "materials.csv"


@pytest.fixture(scope="module")
def library():
    return load_material_library(TABLE)


def test_neutral_takes_the_first_row_and_keeps_a_part_s_own_colour(library):
    palette = Palette(library, 3, "neutral")
    wall = palette.surface("wall", room_type="Kitchen", key=("floor0", "room1"))
    assert wall.row == "wall_neutral" and wall.color == pytest.approx((0xe8 / 255, 0xe4 / 255,
                                                                       0xdc / 255), abs=1e-4)
    seat = palette.part("chair", "part_4_wood", (0.72, 0.55, 0.36))
    assert seat.row == "oak" and seat.color == (0.72, 0.55, 0.36)
    assert Palette(library, 99, "neutral").surface("floor") == palette.surface("floor")


def test_the_same_seed_gives_the_same_materials_whatever_the_order(library):
    keys = [("wall", "Bedroom", ("floor0", f"room{k}")) for k in range(6)]
    a, b = Palette(library, 11, "random"), Palette(library, 11, "random")
    first = [a.surface(s, room_type=t, key=k) for s, t, k in keys]
    second = [b.surface(s, room_type=t, key=k) for s, t, k in reversed(keys)][::-1]
    assert first == second


def test_materials_vary_over_seeds(library):
    looks = {Palette(library, seed, "random").part("desk", "part_0_wood", (0.7, 0.5, 0.3),
                                                   key=("floor0", "room2")).name
             for seed in range(100)}
    assert len(looks) > 50


def test_random_wood_keeps_the_hue_of_its_rows(library):
    hues = {r.name: colorsys.rgb_to_hsv(*r.color)[0] for r in library.rows if r.surface == "wood"}
    for seed in range(100):
        wood = Palette(library, seed, "random").part("chair", "part_0_wood", (0.7, 0.5, 0.3),
                                                     key=("floor0", "room1"))
        # the HSV value moved, the hue did not (up to the 4-decimal rounding of colours)
        assert colorsys.rgb_to_hsv(*wood.color)[0] == pytest.approx(hues[wood.row], abs=2e-3)
        assert min(hues.values()) - 2e-3 <= colorsys.rgb_to_hsv(*wood.color)[0] \
            <= max(hues.values()) + 2e-3


def test_restricted_rows_only_dress_their_models_parts_and_rooms():
    text = ("Material;Surface;Color;Roughness;Weight;Models;Parts;Rooms\n"
            + "".join(f"{s}_n;{s};#808080;0.5;0;;;\n" for s in
                      ("wall", "facade", "floor", "ceiling", "slab", "roof", "stair", "rail",
                       "mass", "face", "furniture"))
            + "plain;fabric;#404040;0.9;1;;;\n"
            + "mesh;fabric;#101010;0.9;1000;officechair;part_15_fabric;\n"
            + "tiles;floor;#dddddd;0.3;1000;;;kitchen\n")
    library = parse_material_library(text)
    for seed in range(50):
        palette = Palette(library, seed, "random")
        assert palette.part("sofa", "part_15_fabric", (0.3, 0.3, 0.3)).row == "plain"
        assert palette.part("officechair", "part_13_fabric", (0.3, 0.3, 0.3)).row == "plain"
        assert palette.surface("floor", room_type="Bedroom", key=(str(seed),)).row != "tiles"
    # with weight 1000 against 1, the targets win nearly always where they are allowed
    assert sum(Palette(library, s, "random").part("officechair", "part_15_fabric",
                                                  (0.3, 0.3, 0.3)).row == "mesh"
               for s in range(50)) > 45
    assert sum(Palette(library, s, "random").surface("floor", room_type="Kitchen",
                                                     key=(str(s),)).row == "tiles"
               for s in range(50)) > 45


def test_an_unknown_mode_is_refused(library):
    with pytest.raises(ValueError, match="neutral, random"):
        Palette(library, 0, "loud")  # type: ignore[arg-type]
