"""Windows on outer walls: count, spacing, clearances."""

from __future__ import annotations

import pytest

from cga.model import FloorSettings, OUTSIDE, Wall
from cga.operations.floorplan.openings import MIN_GAP, place_windows, window_centres


@pytest.mark.parametrize("length, count, expected", [
    (10.0, 2, 2),
    (10.0, 9, 6),     # (10 - 0.4 - 0.3) // (1.2 + 0.3) = 6
    (2.2, 1, 1),      # 2.2 - 0.4 = 1.8 = 0.3 + 1.2 + 0.3: exactly fits
    (2.1, 1, 0),
    (10.0, 0, 0),
])
def test_window_count_drops_on_short_walls(length, count, expected):
    centres = window_centres(length, count, 1.2, 0.2)
    assert len(centres) == expected
    # clear gaps: wall start (past the 0.2 m wall meeting it), between windows, wall end
    bounds = [0.2] + [x for c in centres for x in (c - 0.6, c + 0.6)] + [length - 0.2]
    gaps = [b - a for a, b in zip(bounds[0::2], bounds[1::2])] if centres else []
    assert all(g >= MIN_GAP - 1e-9 for g in gaps)
    assert max(gaps, default=0) - min(gaps, default=0) < 1e-5  # evenly spaced (µm rounding)


def test_place_windows_only_on_outer_walls():
    settings = FloorSettings(windows_per_wall=2, window_width=1.0, window_height=1.3, window_sill=0.8)
    walls = (Wall(0, (0.0, 0.0), (8.0, 0.0), True, (0, OUTSIDE), 0.2),
             Wall(1, (4.0, 0.0), (4.0, 6.0), False, (0, 1), 0.2),
             Wall(2, (8.0, 6.0), (8.0, 0.0), True, (1, OUTSIDE), 0.2))
    out, windows = place_windows(walls, settings)
    assert [len(w.openings) for w in out] == [2, 0, 2]
    assert {o.kind for w in out for o in w.openings} == {"window"}
    assert [(w.id, w.wall, w.room) for w in windows] == [(0, 0, 0), (1, 0, 0), (2, 2, 1), (3, 2, 1)]
    assert windows[2].position == pytest.approx((8.0, 6.0 - out[2].openings[0].center))
    assert all((w.width, w.height, w.sill) == (1.0, 1.3, 0.8) for w in windows)
    assert walls[0].openings == ()  # inputs untouched
