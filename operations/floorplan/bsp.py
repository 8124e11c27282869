"""Binary space partition of a floor into rooms over a half-edge structure.

The floor is the root leaf; every split cuts one leaf (a DCEL face) along an
axis-aligned chord, which becomes an inner wall; the leaves are the rooms (thesis §3.2,
§5.1.2, Algorithms 8–10). The thesis always cut in the middle with alternating axes, so
every floor looked the same; here (docs/architecture.md, "Floor plans"):

* the largest leaf is cut first (ties by id), falling back to smaller ones;
* the cut runs across the leaf's longer side (either way when the bounding box is within
  :data:`SQUARE_RATIO` of square), falling back to the other axis;
* the position is drawn uniformly from ``cut_range`` (fractions of the leaf's extent)
  and snapped to a ``grid`` (1 cm), so outputs are clean numbers;
* both new rooms must stay at least ``min_width`` wide everywhere (every point of a room
  lies in a ``min_width`` square inside it) and ``min_area`` large; when the drawn
  position breaks a rule, nearby positions are tried, nearest first;
* a cut keeps ``min_offset`` away from the leaf's corners and from walls that end on its
  edges, or lines up with one exactly, so no sliver wall segments or jogs of a few
  centimetres appear (lining up with a corner of an L continues the footprint's edge).

Concave leaves (pieces of L, U or T footprints) work the same way: a line may cross
such a leaf several times; each crossing interval is a chord that splits it in two, and
the longest feasible one is taken.

Fixed faces (docs/architecture.md): corridors, entry halls and stair cores can be given up front
(:class:`FixedFace`). They become faces of the DCEL before the first cut, and no cut
ever crosses them; the BSP partitions only the free pieces around them
(:mod:`.tiling`). A leaf that shares wall with a circulation face keeps that access:
both rooms of a cut must keep at least ``min_contact`` metres of wall on circulation
(room for a door and its margins), so every room cut from such a leaf opens onto the
corridor or hall, as in the corridor offices of the TFG and the Twente corridor spine.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from shapely.geometry import Polygon

from .dcel import DCEL, EPS, Face, point_in_ring, signed_area
from .tiling import tile_with_fixed_faces

__all__ = ["SQUARE_RATIO", "Cut", "FixedFace", "Partition", "partition"]

SQUARE_RATIO = 1.1
"""Leaves whose bounding box is closer to square than this pick the cut axis at random."""

Point = tuple[float, float]
_AXES: dict[str, int] = {"x": 0, "z": 1}
_WIDTH_SLACK = 1e-4  # m; cut positions are on a 1 cm grid, so real violations are larger


@dataclass(frozen=True)
class Cut:
    """One split of the BSP: leaf ``face`` was cut along ``axis = position``.

    ``face`` keeps its id for the part left of ``start``→``end``; the other part is the
    new leaf ``new_face``. ``axis`` is the coordinate the cut line holds constant
    (``"x"``: the line ``x = position``, cutting across the x extent).
    """

    face: int
    new_face: int
    axis: Literal["x", "z"]
    position: float
    start: Point
    end: Point


@dataclass(frozen=True)
class FixedFace:
    """A face placed before the BSP runs and never cut: a corridor, hall or stair core.

    ``polygon`` is its outline ``(x, z)`` inside the footprint; ``circulation`` marks
    space whose job is to connect (rooms cut next to it keep a door's length of wall on
    it); ``kind`` names it for the plan (``"corridor"``, ``"hall"``, ``"core"``, ...).
    """

    polygon: tuple[Point, ...]
    circulation: bool = False
    kind: str = "fixed"


@dataclass(frozen=True)
class Partition:
    """The result of :func:`partition`: the DCEL (faces are the rooms) and its cuts.

    ``shortfall`` says why fewer than ``requested`` cuts were made (None when all were).
    Faces ``0 .. len(fixed) - 1`` are the fixed faces, in the order given; the free
    pieces around them and the rooms cut from those follow.
    """

    dcel: DCEL
    cuts: tuple[Cut, ...]
    requested: int
    shortfall: str | None = None
    fixed: tuple[FixedFace, ...] = ()

    @property
    def circulation(self) -> frozenset[int]:
        """Ids of the faces that are circulation (fixed faces marked so)."""
        return frozenset(i for i, f in enumerate(self.fixed) if f.circulation)


@dataclass(frozen=True)
class _Rules:
    min_width: float
    min_area: float
    cut_range: tuple[float, float]
    grid: float
    min_offset: float
    min_contact: float = 0.0


@dataclass(frozen=True)
class _Crossing:
    index: int  # ring index of the edge crossed, or of the vertex lying on the line
    point: Point
    at_vertex: bool


def partition(footprint: Sequence[Point], splits: int, rng: np.random.Generator, *,
              min_width: float = 2.4, min_area: float = 6.0,
              cut_range: tuple[float, float] = (0.35, 0.65), grid: float = 0.01,
              min_offset: float = 0.5, fixed: Sequence[FixedFace] = (),
              min_contact: float = 0.0) -> Partition:
    """Cut a footprint into ``splits + 1`` rooms with a randomised BSP.

    With ``fixed`` faces, the free pieces around them are cut instead: ``splits`` cuts
    make ``splits + pieces`` rooms besides the fixed faces.

    Parameters
    ----------
    footprint
        Counter-clockwise simple polygon ``(x, z)`` without repeated or collinear
        vertices (rectilinear footprints: rectangle, L, U, T; convex ones work too).
    splits
        Number of cuts wanted.
    rng
        Random stream for cut positions and near-square axis choices.
    min_width, min_area
        Least width (m) and area (m²) of every room.
    cut_range
        ``(lo, hi)``: the cut position is drawn from this fraction of the leaf's extent.
    grid
        Cut positions are multiples of this (m).
    min_offset
        Least distance (m) between a cut and the leaf's corners and wall ends along the
        cut axis, unless the cut lines up with one exactly.
    fixed
        Faces placed before any cut and never cut (corridors, halls, stair cores).
    min_contact
        Least wall (m) a room keeps on a circulation face when the leaf it is cut from
        has such a wall (0: no requirement).

    Returns
    -------
    Partition
        The DCEL whose faces are the rooms, the cuts in order, and the shortfall reason
        when a leaf could not be cut without breaking ``min_width``/``min_area``.

    Raises
    ------
    ValueError
        An argument is out of range (a caller's bug: ``make_floor`` checks them).
    PartitionError
        The footprint is not a valid polygon, or a fixed face is not a polygon inside the
        footprint apart from the others.

    Notes
    -----
    Each split sorts the leaves (O(k log k)) and tries candidate positions on a leaf of
    n vertices in O(n) each, plus a shapely opening for non-rectangular pieces; a
    10-room floor takes about a millisecond.

    References
    ----------
    H. Fuchs, Z. Kedem, B. Naylor, "On visible surface generation by a priori tree
    structures", SIGGRAPH 1980. Room-generation thesis §3.2, §5.1.2, Algorithms 8–10.
    """
    if splits < 0:
        raise ValueError(f"splits must be ≥ 0, got {splits}")
    lo, hi = cut_range
    if not 0.0 < lo <= hi < 1.0:
        raise ValueError(f"cut_range must satisfy 0 < lo ≤ hi < 1, got {cut_range}")
    if min_width <= 0 or min_area < 0 or grid <= 0 or min_offset < 0 or min_contact < 0:
        raise ValueError("min_width and grid must be > 0, min_area, min_offset and "
                         "min_contact ≥ 0")
    rules = _Rules(min_width, min_area, (lo, hi), grid, min_offset, min_contact)
    fixed = tuple(fixed)
    if fixed:
        rings, _ = tile_with_fixed_faces(footprint, [f.polygon for f in fixed])
        dcel = DCEL.from_polygons(rings)
    else:
        dcel = DCEL.from_polygon(footprint)
    circulation = {dcel.faces[i] for i, f in enumerate(fixed) if f.circulation}
    cuts: list[Cut] = []
    for _ in range(splits):
        cut = _split_largest(dcel, rng, rules, len(fixed), circulation)
        if cut is None:
            return Partition(dcel, tuple(cuts), splits,
                             _shortfall(dcel, rules, len(fixed), circulation), fixed)
        cuts.append(cut)
    return Partition(dcel, tuple(cuts), splits, None, fixed)


def _split_largest(dcel: DCEL, rng: np.random.Generator, rules: _Rules, first_free: int,
                   circulation: set[Face]) -> Cut | None:
    leaves = dcel.faces[first_free:]
    rings = [(f, dcel.points(f)) for f in leaves]
    areas = [signed_area(ring) for _, ring in rings]
    for k in sorted(range(len(rings)), key=lambda k: (-areas[k], k)):
        face, ring = rings[k]
        if areas[k] < 2 * rules.min_area - EPS:
            break  # sorted by area: no smaller leaf can hold two rooms either
        contact = [h.twin.face in circulation for h in dcel.boundary(face)] if circulation else None
        chosen = _choose_cut(ring, rng, rules, contact)
        if chosen is not None:
            axis, position, p, q = chosen
            h = dcel.split_face(face, p, q)
            return Cut(face.id, h.twin.face.id, axis, position, p, q)
    return None


def _shortfall(dcel: DCEL, rules: _Rules, first_free: int, circulation: set[Face]) -> str:
    """Why no room could be cut again: the sizes, or, for a room big enough to halve
    beside circulation, the wall on it both halves must keep."""
    if first_free == len(dcel.faces):
        return "the fixed faces leave no free floor to cut"
    largest = max(dcel.faces[first_free:], key=lambda f: (dcel.area(f), -f.id))
    xs, zs = zip(*dcel.points(largest))
    size = (f"the largest, room {largest.id}, is {max(xs) - min(xs):.2f} × "
            f"{max(zs) - min(zs):.2f} m, {dcel.area(largest):.2f} m²")
    halvable = (max(max(xs) - min(xs), max(zs) - min(zs)) >= 2 * rules.min_width
                and dcel.area(largest) >= 2 * rules.min_area)
    if halvable and circulation and rules.min_contact > 0:
        return (f"no room can be cut again so that both rooms keep {rules.min_contact:.2f} m "
                f"of wall on a hall or corridor, and are {rules.min_width:.2f} m "
                f"wide and {rules.min_area:.2f} m² ({size})")
    return (f"no room can be cut again without making a room narrower than "
            f"{rules.min_width:.2f} m or smaller than {rules.min_area:.2f} m² ({size})")


def _choose_cut(ring: list[Point], rng: np.random.Generator, rules: _Rules,
                contact: list[bool] | None = None,
                ) -> tuple[Literal["x", "z"], float, Point, Point] | None:
    """Pick axis, position and chord for one leaf, or None when no cut is allowed.

    ``contact[i]`` says whether the edge from ``ring[i]`` to ``ring[i + 1]`` lies on a
    circulation face; if the leaf has such wall, both pieces must keep
    ``rules.min_contact`` of it.
    """
    if contact is not None and not (any(contact) and rules.min_contact > 0):
        contact = None
    xs, zs = zip(*ring)
    dx, dz = max(xs) - min(xs), max(zs) - min(zs)
    if max(dx, dz) < SQUARE_RATIO * min(dx, dz):
        axes: list[Literal["x", "z"]] = ["x", "z"] if rng.random() < 0.5 else ["z", "x"]
    else:
        axes = ["x", "z"] if dx >= dz else ["z", "x"]
    for axis in axes:
        k = _AXES[axis]
        marks = sorted({p[k] for p in ring})
        drawn = marks[0] + rng.uniform(*rules.cut_range) * (marks[-1] - marks[0])
        window = _rectangle_window(ring, k, rules, contact)
        if window[0] > window[1]:
            continue  # no position can work: skip the search (the draw above is kept)
        for position in _candidates(drawn, marks, rules):
            if not window[0] <= position <= window[1]:
                continue
            chord = _best_chord(ring, k, position, rules, contact)
            if chord is not None:
                return axis, position, chord[0], chord[1]
    return None


_WINDOW_SLACK = 2e-6
"""m; :func:`_rectangle_window` widens its bounds by this, far more than the rounding
of the exact tests it stands in front of (about 1e-14 m), far less than the 1 cm grid."""


def _rectangle_window(ring: list[Point], k: int, rules: _Rules,
                      contact: list[bool] | None) -> tuple[float, float]:
    """Cut positions on the line ``coord[k] = c`` worth testing with :func:`_best_chord`.

    A quick necessary test, so the search skips the positions (often all of one axis)
    that cannot give two valid rooms; it never decides a cut, :func:`_best_chord` does.
    For an axis-aligned rectangle the two pieces of a cut at ``c`` are rectangles
    ``c - lo`` and ``hi - c`` long by the leaf's depth ``d``: each must be
    ``min_width`` long, ``min_area`` large and keep ``min_contact`` of circulation wall
    (``d`` for every circulation edge at its end of the leaf, its length for every one
    along the cut axis). Each condition bounds ``c`` from one side. Other leaves: the
    whole line.
    """
    xs, zs = {p[0] for p in ring}, {p[1] for p in ring}
    if len(ring) != 4 or len(xs) != 2 or len(zs) != 2:
        return (-math.inf, math.inf)
    ends = sorted(xs if k == 0 else zs)
    across = sorted(zs if k == 0 else xs)
    lo, hi = ends
    depth = across[1] - across[0]
    if depth < rules.min_width - _WINDOW_SLACK:
        return (math.inf, -math.inf)
    need = max(rules.min_width, rules.min_area / depth)  # length of each piece
    first, last = lo + need, hi - need
    if contact is not None:
        along = at_lo = at_hi = 0
        for i, on in enumerate(contact):
            if not on:
                continue
            a, b = ring[i], ring[(i + 1) % 4]
            if a[k] != b[k]:
                along += 1  # cut in two: each piece keeps its length of it
            elif a[k] == lo:
                at_lo += 1
            else:
                at_hi += 1
        for kept, sign in ((at_lo, 1), (at_hi, -1)):
            short = rules.min_contact - _WINDOW_SLACK - kept * depth
            if short <= 0:
                continue
            if not along:
                return (math.inf, -math.inf)
            if sign > 0:
                first = max(first, lo + short / along)
            else:
                last = min(last, hi - short / along)
    return (first - _WINDOW_SLACK, last + _WINDOW_SLACK)


def _straight_vertices(ring: list[Point]) -> list[bool]:
    """Whether each vertex lies on a straight run of the boundary (a T-junction)."""
    n = len(ring)
    out = []
    for i in range(n):
        (ax, az), (bx, bz), (cx, cz) = ring[i - 1], ring[i], ring[(i + 1) % n]
        cross = (bx - ax) * (cz - az) - (bz - az) * (cx - ax)
        out.append(abs(cross) <= EPS * math.dist((ax, az), (cx, cz)))
    return out


def _candidates(drawn: float, marks: list[float], rules: _Rules) -> Iterator[float]:
    """Allowed cut positions, best first.

    ``marks`` are the leaf's vertex coordinates along the axis (its corners and the ends
    of walls meeting its edges). A cut lies strictly inside the leaf's extent and either
    on a mark (lining up with that corner or wall) or at least ``min_offset`` from every
    mark. The drawn position comes first, snapped to the grid, or moved onto a mark
    closer than ``min_offset``; then other positions inside the ``cut_range`` window,
    nearest to the drawn one first, then those outside it (computed only when needed).
    """
    grid, m, w = rules.grid, rules.min_offset, rules.min_width
    lo, hi = marks[0], marks[-1]

    def up(v: float) -> float:
        return round(math.ceil(v / grid - 1e-9) * grid, 10)

    def down(v: float) -> float:
        return round(math.floor(v / grid + 1e-9) * grid, 10)

    def allowed(c: float) -> bool:
        return lo + EPS < c < hi - EPS and all(abs(c - k) >= m - 1e-9 or abs(c - k) <= EPS for k in marks)

    near = sorted((k for k in marks if abs(drawn - k) < m and allowed(k)), key=lambda k: abs(k - drawn))
    first = near[0] if near else round(round(drawn / grid) * grid, 10)
    if allowed(first):
        yield first
    raw = marks + [up(v) for v in np.linspace(lo, hi, 21)[1:-1]]
    for k in marks:
        for d in (m, w, w + m):
            raw += [up(k + d), down(k - d)]
    window = (lo + rules.cut_range[0] * (hi - lo) - EPS, lo + rules.cut_range[1] * (hi - lo) + EPS)
    yield from sorted({c for c in raw if c != first and allowed(c)},
                      key=lambda c: (not window[0] <= c <= window[1], abs(c - drawn), c))


def _chords(ring: list[Point], k: int, c: float) -> list[tuple[_Crossing, _Crossing]]:
    """The chords of the ring on the line ``coord[k] = c``: maximal open intervals of the
    line inside the polygon, between consecutive boundary points."""
    n = len(ring)
    found = []
    for i in range(n):
        a, b = ring[i], ring[(i + 1) % n]
        if abs(a[k] - c) <= EPS:
            found.append(_Crossing(i, a, True))
        elif (a[k] - c) * (b[k] - c) < 0 and abs(b[k] - c) > EPS:
            t = (c - a[k]) / (b[k] - a[k])
            across = a[1 - k] + t * (b[1 - k] - a[1 - k])
            found.append(_Crossing(i, (c, across) if k == 0 else (across, c), False))
    found.sort(key=lambda x: x.point[1 - k])
    chords = []
    for p, q in zip(found, found[1:]):
        mid = ((p.point[0] + q.point[0]) / 2, (p.point[1] + q.point[1]) / 2)
        if q.point[1 - k] - p.point[1 - k] > EPS and point_in_ring(mid, ring):
            chords.append((p, q))
    return chords


def _best_chord(ring: list[Point], k: int, c: float, rules: _Rules,
                contact: list[bool] | None = None) -> tuple[Point, Point] | None:
    """The longest chord on the line ``coord[k] = c`` whose two pieces are valid rooms
    (keeping their access to circulation, see :func:`_choose_cut`)."""
    best = None
    for p, q in _chords(ring, k, c):
        length = q.point[1 - k] - p.point[1 - k]
        if best is not None and length <= best[0] + EPS:
            continue
        one, other = _arc(ring, p, q), _arc(ring, q, p)
        if contact is not None and min(_contact_length(one, p.index, contact),
                                       _contact_length(other, q.index, contact)) \
                < rules.min_contact - 1e-9:
            continue
        if _valid_room(one, rules) and _valid_room(other, rules):
            best = (length, p.point, q.point)
    return None if best is None else (best[1], best[2])


def _contact_length(arc: list[Point], start: int, contact: list[bool]) -> float:
    """Length of the arc's boundary lying on circulation.

    The arc from :func:`_arc` runs along ring edges ``start, start + 1, ...``: its
    segment ``j`` lies on edge ``start + j`` (the closing chord is not counted).
    """
    n = len(contact)
    return sum(math.dist(arc[j], arc[j + 1]) for j in range(len(arc) - 1)
               if contact[(start + j) % n])


def _arc(ring: list[Point], p: _Crossing, q: _Crossing) -> list[Point]:
    """The piece bounded by the ring from ``p`` forward to ``q`` and the chord back."""
    n = len(ring)
    pts = [p.point]
    i = (p.index + 1) % n
    last = q.index if not q.at_vertex else (q.index - 1) % n
    if not (q.at_vertex and i == q.index):
        while True:
            pts.append(ring[i])
            if i == last:
                break
            i = (i + 1) % n
    pts.append(q.point)
    return pts


def _valid_room(points: list[Point], rules: _Rules) -> bool:
    if signed_area(points) < rules.min_area - 1e-9:
        return False
    corners = [p for p, s in zip(points, _straight_vertices(points)) if not s]
    xs, zs = zip(*corners)
    if len(corners) == 4 and len(set(xs)) == 2 and len(set(zs)) == 2:  # a rectangle
        return min(max(xs) - min(xs), max(zs) - min(zs)) >= rules.min_width - 1e-9
    return _wide_enough(corners, rules.min_width)


def _wide_enough(points: list[Point], width: float) -> bool:
    """Every point of the polygon lies in a ``width`` square inside it.

    A morphological opening with a square: mitred offsets are exact for axis-aligned
    edges. The square is 0.2 mm smaller than ``width`` so rooms exactly ``width`` wide
    erode to a thin strip rather than to nothing, and the mitre limit keeps the acute
    ends of such strips from growing spikes when dilated.
    """
    poly = Polygon(points)
    r = width / 2 - _WIDTH_SLACK
    eroded = poly.buffer(-r, join_style="mitre", mitre_limit=2.0)
    opened = eroded.buffer(r, join_style="mitre", mitre_limit=2.0).intersection(poly)
    return opened.area >= poly.area * (1 - 1e-9) - 1e-6
