"""Stair invariants over random footprints, storey heights and stair parameters.

For any rectangle or L-shaped footprint that takes a core: the core lies inside the
footprint against its boundary and leaves one simple polygon; the stair between two
storeys climbs exactly a storey in risers no higher than ``max_rise`` and treads no
shallower than ``min_going``; its solid is watertight and its treads are at the heights
the model gives; the stairwell and the floor landings do not overlap.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon, box

from cga.errors import DerivationError
from cga.meshing.stairs import stair_mesh
from cga.model import FloorPlan, FloorSettings
from cga.operations.stairs import StairParams, place_core, stair_between

pytestmark = pytest.mark.slow


@st.composite
def footprints(draw) -> Polygon:
    w = draw(st.floats(8, 30).map(lambda v: round(v, 1)))
    d = draw(st.floats(8, 20).map(lambda v: round(v, 1)))
    if draw(st.booleans()):
        return box(0, 0, w, d)
    cx = draw(st.floats(0.4, 0.7)) * w
    cz = draw(st.floats(0.4, 0.7)) * d
    return Polygon([(0, 0), (w, 0), (w, round(cz, 1)), (round(cx, 1), round(cz, 1)),
                    (round(cx, 1), d), (0, d)])


def _storey(footprint: Polygon, index: int, height: float) -> FloorPlan:
    return FloorPlan(index=index, elevation=index * height, height=height, footprint=footprint,
                     settings=FloorSettings(), rooms=(), walls=(), core_room=0)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(footprint=footprints(), height=st.floats(2.5, 4.2), kind=st.sampled_from(["U", "straight"]),
       width=st.floats(0.9, 1.6), max_rise=st.floats(0.15, 0.2), min_going=st.floats(0.22, 0.32),
       seed=st.integers(0, 2**16))
def test_stairs_keep_their_invariants(footprint, height, kind, width, max_rise, min_going, seed):
    params = StairParams(kind=kind, width=round(width, 2), max_rise=max_rise, min_going=min_going)
    try:
        core = place_core(footprint, height, 2, params, wall=0.2, door_width=0.9, min_width=2.4,
                          rng=np.random.default_rng(seed))
    except DerivationError:
        assume(False)  # too small for a core of this size: a clear error, not a stair
    assert footprint.buffer(1e-7).covers(core.polygon)
    assert core.polygon.exterior.intersection(footprint.exterior).length > 0
    rest = footprint.difference(core.polygon)
    assert isinstance(rest, Polygon) and not rest.interiors
    lower, upper = _storey(footprint, 0, height), _storey(footprint, 1, height)
    stair = stair_between(core, lower, upper, 0)
    assert stair.rise <= max_rise + 1e-12 and stair.going >= min_going - 1e-12
    assert stair.width == params.width
    assert stair.risers * stair.rise == pytest.approx(height)
    assert stair.flights[-1].top_y == pytest.approx(upper.floor_y)
    assert all(stair.polygon.intersection(p).area < 1e-9 for p in stair.landings)
    assert core.polygon.buffer(1e-7).covers(stair.polygon)
    mesh = stair_mesh(stair)
    assert mesh.is_watertight and mesh.volume > 0
    assert mesh.bounds[0][1] == pytest.approx(lower.floor_y)
    assert mesh.bounds[1][1] == pytest.approx(upper.floor_y)
