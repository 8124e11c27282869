"""Hypothesis strategies for storey footprints: rectangles, L, U and T shapes.

Drawn on the 1 cm grid, rotated by quarter turns, mirrored and moved, so the floor
operations meet every orientation.
"""

from __future__ import annotations

from hypothesis import strategies as st
from shapely import affinity
from shapely.geometry import Polygon, box
from shapely.geometry.polygon import orient

__all__ = ["grid", "footprints", "winged_footprints"]


def grid(draw, lo, hi):
    """A length in [lo, hi] on the 1 cm grid."""
    return draw(st.integers(round(lo * 100), round(hi * 100))) / 100


@st.composite
def footprints(draw, kind, width=(8, 24), depth=(6, 18)):
    w, d = grid(draw, *width), grid(draw, *depth)
    if kind == "rectangle":
        shape = box(0, 0, w, d)
    elif kind == "L":
        nx, nz = grid(draw, 0.3 * w, 0.7 * w), grid(draw, 0.3 * d, 0.7 * d)
        shape = Polygon([(0, 0), (w, 0), (w, nz), (nx, nz), (nx, d), (0, d)])
    elif kind == "U":
        left, right = grid(draw, 0.2 * w, 0.4 * w), grid(draw, 0.2 * w, 0.4 * w)
        depth = grid(draw, 0.3 * d, 0.7 * d)
        shape = Polygon([(0, 0), (w, 0), (w, d), (w - right, d), (w - right, d - depth),
                         (left, d - depth), (left, d), (0, d)])
    else:  # T: a bar along the bottom, a stem up from it
        bar = grid(draw, 0.3 * d, 0.6 * d)
        stem_w = grid(draw, 0.3 * w, 0.6 * w)
        x0 = grid(draw, 0.05 * w, w - stem_w - 0.05 * w)
        shape = Polygon([(0, 0), (w, 0), (w, bar), (x0 + stem_w, bar), (x0 + stem_w, d),
                         (x0, d), (x0, bar), (0, bar)])
    return _placed(draw, shape)


def _placed(draw, shape):
    """``shape`` turned by quarter turns, maybe mirrored, moved, on the 1 cm grid."""
    shape = affinity.rotate(shape, 90 * draw(st.integers(0, 3)), origin=(0, 0))
    if draw(st.booleans()):
        shape = affinity.scale(shape, -1, 1, origin=(0, 0))
    dx, dz = grid(draw, -20, 20), grid(draw, -20, 20)
    shape = affinity.translate(shape, dx, dz)
    coords = [(round(x, 2), round(z, 2)) for x, z in shape.exterior.coords]
    return orient(Polygon(coords), 1.0)


@st.composite
def winged_footprints(draw, kind):
    """Rectangle, L, U or T storeys whose wings are 6–12 m deep: room for a corridor with
    rooms on both sides (and sometimes just too little), placed as :func:`footprints`."""
    length, depth = grid(draw, 12, 36), grid(draw, 6, 12)
    wing = (lambda: (grid(draw, 6, 12), grid(draw, 3, 14)))
    if kind == "rectangle":
        shape = box(0, 0, length, grid(draw, 6, 24))
    elif kind == "L":
        (ww, wl) = wing()
        shape = Polygon([(0, 0), (length, 0), (length, depth), (ww, depth), (ww, depth + wl),
                         (0, depth + wl)])
    elif kind == "U":
        (lw, ll), (rw, rl) = wing(), wing()
        length = max(length, lw + rw + 2)
        shape = Polygon([(0, 0), (length, 0), (length, depth + rl), (length - rw, depth + rl),
                         (length - rw, depth), (lw, depth), (lw, depth + ll), (0, depth + ll)])
    else:
        (sw, sl) = wing()
        length = max(length, sw + 2)
        x0 = grid(draw, 0.5, length - sw - 0.5)
        shape = Polygon([(0, 0), (length, 0), (length, depth), (x0 + sw, depth),
                         (x0 + sw, depth + sl), (x0, depth + sl), (x0, depth), (0, depth)])
    return _placed(draw, shape)
