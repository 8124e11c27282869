"""The UvA generator's rules, each against the paper's formula (Zwennes 2011, §4)."""

from __future__ import annotations

from collections import Counter
from fractions import Fraction

import numpy as np
import pytest

from cga.operations.usar.catalogue import CatalogueRoom
from cga.operations.usar.generator import (CUT, HALL, OPEN, cycle_prevention_probability,
                                           doorway_probability, expected_room_difficulty,
                                           generate, hallway_spacing, room_weights)

from usar_paper import PAPER

CATALOGUE = tuple(CatalogueRoom(name, w, d, diff, "Empty") for name, w, d, diff in PAPER)


@pytest.mark.parametrize("d, size, gaussian, expected", [
    (0, 20, 0.0, 4),      # 0.2 * 20
    (10, 20, 0.0, 16),    # 0.8 * 20
    (5, 20, 1.0, 12),     # 0.5 * 20 + 0.1 * 20
    (0, 20, -3.0, 3),     # -2 -> clamped to 3
    (10, 20, 3.0, 20),    # 22 -> clamped to size
])
def test_hallway_spacing(d, size, gaussian, expected):
    assert hallway_spacing(d, size, gaussian) == expected


def test_doorway_and_cycle_probabilities():
    assert doorway_probability(0) == 0.375 and doorway_probability(10) == pytest.approx(1.0)
    assert doorway_probability(4) == pytest.approx(4 / 16 + 0.375)
    assert cycle_prevention_probability(0) == 1.0 and cycle_prevention_probability(10) == 0.0
    assert cycle_prevention_probability(3) == pytest.approx(0.7)


@pytest.mark.parametrize("d", range(11))
def test_expected_room_difficulty_is_exact(d):
    # E[diff] = sum ISE(r) diff(r) / sum ISE(r), ISE = 1 / ((d - diff)^2 + 1), in fractions
    ise = [Fraction(1) / ((Fraction(d) - Fraction(str(diff))) ** 2 + 1) for *_, diff in PAPER]
    exact = sum(w * Fraction(str(diff)) for w, (*_, diff) in zip(ise, PAPER)) / sum(ise)
    assert expected_room_difficulty(CATALOGUE, d) == pytest.approx(float(exact), rel=1e-12)
    weights = room_weights(CATALOGUE, d)
    assert weights.sum() == pytest.approx(1.0)
    assert [float(w) for w in weights] == pytest.approx([float(w / sum(ise)) for w in ise])


def test_rooms_are_drawn_with_the_ise_weights_when_all_fit():
    # 1 x 1 rooms fit every empty cell, so the draw is P(r) itself
    small = tuple(CatalogueRoom(f"r{k}", 1, 1, diff, "Empty") for k, diff in enumerate((0.5, 3, 6, 9.5)))
    counts: Counter[str] = Counter()
    for seed in range(40):
        layout = generate(12, 12, 6.0, small, np.random.default_rng(seed))
        counts.update(p.room.name for p in layout.rooms)
    total = sum(counts.values())
    for room, p in zip(small, room_weights(small, 6.0)):
        assert counts[room.name] / total == pytest.approx(p, abs=0.03)


def test_hallways_fill_every_spaced_column_and_row():
    layout = generate(16, 12, 5.0, CATALOGUE, np.random.default_rng(3))
    sx, sy = layout.spacing
    corridor = np.isin(layout.cells, (HALL, CUT))
    assert corridor[:, ::sx].all() and corridor[::sy, :].all()
    for p in layout.rooms:
        x0, y0, x1, y1 = p.rect
        assert (layout.cells[y0:y1, x0:x1] == p.index).all()


def test_open_areas_are_the_cells_the_column_jump_skips():
    # a 2-wide room then a 1-wide room in one column leaves the cell beside the latter
    catalogue = (CatalogueRoom("wide", 2, 2, 5.0, "Empty"), CatalogueRoom("one", 1, 1, 5.0, "Empty"))
    layout = generate(8, 8, 10.0, catalogue, np.random.default_rng(0))
    assert (layout.cells == OPEN).any() or all(p.room.name == "wide" for p in layout.rooms)
    regions = {r.kind for r in layout.regions}
    assert "room" in regions and "hallway" in regions


def test_small_grid_and_bad_difficulty_are_refused():
    with pytest.raises(ValueError, match="4 x 4"):
        generate(3, 8, 5.0, CATALOGUE, np.random.default_rng(0))
    with pytest.raises(ValueError, match="difficulty"):
        generate(8, 8, 11.0, CATALOGUE, np.random.default_rng(0))
