"""Property: at full disorder, furnished house and office floors keep every guarantee.

The fast version of ``scripts/disorder_check.py`` (300 floors): random floors of the
furniture property test, furnished by the shipped tables at disorder 1, checked by the
independent validator with the documented largest free turn.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings, strategies as st

from cga.authoring import floor_from_rectangles, furnish_floor, type_floor
from cga.errors import NoSolutionError
from cga.operations.furniture.disorder import MAX_YAW
from cga.operations.furniture.library import default_library

from furniture_checks import furniture_violations
from hall_floors import KINDS, with_hall

RULES = Path(__file__).resolve().parents[2] / "rules"
LIBRARY = default_library()


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
