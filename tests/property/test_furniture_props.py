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
from shapely.geometry import Polygon, box
from shapely.ops import unary_union

from cga.authoring import floor_from_rectangles, type_floor
from cga.errors import NoSolutionError
from cga.authoring import furnish_floor
from cga.operations.furniture.library import default_library

from furniture_checks import furniture_violations

RULES = Path(__file__).resolve().parents[2] / "rules"
FLOORS = 300
KINDS = {"house": ("house_types.csv", "furniture_house.csv", (10, 15), (8, 11), (3, 7)),
         "office": ("office_types.csv", "furniture_office.csv", (14, 20), (10, 14), (5, 9))}


def tiling(rng: np.random.Generator, width: tuple, depth: tuple, rooms: tuple
           ) -> list[tuple[float, float, float, float]]:
    """Guillotine cuts of a random rectangle: the largest piece is cut across its longer
    side at 35..65 %, keeping every piece at least 2.6 m wide; sometimes a corner piece
    is dropped so the footprint is an L."""
    w, d = round(rng.uniform(*width), 1), round(rng.uniform(*depth), 1)
    pieces = [(0.0, 0.0, w, d)]
    for _ in range(int(rng.integers(*rooms))):
        pieces.sort(key=lambda r: (r[2] - r[0]) * (r[3] - r[1]))
        x0, z0, x1, z1 = pieces[-1]
        axis = 0 if x1 - x0 >= z1 - z0 else 1
        lo, hi = (x0, x1) if axis == 0 else (z0, z1)
        cut = round(lo + (hi - lo) * rng.uniform(0.35, 0.65), 2)
        if min(cut - lo, hi - cut) < 2.6:
            break
        pieces.pop()
        pieces += ([(x0, z0, cut, z1), (cut, z0, x1, z1)] if axis == 0
                   else [(x0, z0, x1, cut), (x0, cut, x1, z1)])
    corners = [r for r in pieces if sum((r[0] == 0, r[1] == 0, r[2] == w, r[3] == d)) == 2]
    if len(pieces) > 3 and corners and rng.random() < 0.3:
        rest = [r for r in pieces if r != corners[int(rng.integers(len(corners)))]]
        if isinstance(unary_union([box(*r) for r in rest]), Polygon):
            return rest
    return pieces


@pytest.mark.slow
def test_furnished_floors_keep_every_guarantee():
    library = default_library()
    furnished, seed = 0, 0
    while furnished < FLOORS:
        seed += 1
        kind = "office" if seed % 3 == 0 else "house"
        types, table, width, depth, rooms = KINDS[kind]
        rng = np.random.default_rng(seed)
        plan = floor_from_rectangles(tiling(rng, width, depth, rooms), windows_per_wall=2)
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
