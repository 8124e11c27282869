"""Properties of furniture variation and disorder.

* At full disorder, furnished house and office floors keep every guarantee: the fast
  version of ``scripts/disorder_check.py`` (300 floors): random floors of the furniture
  property test, furnished by the shipped tables at disorder 1, checked by the
  independent validator with the documented largest free turn.
* A jittered item's size stays within its row's range, its posed collision parts fill
  exactly the box its visual mesh fills and the mesh lies in the item's footprint, at
  any size, quarter turn and free yaw.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings, strategies as st
from shapely.geometry import box

from cga.authoring import floor_from_rectangles, furnish_floor, type_floor
from cga.meshing.items import item_node
from cga.model import FloorPlan, FloorSettings, FurnitureItem, Room
from cga.errors import NoSolutionError
from cga.operations.furniture.disorder import MAX_YAW
from cga.operations.furniture.library import default_library
from cga.operations.furniture.variation import jittered_size

from furniture_checks import furniture_violations
from hall_floors import KINDS, with_hall

RULES = Path(__file__).resolve().parents[2] / "rules"
LIBRARY = default_library()
MODELS = ["desk", "officechair", "tablebig", "bookshelf", "sofa", "chair"]


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(1, 10_000), kind=st.sampled_from(["house", "office"]))
def test_full_disorder_breaks_no_guarantee(seed, kind):
    types, table, width, depth, _ = KINDS[kind]
    plan = floor_from_rectangles(with_hall(np.random.default_rng(seed), width, depth),
                                 windows_per_wall=2, circulation=[0])
    try:
        typed = type_floor(plan, types, seed=seed)
    except NoSolutionError:
        return
    furnished = furnish_floor(typed, table, seed=seed, clearance_tries=5, disorder=1.0,
                              library=LIBRARY)
    assert furniture_violations(furnished, RULES / table, max_yaw=MAX_YAW) == []


fractions = st.floats(0.0, 0.5, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(model=st.sampled_from(MODELS), jitter=st.tuples(fractions, fractions, fractions),
       seed=st.integers(0, 2**32 - 1), rotation=st.integers(0, 3),
       yaw=st.floats(-math.pi / 6, math.pi / 6, allow_nan=False))
def test_jittered_items_stay_in_range_and_collide_as_they_look(model, jitter, seed, rotation,
                                                                 yaw):
    own = LIBRARY.get(model).size
    size = jittered_size(own, jitter, np.random.default_rng(seed))
    assert size == jittered_size(own, jitter, np.random.default_rng(seed))
    for extent, base, fraction in zip(size, own, jitter):
        assert base * (1 - fraction) - 1e-12 <= extent <= base * (1 + fraction) + 1e-12
    square = box(0, 0, 10, 10)
    plan = FloorPlan(0, 0.0, 3.0, square, FloorSettings(), (Room(0, square, square, "Office"),),
                     ())
    item = FurnitureItem(model, model, 0, (5.0, 5.0), rotation, size, yaw=yaw)
    node = item_node(item, plan, LIBRARY)
    parts = np.vstack([p.vertices for p in node.parts])
    assert parts.min(axis=0) == pytest.approx(node.mesh.bounds[0], abs=1e-9)
    assert parts.max(axis=0) == pytest.approx(node.mesh.bounds[1], abs=1e-9)
    # the model, scaled and turned, lies in the footprint the solver reserved for it
    footprint = item.footprint().buffer(1e-9, join_style="mitre")
    vertices = np.asarray(node.mesh.vertices)
    assert shapely.contains_xy(footprint, vertices[:, 0], vertices[:, 2]).all()
    assert node.mesh.bounds[1][1] - node.mesh.bounds[0][1] == pytest.approx(size[1])
