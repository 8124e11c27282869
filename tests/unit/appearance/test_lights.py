"""Ceiling lights: count and spacing from room size, three in a row at L/6, L/2, 5L/6."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon, box

from cga.appearance.lights import (MAX_LIGHTS, kelvin_to_rgb, load_light_rules,
                                   parse_light_rules, room_light_points)
from cga.errors import RuleTableError

TABLE = Path(__file__).resolve().parents[3] / "rules" / "lights.csv"


def _rules(text: str):
    return parse_light_rules("Room;Count;Spacing;Lumens;Temperature\n" + text, file="l.csv")


@pytest.mark.parametrize("length, width", [(6.0, 3.0), (9.0, 4.5), (4.2, 2.4)])
def test_three_lights_along_an_office_at_sixths(length, width):
    rule = load_light_rules(TABLE).for_room("Office")
    assert rule.count == 3
    # the office runs along z here: its length is the longer side wherever it lies
    room = box(2.0, 1.0, 2.0 + width, 1.0 + length)
    points = sorted(room_light_points(room, rule), key=lambda p: p[1])
    assert [p[1] - 1.0 for p in points] == pytest.approx([length / 6, length / 2,
                                                          5 * length / 6])
    assert all(p[0] == pytest.approx(2.0 + width / 2) for p in points)


def test_a_turned_room_keeps_its_lights_along_its_length():
    rule = _rules("*;3;;800;3000\n").for_room(None)
    room = Polygon([(0, 0), (6 * math.cos(0.5), 6 * math.sin(0.5)),
                    (6 * math.cos(0.5) - 2 * math.sin(0.5), 6 * math.sin(0.5) + 2 * math.cos(0.5)),
                    (-2 * math.sin(0.5), 2 * math.cos(0.5))])
    points = room_light_points(room, rule)
    along = sorted(p[0] * math.cos(0.5) + p[1] * math.sin(0.5) for p in points)
    assert along == pytest.approx([1.0, 3.0, 5.0])


@settings(max_examples=60, deadline=None)
@given(st.floats(1.0, 20.0), st.floats(1.0, 20.0), st.floats(1.5, 5.0))
def test_auto_lights_fill_the_room_on_a_grid(length, width, spacing):
    rule = _rules(f"*;auto;{spacing};800;3000\n").for_room("Bedroom")
    room = box(0, 0, length, width)
    points = room_light_points(room, rule)
    long_side, short_side = max(length, width), min(length, width)
    expected = max(1, round(long_side / spacing)) * max(1, round(short_side / spacing))
    assert len(points) == expected if expected <= MAX_LIGHTS else len(points) <= MAX_LIGHTS
    assert all(room.contains(Polygon(box(x - 1e-9, z - 1e-9, x + 1e-9, z + 1e-9)))
               for x, z in points)


@pytest.mark.parametrize("length, width", [(99_999.0, 40.0), (400.0, 300.0), (40.0, 40.0)])
def test_a_huge_room_hangs_at_most_the_cap_spread_evenly(length, width):
    rule = _rules("*;auto;3;800;3000\n").for_room("Hall")
    points = room_light_points(box(0, 0, length, width), rule)
    assert 1 < len(points) <= MAX_LIGHTS
    xs = sorted({round(x, 6) for x, _ in points})
    gaps = {round(b - a, 3) for a, b in zip(xs, xs[1:])}
    assert len(gaps) == 1 and xs[0] == pytest.approx(gaps.pop() / 2, abs=1e-3)  # even, centred


def test_an_l_shaped_room_keeps_at_least_one_light_inside():
    room = Polygon([(0, 0), (4, 0), (4, 1), (1, 1), (1, 4), (0, 4)])
    rule = _rules("*;1;;800;3000\n").for_room(None)
    [(x, z)] = room_light_points(room, rule)
    assert room.contains(box(x - 1e-6, z - 1e-6, x + 1e-6, z + 1e-6))


def test_warm_light_is_redder_than_cool_light():
    warm, cool = kelvin_to_rgb(2700), kelvin_to_rgb(6500)
    assert max(warm) == pytest.approx(1.0) and max(cool) == pytest.approx(1.0)
    assert warm[2] / warm[0] < 0.5 < cool[2] / cool[0]


@pytest.mark.parametrize("text, column", [
    ("*;two;;800;3000\n", "Count"),
    ("*;2.5;;800;3000\n", "Count"),
    ("*;auto;0;800;3000\n", "Spacing"),
    ("*;auto;3;900..100;3000\n", "Lumens"),
    ("*;auto;3;900;300\n", "Temperature"),
])
def test_a_bad_light_cell_names_row_and_column(text, column):
    with pytest.raises(RuleTableError) as info:
        _rules(text)
    assert (info.value.row, info.value.column) == (2, column)


def test_a_light_table_needs_a_default_row():
    with pytest.raises(RuleTableError, match="'\\*'"):
        _rules("Office;3;;800;3000\n")
