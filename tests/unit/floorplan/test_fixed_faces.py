"""Fixed faces in the BSP: corridors and cores placed up front, never cut, DCEL kept."""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import Polygon, box

from cga.operations.floorplan.bsp import FixedFace, partition
from dcel_checks import validate_dcel

RECT = [(0, 0), (20, 0), (20, 12), (0, 12)]
L_SHAPE = [(0, 0), (14, 0), (14, 6), (8, 6), (8, 10), (0, 10)]


def ring(x0, z0, x1, z1):
    return ((x0, z0), (x1, z0), (x1, z1), (x0, z1))


def faces(result):
    return [Polygon(result.dcel.points(f)) for f in result.dcel.faces]


def touching_length(a: Polygon, b: Polygon) -> float:
    return a.boundary.intersection(b.boundary).length


@pytest.mark.parametrize("seed", range(15))
def test_a_corridor_wall_to_wall_is_kept_whole_and_every_room_opens_onto_it(seed):
    corridor = FixedFace(ring(0, 5.4, 20, 6.6), circulation=True, kind="corridor")
    result = partition(RECT, 8, np.random.default_rng(seed), fixed=[corridor], min_contact=1.3)
    validate_dcel(result.dcel, Polygon(RECT))
    polys = faces(result)
    assert polys[0].equals(box(0, 5.4, 20, 6.6))  # face 0 is the corridor, uncut
    assert result.circulation == frozenset({0})
    assert len(polys) == 1 + 2 + 8  # two free pieces, eight cuts
    for room in polys[1:]:
        assert touching_length(room, polys[0]) >= 1.3 - 1e-9


@pytest.mark.parametrize("seed", range(10))
def test_a_core_inside_the_floor_is_its_own_face_and_the_rest_is_partitioned(seed):
    core = FixedFace(ring(8, 4, 11, 8), kind="core")
    result = partition(RECT, 6, np.random.default_rng(seed), fixed=[core])
    validate_dcel(result.dcel, Polygon(RECT))
    polys = faces(result)
    assert polys[0].equals(box(8, 4, 11, 8))
    assert result.circulation == frozenset()
    assert sum(p.area for p in polys) == pytest.approx(240)
    for cut in result.cuts:
        assert cut.face != 0 and cut.new_face != 0


def test_fixed_faces_on_an_l_shape_and_touching_each_other():
    corridor = FixedFace(ring(3.4, 0, 4.6, 10), circulation=True)
    core = FixedFace(ring(4.6, 0, 7.6, 3), kind="core")
    result = partition(L_SHAPE, 4, np.random.default_rng(3), fixed=[corridor, core],
                       min_contact=1.3)
    validate_dcel(result.dcel, Polygon(L_SHAPE))
    polys = faces(result)
    assert polys[0].equals(box(3.4, 0, 4.6, 10)) and polys[1].equals(box(4.6, 0, 7.6, 3))
    assert touching_length(polys[0], polys[1]) == pytest.approx(3)


@pytest.mark.parametrize("fixed, message", [
    ([FixedFace(ring(18, 0, 22, 4))], "outside the footprint"),
    ([FixedFace(ring(0, 0, 4, 4)), FixedFace(ring(3, 3, 6, 6))], "overlap"),
    ([FixedFace(((0, 0), (1, 1), (2, 2)))], "not a simple polygon"),
])
def test_bad_fixed_faces_are_refused(fixed, message):
    with pytest.raises(ValueError, match=message):
        partition(RECT, 2, np.random.default_rng(0), fixed=fixed)


def test_a_floor_filled_by_fixed_faces_reports_why_it_has_no_cuts():
    result = partition(RECT, 3, np.random.default_rng(0),
                       fixed=[FixedFace(ring(0, 0, 20, 6)), FixedFace(ring(0, 6, 20, 12))])
    assert result.cuts == () and "no free floor" in result.shortfall
