"""Window placement on outer walls.

The thesis cut ``numWindows`` windows into every outer wall and reduced the count until
they fit (§5.1.3). Here a wall's free span is the segment minus the wall thickness at
each end (where the perpendicular wall stands); windows are spread so that the gaps
between them and to both ends are equal and never smaller than :data:`MIN_GAP`, and the
count drops when the span is too short.
"""

from __future__ import annotations

import math
from dataclasses import replace

from cga.model import FloorSettings, Opening, Wall, Window

__all__ = ["MIN_GAP", "window_centres", "place_windows"]

MIN_GAP = 0.3
"""Least clear distance (m) between a window and a corner or another window."""


def window_centres(length: float, count: int, width: float, thickness: float) -> list[float]:
    """Centres (distance from the wall start) of up to ``count`` evenly spaced windows.

    Parameters
    ----------
    length
        Length of the wall segment (m).
    count
        Windows wanted.
    width
        Width of one window (m).
    thickness
        Wall thickness (m), kept free at both ends for the walls that meet this one.

    Returns
    -------
    list[float]
        ``n ≤ count`` centres (rounded to the micrometre); the ``n + 1`` gaps (ends
        included) are equal and at least :data:`MIN_GAP`. Empty when not even one
        window fits.
    """
    span = length - 2 * thickness
    if count <= 0 or width <= 0:
        return []
    fits = math.floor((span - MIN_GAP) / (width + MIN_GAP) + 1e-9)
    n = min(count, fits)
    if n <= 0:
        return []
    gap = (span - n * width) / (n + 1)
    return [round(thickness + gap * (k + 1) + width * (k + 0.5), 6) for k in range(n)]


def place_windows(walls: tuple[Wall, ...],
                  settings: FloorSettings) -> tuple[tuple[Wall, ...], tuple[Window, ...]]:
    """Cut ``settings.windows_per_wall`` windows into every outer wall.

    Parameters
    ----------
    walls
        The floor's walls; outer walls have their room on the left (``rooms[0]``).
    settings
        Window count, width, height and sill, and the wall thickness.

    Returns
    -------
    (walls, windows)
        The walls with ``Opening(kind="window")`` appended to the outer ones, and one
        :class:`cga.model.Window` record per opening, numbered in wall order.
    """
    out_walls = []
    windows: list[Window] = []
    for wall in walls:
        if not wall.outer:
            out_walls.append(wall)
            continue
        centres = window_centres(wall.length, settings.windows_per_wall,
                                 settings.window_width, settings.wall_thickness)
        openings = tuple(Opening("window", c, settings.window_width, settings.window_height,
                                 settings.window_sill) for c in centres)
        for c in centres:
            windows.append(Window(len(windows), wall.id, wall.rooms[0], wall.point_at(c),
                                  settings.window_width, settings.window_height,
                                  settings.window_sill))
        out_walls.append(replace(wall, openings=wall.openings + openings))
    return tuple(out_walls), tuple(windows)
