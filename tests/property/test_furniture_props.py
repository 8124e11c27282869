"""Property: furnished house and office floors never break a furniture guarantee.

Floors are random rectangle tilings (guillotine cuts, sometimes with a corner piece
removed to make an L), typed by the shipped tables through the rule-author API and
furnished by the shipped furniture tables; the independent validator
(``tests/support/furniture_checks.py``) must find nothing, on 300 floors or more.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cga.authoring import floor_from_rectangles, type_floor
from cga.errors import NoSolutionError
from cga.authoring import furnish_floor
from cga.operations.furniture.library import default_library

from furniture_checks import furniture_violations
from hall_floors import KINDS, with_hall

RULES = Path(__file__).resolve().parents[2] / "rules"
FLOORS = 300


@pytest.mark.slow
def test_furnished_floors_keep_every_guarantee():
    library = default_library()
    furnished, seed = 0, 0
    while furnished < FLOORS:
        seed += 1
        kind = "office" if seed % 3 == 0 else "house"
        types, table, width, depth, _ = KINDS[kind]
        rng = np.random.default_rng(seed)
        plan = floor_from_rectangles(with_hall(rng, width, depth), windows_per_wall=2,
                                     circulation=[0])
        try:
            typed = type_floor(plan, types, seed=seed)
        except NoSolutionError:
            continue
        result = furnish_floor(typed, table, seed=seed, clearance_tries=5, library=library)
        problems = furniture_violations(result, RULES / table)
        assert problems == [], f"{kind} floor, seed {seed}: {problems[:5]}"
        assert any(not item.is_detail for item in result.furniture), f"seed {seed}: nothing placed"
        furnished += 1
    assert seed < 2 * FLOORS  # typing rarely fails, so the floors are not a thin sample
