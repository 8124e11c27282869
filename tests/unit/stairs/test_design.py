"""Stair sizing and core placement (DESIGN §12)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon, box

from cga.errors import DerivationError
from cga.operations.stairs import StairParams, core_for_storey, design_risers, place_core
from cga.operations.stairs.design import going_for

L_SHAPE = Polygon([(0, 0), (18, 0), (18, 8), (11, 8), (11, 14), (0, 14)])


@pytest.mark.parametrize("height", [2.6, 2.8, 3.0, 3.3, 3.5, 4.0])
@pytest.mark.parametrize("kind", ["U", "straight"])
def test_risers_never_exceed_the_maximum_and_add_up_to_the_storey(height, kind):
    n, rise = design_risers(height, 0.19, kind)
    assert rise <= 0.19 + 1e-12 and n * rise == pytest.approx(height)
    assert n == math.ceil(height / 0.19 - 1e-9) + (1 if kind == "U" and math.ceil(height / 0.19 - 1e-9) % 2 else 0)
    if kind == "U":
        assert n % 2 == 0  # two equal flights


def test_going_follows_blondel_but_not_below_the_minimum():
    assert going_for(0.1875, 0.25) == pytest.approx(0.255)
    assert going_for(0.19, 0.28) == 0.28
    assert 2 * 0.16 + going_for(0.16, 0.25) == pytest.approx(0.63, abs=1e-3)


@pytest.mark.parametrize("footprint", [box(0, 0, 14, 10), box(0, 0, 20, 12), L_SHAPE],
                         ids=["house", "office", "L"])
@pytest.mark.parametrize("kind", ["U", "straight"])
def test_the_core_fits_against_the_boundary_and_leaves_one_simple_rest(footprint, kind):
    for seed in range(5):
        core = place_core(footprint, 3.0, 2, StairParams(kind=kind), wall=0.2, door_width=0.9,
                          min_width=2.4, rng=np.random.default_rng(seed))
        assert footprint.covers(core.polygon)
        assert core.polygon.exterior.intersection(footprint.exterior).length > 0  # on the boundary
        rest = footprint.difference(core.polygon)
        assert isinstance(rest, Polygon) and not rest.interiors
        # the flights and landings fit inside the core's walls
        inside = core.rect(0, core.interior_length, 0, core.interior_width)
        assert core.polygon.buffer(-0.2 + 1e-9, join_style="mitre").covers(inside)
        assert core.width >= 0.9 and core.rise <= 0.19 and core.going >= 0.25


def test_the_landing_faces_the_inside_of_the_building():
    footprint = box(0, 0, 14, 10)
    for seed in range(8):
        core = place_core(footprint, 3.0, 2, StairParams(), wall=0.2, door_width=0.9,
                          min_width=2.4, rng=np.random.default_rng(seed))
        # just beyond the landing's long side lies the floor, not the outside
        probe = shapely.Point(core.at(core.landing_depth / 2, core.interior_width + 0.5))
        assert footprint.contains(probe)


def test_a_footprint_too_small_for_a_core_is_a_clear_error():
    with pytest.raises(DerivationError, match="no place for a U stair core"):
        place_core(box(0, 0, 5, 4), 3.0, 2, StairParams(), wall=0.2, door_width=0.9,
                   min_width=2.4, rng=np.random.default_rng(0))


@pytest.mark.parametrize("params, message", [
    (StairParams(width=0.3), "stair_width"),
    (StairParams(max_rise=0.4), "max_rise"),
    (StairParams(min_going=0.05), "min_going"),
])
def test_impossible_parameters_are_refused(params, message):
    with pytest.raises(DerivationError, match=message):
        params.check()


def test_every_storey_of_a_building_gets_the_same_core():
    cache: dict = {}
    first = core_for_storey(cache, 7, L_SHAPE, 3.0, 3, StairParams(), wall=0.2, door_width=0.9,
                            min_width=2.4)
    again = core_for_storey(cache, 7, L_SHAPE, 3.0, 3, StairParams(width=1.5), wall=0.2,
                            door_width=0.9, min_width=2.4)
    assert again is first
    fresh = core_for_storey({}, 7, L_SHAPE, 3.0, 3, StairParams(), wall=0.2, door_width=0.9,
                            min_width=2.4)
    assert fresh == first  # the place depends on the seed and footprint, not on who asks first


def _landing_opening(core, corridor: Polygon) -> float:
    """Length of the corridor's side the landing (grown to its wall centre lines) lies on."""
    landing = core.rect(-0.2, core.landing_depth, -0.2, core.interior_width + 0.2)
    return landing.buffer(1e-6).intersection(corridor.exterior).length


def test_with_a_corridor_the_landing_opens_onto_it():
    # the house demo: a 1.6 m spine corridor 4.2 m from the south wall of a 14 m x 10 m house
    footprint, corridor = box(0, 0, 14, 10), box(0, 4.2, 14, 5.8)
    for seed in range(8):
        core = place_core(footprint, 3.0, 2, StairParams(), wall=0.2, door_width=0.9,
                          min_width=2.0, rng=np.random.default_rng(seed), corridors=[corridor])
        assert core.polygon.intersection(corridor).area < 1e-9
        assert _landing_opening(core, corridor) >= 0.9 + 0.2  # a door and its margins


def test_a_core_beside_a_short_hall_leaves_the_rooms_most_of_it():
    """An 11 m x 10 m house with a 1.5 m hall across it: a U core laid along the hall
    would take 4.8 of the 10 m the rooms beyond it share; standing flush against the
    hall's side, across it, the core's end opens onto the hall and the rooms keep 7.4 m."""
    footprint, hall = box(0, 0, 11, 10), box(2.55, 0, 4.05, 10)
    beyond = box(4.05, 0, 11, 10)
    for seed in range(8):
        core = place_core(footprint, 3.0, 3, StairParams(), wall=0.2, door_width=0.9,
                          min_width=2.0, rng=np.random.default_rng(seed), corridors=[hall])
        assert core.polygon.intersection(hall).area < 1e-9
        assert _landing_opening(core, hall) >= 0.9 + 0.2
        side = beyond.boundary.intersection(hall.boundary.buffer(1e-6))
        taken = core.polygon.boundary.intersection(hall.boundary.buffer(1e-6)).length
        assert taken <= 0.4 * side.length, (seed, core.polygon.bounds)


def test_a_core_in_a_bay_too_shallow_for_a_room_beside_it_fills_the_bay():
    # the office demo: a 22 m x 10 m floor, a 1.8 m spine corridor; bays 4.1 m deep, and a
    # 2.5 m deep core would leave a 1.6 m strip where a 2 m room is needed
    footprint, corridor = box(0, 0, 22, 10), box(0, 4.1, 22, 5.9)
    for seed in range(8):
        core = place_core(footprint, 3.3, 2, StairParams(), wall=0.15, door_width=1.0,
                          min_width=2.0, rng=np.random.default_rng(seed), corridors=[corridor])
        x0, z0, x1, z1 = core.polygon.bounds
        assert z1 - z0 == pytest.approx(4.1) or x1 - x0 == pytest.approx(4.1)
        assert _landing_opening(core, corridor) >= 1.0 + 0.2
        # the stair still lies inside the core's walls, and the lobby is inside the core
        inside = core.rect(0, core.interior_length, 0, core.interior_width)
        assert core.interior.buffer(1e-6).covers(inside)
        assert core.interior.area > inside.area + 1.0


def test_a_lot_placed_again_gets_the_places_it_got_the_first_time(monkeypatch):
    """The ranking is kept per process by the exact footprint, corridors and sizes; a
    seed only draws among the best places, so every seed of a kept lot draws the core
    it would draw from a fresh ranking, and a lot that differs is ranked afresh."""
    from cga.operations.stairs import design

    footprint, corridor = box(0, 0, 14, 10), box(0, 4.2, 14, 5.8)
    kwargs = dict(wall=0.2, door_width=0.9, min_width=2.0, corridors=[corridor])
    ranked = []
    rank = design._rank_places
    monkeypatch.setattr(design, "_PLACES", {})
    monkeypatch.setattr(design, "_rank_places", lambda *a: ranked.append(a) or rank(*a))
    first = [place_core(footprint, 3.0, 2, StairParams(), rng=np.random.default_rng(seed),
                        **kwargs) for seed in range(6)]
    assert len(ranked) == 1
    assert len({(c.origin, c.u) for c in first}) > 1  # the seeds draw different places
    fresh = []
    for seed in range(6):
        design._PLACES.clear()
        fresh.append(place_core(footprint, 3.0, 2, StairParams(),
                                rng=np.random.default_rng(seed), **kwargs))
    assert fresh == first and len(ranked) == 7
    place_core(box(0, 0, 14, 10.5), 3.0, 2, StairParams(), rng=np.random.default_rng(0),
               **kwargs)
    place_core(footprint, 3.0, 2, StairParams(width=1.2), rng=np.random.default_rng(0),
               **kwargs)
    assert len(ranked) == 9  # another lot and another stair are ranked afresh
    for size in range(design._PLACES_KEPT + 4):  # the process keeps a bounded number
        place_core(box(0, 0, 14 + size, 10), 3.0, 2, StairParams(),
                   rng=np.random.default_rng(0), wall=0.2, door_width=0.9, min_width=2.0)
    assert len(design._PLACES) == design._PLACES_KEPT


def test_a_lot_with_no_place_is_refused_every_time():
    for _ in range(2):
        with pytest.raises(DerivationError, match="no place for a U stair core"):
            place_core(box(0, 0, 5, 4), 3.0, 2, StairParams(), wall=0.2, door_width=0.9,
                       min_width=2.4, rng=np.random.default_rng(0))
