"""Where the corridor or hall of a floor goes, before the rooms are cut (docs/architecture.md).

Every mode returns fixed faces for :func:`.bsp.partition`: the circulation (one face,
never cut) and, for the TFG's rooms-per-side control, the rooms along it.

* ``"spine"``: a double-loaded corridor along the long axis of the footprint, wall to
  wall, with rooms on both sides (TFG corridor offices). ``position`` places it across
  the building (0.5: in the middle), so one side can be deeper than the other. A
  building so deep that the rooms on either side would be deeper than ``max_depth``
  gets as many parallel spines as keep every band of rooms within it, evenly spaced and
  joined by a cross corridor through the middle of the bands between them (one
  circulation face, a ladder): every room between two spines opens onto one of them,
  and a bathroom need not run the depth of a 9 m band. So does a ``centre_line``
  corridor on a rectangle that deep (its centre line is its spine).
* ``"hall"``: the same across the short axis, a hall from the front wall through the
  depth of a house with the rooms on both sides of it.
* ``"centre_line"``: a corridor along the centre line of every wing of an L, U or T
  footprint (Twente: "a corridor spine derived from the footprint", rooms between
  corridor and shell). The footprint is cut into rectangles by slabs; the largest is the
  main wing with the corridor along its long axis, wall to wall; every other wing gets a
  corridor from there, perpendicular to the wall it shares, to its far outer wall.

Every corridor reaches the outer wall (so the front door or a window can open into it),
and the rooms between corridor and shell must be at least ``min_depth`` deep.

References
----------
TFG "Generación procedural de entornos de oficina", corridor layout with ``n_left``
and ``n_right`` offices. Twente, "Indoor L-systems", corridor spine, min room depth
2.5 m. Marson & Musse, "Automatic real-time generation of floor plans based on
squarified treemaps", corridors inserted between rooms.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Literal

import shapely
from shapely.geometry import Polygon, box
from shapely.geometry.polygon import orient

from .bsp import FixedFace

__all__ = ["CORRIDOR_MODES", "CirculationError", "CorridorSpec", "circulation_faces"]

CORRIDOR_MODES = ("none", "spine", "hall", "centre_line")
"""Values of ``make_floor``'s ``corridor`` option."""

Mode = Literal["none", "spine", "hall", "centre_line"]
Point = tuple[float, float]
Rect = tuple[float, float, float, float]
_TOL = 1e-7


class CirculationError(ValueError):
    """The footprint cannot hold the corridor asked for (the message says why)."""


@dataclass(frozen=True)
class CorridorSpec:
    """The corridor options of ``make_floor``.

    ``width`` is the clear corridor width between wall centre lines (m);
    ``position`` the corridor's place across the building for ``spine``/``hall``
    (fraction of the depth, 0.5 in the middle); ``min_depth`` the least depth of the
    rooms between corridor and shell; ``n_left``/``n_right`` the rooms on each side of a
    ``spine`` (0: the BSP decides), left being the side of smaller coordinate.
    ``single_loaded``: a ``spine`` or ``hall`` runs along the outer wall on the side
    ``position`` leans to, with rooms on the other side only (a building too shallow
    for rooms on both sides; ``make_floor`` falls back to it with a warning).
    """

    mode: Mode = "none"
    width: float = 1.2
    position: float = 0.5
    min_depth: float = 2.5
    n_left: int = 0
    n_right: int = 0
    single_loaded: bool = False
    max_depth: float = math.inf

    def spines(self, depth: float) -> int:
        """How many parallel spines a building ``depth`` deep across them gets: the
        fewest that leave no band of rooms deeper than ``max_depth`` (one for a
        ``hall``, a single-loaded corridor or rooms counted per side)."""
        if (self.mode != "spine" or self.single_loaded or self.n_left or self.n_right
                or not math.isfinite(self.max_depth)):
            return 1
        count = 1
        while (depth - count * self.width) / (count + 1) > self.max_depth + _TOL:
            count += 1
        return count


def circulation_faces(footprint: Sequence[Point], spec: CorridorSpec) -> list[FixedFace]:
    """The fixed faces for ``spec`` on ``footprint`` (empty for mode ``"none"``).

    Raises
    ------
    CirculationError
        The footprint is too small for the corridor and rooms of ``min_depth`` on both
        sides, or (``centre_line``) it is not rectilinear or its wings do not attach to
        the main wing's long side.
    """
    if spec.mode == "none":
        return []
    return list(_faces(tuple(map(tuple, footprint)), spec))


@functools.lru_cache(maxsize=64)
def _faces(footprint: tuple[Point, ...], spec: CorridorSpec) -> tuple[FixedFace, ...]:
    """:func:`circulation_faces` on hashable arguments, cached (every floor of a
    building asks for the same corridor)."""
    outline = Polygon(footprint)
    if spec.mode == "centre_line" and _deep_rectangle(outline, spec):
        spec = replace(spec, mode="spine")  # a rectangle's centre line is its spine
    if spec.mode == "centre_line":
        corridor = _centre_line(outline, spec)
        return (FixedFace(_ring(corridor), circulation=True, kind="corridor"),)
    along_long = spec.mode == "spine"
    corridor, sides = _straight(outline, spec, along_long)
    faces = [FixedFace(_ring(corridor), circulation=True,
                       kind="corridor" if along_long else "hall")]
    for side, count in zip(sides, (spec.n_left, spec.n_right)):
        if side.area > _TOL:  # a single-loaded corridor leaves one side empty
            faces += [FixedFace(_ring(room), kind="room")
                      for room in _divide(side, count, along_long)]
    return tuple(faces)


def _straight(outline: Polygon, spec: CorridorSpec,
              along_long: bool) -> tuple[Polygon, tuple[Polygon, Polygon]]:
    """A wall-to-wall corridor across the bounding box and the two sides it leaves."""
    minx, minz, maxx, maxz = outline.bounds
    runs_x = (maxx - minx >= maxz - minz) == along_long
    lo, hi = (minz, maxz) if runs_x else (minx, maxx)
    depth = hi - lo
    spines = spec.spines(depth)
    if spines > 1:
        return _ladder(outline, spec, runs_x, spines), (Polygon(), Polygon())
    loaded = 1 if spec.single_loaded else 2
    need = spec.width + loaded * spec.min_depth
    if depth < need - _TOL:
        raise CirculationError(
            f"the building is {depth:.2f} m deep across the corridor; a {spec.width:.2f} m "
            f"corridor with rooms at least {spec.min_depth:.2f} m deep on "
            f"{'one side' if spec.single_loaded else 'both sides'} needs {need:.2f} m")
    if spec.single_loaded:
        start = lo if spec.position < 0.5 else hi - spec.width
    else:
        start = lo + spec.position * depth - spec.width / 2
        start = min(max(start, lo + spec.min_depth), hi - spec.min_depth - spec.width)
    start = round(start, 6)
    end = round(start + spec.width, 6)
    # a corridor flush with an outer wall ends on the wall's own coordinate: rounded, it
    # could stop short of it by a sliver no room fits in (a 6.0234375 m deep floor)
    start, end = (lo if abs(start - lo) <= 1e-6 else start), (hi if abs(end - hi) <= 1e-6 else end)
    strip = box(minx - 1, start, maxx + 1, end) if runs_x else box(start, minz - 1, end, maxz + 1)
    corridor = outline.intersection(strip)
    if not isinstance(corridor, Polygon) or not _is_rectangle(corridor) \
            or abs(corridor.area - (end - start) * (maxx - minx if runs_x else maxz - minz)) > 1e-6:
        raise CirculationError("a straight corridor from wall to wall does not fit this "
                               "footprint; use corridor=\"centre_line\" for L, U or T footprints")
    band = (lambda a, b: box(minx - 1, a, maxx + 1, b)) if runs_x else (
        lambda a, b: box(a, minz - 1, b, maxz + 1))
    sides = (outline.intersection(band(lo - 1, start)), outline.intersection(band(end, hi + 1)))
    _check_free(outline.difference(corridor), spec)
    return corridor, sides


def _is_rectangle(polygon: Polygon) -> bool:
    """Whether ``polygon`` fills its bounding box (an axis-aligned rectangle)."""
    return abs(polygon.area - shapely.envelope(polygon).area) <= 1e-6


def _deep_rectangle(outline: Polygon, spec: CorridorSpec) -> bool:
    """Whether ``outline`` is a rectangle too deep across its long axis for one spine
    (a one-wing footprint given ``centre_line``, e.g. a grammar for an L built on a
    rectangular ``--lot``)."""
    if not _is_rectangle(outline):
        return False
    minx, minz, maxx, maxz = outline.bounds
    return replace(spec, mode="spine").spines(min(maxx - minx, maxz - minz)) > 1


def _ladder(outline: Polygon, spec: CorridorSpec, runs_x: bool, count: int) -> Polygon:
    """``count`` evenly spaced spines across a rectangle's depth, joined by a cross
    corridor in the middle of its length (see the module notes)."""
    if not _is_rectangle(outline):
        raise CirculationError("parallel spines need a rectangular footprint; use "
                               "corridor=\"centre_line\" for L, U or T footprints")
    minx, minz, maxx, maxz = outline.bounds
    lo, hi = (minz, maxz) if runs_x else (minx, maxx)
    start, end = (minx, maxx) if runs_x else (minz, maxz)
    band = (hi - lo - count * spec.width) / (count + 1)
    near = [round(lo + (k + 1) * band + k * spec.width, 6) for k in range(count)]
    far = [round(e + spec.width, 6) for e in near]
    middle = round((start + end) / 2 - spec.width / 2, 6)
    pieces = [(start, e, end, f) for e, f in zip(near, far)]  # (along0, across0, ...)
    pieces += [(middle, f, round(middle + spec.width, 6), e) for f, e in zip(far, near[1:])]
    boxes = [box(a0, c0, a1, c1) if runs_x else box(c0, a0, c1, a1) for a0, c0, a1, c1 in pieces]
    ladder = shapely.union_all(boxes)
    _check_free(outline.difference(ladder), spec)
    return orient(shapely.simplify(ladder, 0.0), sign=1.0)


def _divide(side: Polygon | shapely.Geometry, count: int, along_long: bool) -> list[Polygon]:
    """``count`` rooms of equal width along a rectangular side (none for count 0)."""
    if count <= 0:
        return []
    if not isinstance(side, Polygon) or not _is_rectangle(side):
        raise CirculationError("rooms per side (n_left, n_right) need a rectangular footprint")
    minx, minz, maxx, maxz = side.bounds
    if maxx - minx >= maxz - minz:
        cuts = [minx + (maxx - minx) * k / count for k in range(count + 1)]
        return [box(round(a, 6), minz, round(b, 6), maxz) for a, b in zip(cuts, cuts[1:])]
    cuts = [minz + (maxz - minz) * k / count for k in range(count + 1)]
    return [box(minx, round(a, 6), maxx, round(b, 6)) for a, b in zip(cuts, cuts[1:])]


def _centre_line(outline: Polygon, spec: CorridorSpec) -> Polygon:
    """The corridor through every wing (see the module notes)."""
    coords = list(outline.exterior.coords)
    if any(abs(a[0] - b[0]) > _TOL and abs(a[1] - b[1]) > _TOL for a, b in zip(coords, coords[1:])):
        raise CirculationError("corridor=\"centre_line\" needs a rectilinear footprint "
                               "(walls along x and z only)")
    options = []
    for horizontal in (True, False):
        wings = _slabs(outline, horizontal)
        if not wings:  # every side shorter than the tolerance: a speck, not a building
            raise CirculationError("the footprint is too small for a corridor")
        main = max(range(len(wings)), key=lambda i: (_area(wings[i]), -i))
        x0, z0, x1, z1 = wings[main]
        if (x1 - x0 >= z1 - z0) == horizontal or len(wings) == 1:
            options.append((len(wings), -_area(wings[main]), not horizontal, wings, main))
    if not options:
        raise CirculationError("no wing of this footprint runs along the side its other "
                               "wings attach to; use corridor=\"spine\" or none")
    errors = []
    for _, _, vertical, wings, main in sorted(options, key=lambda o: o[:3]):
        try:
            return _wing_corridors(outline, wings, main, spec, not vertical)
        except CirculationError as error:
            errors.append(error)
    raise errors[0]


def _wing_corridors(outline: Polygon, wings: list[Rect], main: int, spec: CorridorSpec,
                    horizontal: bool) -> Polygon:
    """The main wing's corridor joined by one through every other wing."""
    strips = [_main_strip(wings[main], spec, horizontal)]
    for i, wing in enumerate(wings):
        if i != main:
            if box(*wing).intersection(box(*wings[main])).length <= _TOL:
                raise CirculationError("a wing does not share a wall with the main wing")
            strips.append(_wing_strip(wing, wings[main], strips[0], spec, horizontal))
    corridor = shapely.union_all([box(*s) for s in strips])
    corridor = shapely.simplify(corridor, 0.0)
    if not isinstance(corridor, Polygon) or corridor.interiors:
        raise CirculationError("the wings' corridors do not join into one corridor")
    if corridor.difference(outline).area > 1e-9:
        raise CirculationError("a wing's corridor would leave the footprint")
    _check_free(outline.difference(corridor), spec)
    return corridor


def _area(r: Rect) -> float:
    return (r[2] - r[0]) * (r[3] - r[1])


def _slabs(outline: Polygon, horizontal: bool) -> list[Rect]:
    """The footprint cut into rectangles by lines through its corners (along x when
    ``horizontal``), neighbouring slab pieces of equal extent merged."""
    k = 1 if horizontal else 0
    marks = sorted({round(c[k], 9) for c in outline.exterior.coords})
    pieces: list[Rect] = []
    for a, b in zip(marks, marks[1:]):
        band = box(-1e9, a, 1e9, b) if horizontal else box(a, -1e9, b, 1e9)
        part = outline.intersection(band)
        for g in getattr(part, "geoms", [part]):
            if isinstance(g, Polygon) and g.area > _TOL:
                pieces.append(tuple(round(v, 9) for v in g.bounds))
    merged = True
    while merged:
        merged = False
        for i, p in enumerate(pieces):
            for j, q in enumerate(pieces):
                if i == j:
                    continue
                if horizontal and (p[0], p[2]) == (q[0], q[2]) and p[3] == q[1]:
                    pieces[i] = (p[0], p[1], p[2], q[3])
                elif not horizontal and (p[1], p[3]) == (q[1], q[3]) and p[2] == q[0]:
                    pieces[i] = (p[0], p[1], q[2], p[3])
                else:
                    continue
                del pieces[j]
                merged = True
                break
            if merged:
                break
    return pieces


def _main_strip(wing: Rect, spec: CorridorSpec, horizontal: bool) -> Rect:
    x0, z0, x1, z1 = wing
    lo, hi = (z0, z1) if horizontal else (x0, x1)
    _check_depth(hi - lo, spec, "the main wing")
    a = round((lo + hi) / 2 - spec.width / 2, 6)
    b = round(a + spec.width, 6)
    return (x0, a, x1, b) if horizontal else (a, z0, b, z1)


def _wing_strip(wing: Rect, main: Rect, spine: Rect, spec: CorridorSpec,
                horizontal: bool) -> Rect:
    """The corridor of a wing attached to the main wing: across the shared wall, from
    the main corridor to the wing's far outer wall, in the middle of the wing."""
    x0, z0, x1, z1 = wing
    if horizontal:  # wings sit above or below the main wing: corridor along z
        if not (z0 >= main[3] - _TOL or z1 <= main[1] + _TOL):
            raise CirculationError("a wing does not attach to the main wing's long side")
        _check_depth(x1 - x0, spec, "a wing")
        a = round((x0 + x1) / 2 - spec.width / 2, 6)
        b = round(a + spec.width, 6)
        return (a, spine[3], b, z1) if z0 >= main[3] - _TOL else (a, z0, b, spine[1])
    if not (x0 >= main[2] - _TOL or x1 <= main[0] + _TOL):
        raise CirculationError("a wing does not attach to the main wing's long side")
    _check_depth(z1 - z0, spec, "a wing")
    a = round((z0 + z1) / 2 - spec.width / 2, 6)
    b = round(a + spec.width, 6)
    return (spine[2], a, x1, b) if x0 >= main[2] - _TOL else (x0, a, spine[0], b)


def _check_depth(depth: float, spec: CorridorSpec, what: str) -> None:
    need = spec.width + 2 * spec.min_depth
    if depth < need - _TOL:
        raise CirculationError(
            f"{what} is {depth:.2f} m wide across its corridor; a {spec.width:.2f} m corridor "
            f"with rooms at least {spec.min_depth:.2f} m deep on both sides needs {need:.2f} m")


def _check_free(free: shapely.Geometry, spec: CorridorSpec) -> None:
    """Every point between corridor and shell lies in a ``min_depth`` square there."""
    r = spec.min_depth / 2 - 1e-4
    opened = free.buffer(-r, join_style="mitre").buffer(r, join_style="mitre")
    if opened.area < free.area - 1e-4:
        raise CirculationError(
            f"part of the floor between the corridor and the outer walls is less than "
            f"min_room_depth = {spec.min_depth:.2f} m deep; move or narrow the corridor, or "
            f"lower min_room_depth")


def _ring(polygon: Polygon) -> tuple[Point, ...]:
    return tuple((float(x), float(z)) for x, z in list(orient(polygon).exterior.coords)[:-1])
