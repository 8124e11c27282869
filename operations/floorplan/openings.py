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

from cga.model import Diagnostic, FloorSettings, Opening, Wall, Window

__all__ = ["MIN_GAP", "window_centres", "place_windows", "window_shortfall"]

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


def window_shortfall(walls: tuple[Wall, ...], settings: FloorSettings,
                     floor: int) -> Diagnostic | None:
    """What :func:`place_windows` left out of a floor's outer walls, in words (None
    when every outer wall segment got ``settings.windows_per_wall`` windows).

    A warning when no window fits at all (a window wider than every wall's free span),
    else an info: short segments take fewer windows by design, but the user asked for
    more and should be able to see where the count went."""
    outer = [w for w in walls if w.outer]
    asked = settings.windows_per_wall * len(outer)
    placed = sum(o.kind == "window" for w in outer for o in w.openings)
    if asked <= 0 or placed >= asked:
        return None
    longest = max(w.length for w in outer) - 2 * settings.wall_thickness
    if placed == 0:
        return Diagnostic(
            "warning", "make_floor",
            f"no window fits: a window {settings.window_width:.2f} m wide with "
            f"{MIN_GAP:.2f} m on each side needs {settings.window_width + 2 * MIN_GAP:.2f} m of "
            f"wall, and the longest outer wall has {longest:.2f} m free between its corners; "
            f"the floor has no windows", floor=floor)
    short = sum(sum(o.kind == "window" for o in w.openings) < settings.windows_per_wall
                for w in outer)
    return Diagnostic(
        "info", "make_floor",
        f"placed {placed} of {asked} windows ({settings.windows_per_wall} per outer wall "
        f"segment): {short} of {len(outer)} segments are too short for all of theirs "
        f"(each window takes {settings.window_width + MIN_GAP:.2f} m of wall: its width and "
        f"a {MIN_GAP:.2f} m gap)", floor=floor)
