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

RULES = Path(__file__).resolve().parents[2] / "rules"
FLOORS = 300
KINDS = {"house": ("house_types.csv", "furniture_house.csv", (10, 15), (8, 11), (3, 7)),
         "office": ("office_types.csv", "furniture_office.csv", (14, 20), (10, 14), (5, 9))}
HALL = 1.8  # the shipped tables enter every room from a hall or corridor


def with_hall(rng: np.random.Generator, width: tuple, depth: tuple
              ) -> list[tuple[float, float, float, float]]:
    """A hall along the middle of a random rectangle (room 0), rooms 2–6 m wide cut
    across the two sides."""
    w, d = round(rng.uniform(*width), 1), round(rng.uniform(*depth), 1)
    z0 = round((d - HALL) / 2, 2)
    pieces = [(0.0, z0, w, z0 + HALL)]
    for lo, hi in ((0.0, z0), (z0 + HALL, d)):
        x = 0.0
        while w - x >= 4.0:
            step = round(min(rng.uniform(2.0, 6.0), w - x - 2.0), 2)
            pieces.append((x, lo, x + step, hi))
            x += step
        pieces.append((x, lo, w, hi))
    return pieces


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
