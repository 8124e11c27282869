"""The UvA generator's "Done when" statistics and invariants (issue 14; DESIGN §13), on
grids only: no furniture, no physics. The validator is independent
(tests/support/usar_checks.py)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cga.operations.usar.catalogue import load_catalogue
from cga.operations.usar.generator import generate
from cga.resources import resolve_resource
from usar_checks import (every_region_reachable, hallway_cells_are_a_forest,
                         hallway_links_are_a_forest, validate_layout)

CATALOGUE = load_catalogue(resolve_resource("usar_rooms.csv", "rules"))


@pytest.mark.parametrize("d", [1, 3, 5, 7, 9])
def test_hundred_maps_per_difficulty(d):
    draws = opened = fired = 0
    for seed in range(100):
        rng = np.random.default_rng([d, seed])
        columns, rows = 10 + seed % 9, 8 + seed % 7
        layout = generate(columns, rows, float(d), CATALOGUE, rng)
        sx, sy = layout.spacing
        assert 3 <= sx <= columns - 1 and 3 <= sy <= rows - 1
        draws += len(layout.doorways)
        opened += sum(w.opened for w in layout.doorways)
        validate_layout(layout)
        assert every_region_reachable(layout)
        if layout.cycle_prevention:
            fired += 1
            assert hallway_links_are_a_forest(layout)
            assert hallway_cells_are_a_forest(layout)
    assert abs(opened / draws - (d / 16 + 0.375)) <= 0.03
    # 1 - d/10 of the maps; at d = 9 the chance of none in 100 is 0.9^100
    assert fired > 0


@settings(max_examples=40, deadline=None)
@given(d=st.floats(0, 10), columns=st.integers(4, 24), rows=st.integers(4, 24),
       seed=st.integers(0, 2**32 - 1))
def test_any_map_is_valid(d, columns, rows, seed):
    layout = generate(columns, rows, d, CATALOGUE, np.random.default_rng(seed))
    validate_layout(layout)
    assert every_region_reachable(layout)
    if layout.cycle_prevention:
        assert hallway_links_are_a_forest(layout) and hallway_cells_are_a_forest(layout)
