"""Euclidean distance transforms of boolean grids, bit for bit those of scipy, faster.

The navigability check and the difficulty metrics take many exact Euclidean distance
transforms of occupancy grids (clearances, the robot's body, one per disc radius of the
local width). The ``edt`` package (Silversmith et al., seung-lab: the separable exact
algorithm of Meijster et al. 2000 with the lower envelope of parabolas of Felzenszwalb
and Huttenlocher 2012) computes them faster than ``scipy.ndimage.distance_transform_edt``
and imports in milliseconds. Its squared distances are float32 sums of squared whole cell
offsets, exact below 2**24, so their float64 square root is the very number scipy
returns (scipy takes the float64 square root of the same whole number). A grid whose
diagonal reaches 2**12 cells, whose squared distances could pass 2**24, is left to scipy.

The grid morphology the check needs besides (:func:`disc_dilation`, :func:`disc_dilations`,
:func:`diamond_dilation`, :func:`component_labels`) is here too, in numpy and SciPy's
sparse graphs, so a build never imports ``scipy.ndimage``: its import alone costs
0.16 s of CPU, most of it SciPy rewriting docstrings (issue 21).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

__all__ = ["component_labels", "diamond_dilation", "disc_dilation", "disc_dilations",
           "distance_to_false", "squared_distance_to_false", "squared_reach"]

_EXACT_DIAGONAL_SQUARED = 2**24
"""Squared distances (cells²) below this are whole numbers in float32."""


def squared_distance_to_false(inside: np.ndarray) -> np.ndarray:
    """``float[rows, cols]``: the squared distance (cells², a whole number) from each
    cell centre to the nearest false cell's centre, 0 on false cells. ``inside`` must
    have a false cell."""
    rows, cols = inside.shape
    if rows * rows + cols * cols >= _EXACT_DIAGONAL_SQUARED:
        from scipy import ndimage

        return np.rint(np.square(ndimage.distance_transform_edt(inside)))
    import edt

    return edt.edtsq(np.ascontiguousarray(inside, dtype=bool), black_border=False, parallel=1)


def distance_to_false(inside: np.ndarray) -> np.ndarray:
    """``float64[rows, cols]``: the distance (in cells) from each cell centre to the
    nearest false cell's centre, 0 on false cells: exactly what
    ``scipy.ndimage.distance_transform_edt(inside)`` returns. ``inside`` must have a
    false cell."""
    return np.sqrt(squared_distance_to_false(inside).astype(np.float64))


def squared_reach(radius: float, resolution: float) -> int:
    """The largest squared cell distance ``d2`` with ``sqrt(d2) * resolution <= radius``
    in float64, so that ``distance_to_false(m) * resolution <= radius`` and
    ``squared_distance_to_false(m) <= squared_reach(radius, resolution)`` pick the same
    cells (both sides are monotone in ``d2``); -1 when not even 0 is within reach."""
    if not 0.0 * resolution <= radius:
        return -1
    d2 = math.floor((radius / resolution) ** 2)
    while math.sqrt(d2 + 1) * resolution <= radius:
        d2 += 1
    while d2 > 0 and math.sqrt(d2) * resolution > radius:
        d2 -= 1
    return d2


def disc_dilation(mask: np.ndarray, reach: int) -> np.ndarray:
    """``bool[rows, cols]``: the cells whose squared distance (cells²) to a true cell of
    ``mask`` is at most ``reach`` (none when ``reach`` < 0), exactly
    ``squared_distance_to_false(~mask) <= reach``.

    The disc is the union of its rows, so the dilation is: ``mask`` grown sideways by
    each row's half width (grown one cell at a time, each width kept), then those
    stacked up and down: about ``3·√reach`` ors of the whole grid, where a distance
    transform (or a dilation by the disc's ``≈3·reach`` cells) costs more when only the
    cells within one reach are wanted. The grid is laid out flat with a false margin as
    wide as the disc right of every row, so a sideways shift is one contiguous or of the
    flat array that never carries a cell onto the next row (an or of a column slice
    costs about three times as much): the result is a view without the margin.
    """
    if reach < 0:
        return np.zeros_like(mask, dtype=bool)
    rows, cols = mask.shape
    half = _half_widths(reach, mask.shape)
    top = len(half) - 1
    width = cols + half[0]
    framed = np.zeros((rows, width), dtype=bool)
    framed[:, :cols] = mask
    seeds = framed.ravel()
    kept, spans, grown = set(half), {0: seeds}, seeds.copy()
    for w in range(1, half[0] + 1):
        grown[w:] |= seeds[:-w]
        grown[:-w] |= seeds[w:]
        if w in kept:
            spans[w] = grown.copy()
    out = spans[half[0]].copy()
    for dy in range(1, top + 1):
        row, shift = spans[half[dy]], dy * width
        out[shift:] |= row[:-shift]
        out[:-shift] |= row[shift:]
    return out.reshape(rows, width)[:, :cols]


def _half_widths(reach: int, shape: tuple[int, ...]) -> list[int]:
    """The half widths of the rows of the disc of squared radius ``reach`` (≥ 0), from
    its middle row (the widest) to its top, none wider or more rows than the grid:
    wider rows or farther ones add nothing."""
    rows, cols = shape
    top = min(math.isqrt(reach), rows)
    return [min(math.isqrt(reach - dy * dy), cols) for dy in range(top + 1)]


def disc_dilations(planes: np.ndarray, reaches: Sequence[int]) -> np.ndarray:
    """``uint8[rows, cols]``: bit ``j`` set on the cells of ``disc_dilation(planes & 1 <<
    j, reaches[j])``, for the bit planes ``j < len(reaches)`` (at most 8) of the byte grid
    ``planes``: eight dilations by discs of about one size at the cost of about three.

    One or of the byte grid moves all eight planes. A dilation is the disc's rows
    stacked up and down, written as Horner's scheme: ``out = span(top) ; out = out ∪ out
    moved one row up and down ∪ span(dy)`` for ``dy`` from the disc's top row down to
    its middle, ``span(dy)`` the plane grown sideways by that row's half width (each
    row's cells move ``|dy|`` rows at most, and a row's span lies within each wider
    one's). The half widths only grow on the way, so ``span`` is grown one cell at a
    time (:func:`_horner_schedule`), only in the planes still short of their width; a
    plane joins ``out`` at its disc's top row. Laid out flat with a zero margin as in
    :func:`disc_dilation`."""
    if len(reaches) > 8:
        raise ValueError("at most 8 reaches: one per bit of a byte")
    rows, cols = planes.shape
    halves = {j: _half_widths(reach, (rows, cols)) for j, reach in enumerate(reaches)
              if reach >= 0}
    if not halves:
        return np.zeros((rows, cols), dtype=np.uint8)
    width = cols + max(half[0] for half in halves.values())
    framed = np.zeros((rows, width), dtype=np.uint8)
    framed[:, :cols] = planes & np.uint8(sum(1 << j for j in halves))
    spans, out = framed.ravel(), np.zeros(rows * width, dtype=np.uint8)
    moving = np.empty_like(out)
    for grows, active in _horner_schedule(halves):
        for grown in grows:
            _dilate_by_one(spans, 1, grown, moving)
        _dilate_by_one(out, width, 0xFF, moving)
        out |= spans if active == 0xFF else spans & np.uint8(active)
    return out.reshape(rows, width)[:, :cols]


def _horner_schedule(halves: dict[int, list[int]]) -> list[tuple[list[int], int]]:
    """For each row of :func:`disc_dilations`'s Horner scheme, from the top row down:
    the planes (a byte each) grown sideways by one cell, step by step, from their half
    widths one row up (0 above a disc's top) to their half widths in this row, and the
    planes then added to the output (those whose disc reaches the row)."""
    bits = np.array([1 << j for j in halves])
    tall = max(len(half) for half in halves.values())
    widths = np.zeros((len(bits), tall + 1), dtype=np.int64)  # [plane, row], 0 beyond
    for plane, half in enumerate(halves.values()):
        widths[plane, :len(half)] = half
    gaps = widths[:, :-1] - widths[:, 1:]  # each row's half width less the one above
    grows = ((gaps[:, :, None] > np.arange(gaps.max())) * bits[:, None, None]).sum(axis=0)
    added = np.arange(tall) < np.array([[len(half)] for half in halves.values()])
    active = (added * bits[:, None]).sum(axis=0)
    return [(grows[dy, :steps].tolist(), int(active[dy]))
            for dy, steps in reversed(list(enumerate(gaps.max(axis=0))))]


def _dilate_by_one(flat: np.ndarray, stride: int, planes: int, moving: np.ndarray) -> None:
    """Grows the bit ``planes`` of ``flat`` by one step of ``stride`` cells both ways
    (a step off either end is dropped), in place; ``moving`` is scratch of its size."""
    np.bitwise_and(flat, np.uint8(planes), out=moving)
    flat[stride:] |= moving[:-stride]
    flat[:-stride] |= moving[stride:]


def diamond_dilation(mask: np.ndarray, steps: int) -> np.ndarray:
    """``bool[rows, cols]``: the cells at most ``steps`` moves up, down, left or right
    from a true cell of ``mask`` (``steps`` ≥ 1): exactly
    ``scipy.ndimage.binary_dilation(mask, iterations=steps)`` with its default cross,
    one shift-and-or per side and step."""
    out = np.asarray(mask, dtype=bool).copy()
    for _ in range(steps):
        grown = out.copy()
        grown[1:] |= out[:-1]
        grown[:-1] |= out[1:]
        grown[:, 1:] |= out[:, :-1]
        grown[:, :-1] |= out[:, 1:]
        out = grown
    return out


def component_labels(mask: np.ndarray) -> np.ndarray:
    """``int[rows, cols]``: the 4-connected pieces of ``mask``, numbered from 1 (0 on
    false cells): the same pieces as ``scipy.ndimage.label(mask)[0]``, perhaps numbered
    in another order (callers compare labels, never read their values). The pieces are
    the connected components of the graph of true cells and their right and lower
    neighbours (SciPy's sparse ``connected_components``)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    mask = np.asarray(mask, dtype=bool)
    flat = np.flatnonzero(mask)
    numbers = np.full(mask.size, -1, dtype=np.int64)
    numbers[flat] = np.arange(len(flat))
    index = numbers.reshape(mask.shape)
    across = mask[:, :-1] & mask[:, 1:]
    down = mask[:-1] & mask[1:]
    u = np.concatenate([index[:, :-1][across], index[:-1][down]])
    v = np.concatenate([index[:, 1:][across], index[1:][down]])
    graph = coo_matrix((np.ones(len(u), dtype=np.int8), (u, v)), shape=(len(flat), len(flat)))
    _, pieces = connected_components(graph, directed=False)
    labels = np.zeros(mask.shape, dtype=np.int64)
    labels.ravel()[flat] = pieces + 1
    return labels
