"""Office desk layouts: as many desks as fit, along the walls (MSU procedural interiors).

A furniture row with ``layout`` = ``perimeter`` asks for as many copies of its item
(a desk, with its children: the office chair) as the room holds. The layouts follow the
"Furniture layout" section of the MSU paper; every strategy lays desks out greedily
and the one that seats the most complete desks (desk and all its children) wins, the
first of equals in the order below:

1. **rotation**: walk the walls and lay down as many desks as fit along each, back to
   the wall (the sitter faces the wall), from the end the walk arrives at; walls shorter
   than a desk are skipped. Three walks: clockwise and counter-clockwise from the wall
   holding the room's first door (that wall last), and longest wall first;
2. **left-right**: the walls on one side of the line through the door, perpendicular to
   its wall, then those on the other side, each filled from the end nearest the door's
   wall ("bottom up", so the result tends to be symmetric). *Strict*: walls shorter than
   a desk are skipped; *relaxed*: every wall is used and a desk may hang past the end of
   its wall by up to half its width (a short wall between two recesses), where the free
   floor allows;
3. **brute force**, only for rooms with at most :data:`MAX_BRUTE_FORCE_WALLS` walls
   (3⁴ = 81 combinations; 3⁵ = 243 is too many, as the paper says): each wall long
   enough for a desk gets *none*, *facing the wall* (a row as above) or *back to back*
   (banks of two desks joined at their backs, standing out from the wall into the
   room, each bank as long as the room allows). Rows are laid before banks. A
   combination whose walls, each laid out alone, would not beat the best layout found
   so far is skipped.

Every desk and chair is tested by the room's :class:`~.layout.Layout` like any item:
walls, door swings (no desk in a door's swing), windows, clearances and the passage
rule. Copies are named ``desk``, ``desk#2``, ``desk#3``, ... and their children
``officechair``, ``officechair#2``, ...; all copies share the row's (possibly
jittered) size.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np

from .clearance import OpeningStrip, quarter_turn_towards
from .layout import ItemSpec, Pose
from .placement import Edge, Placer, flush, flush_box

__all__ = ["MAX_BRUTE_FORCE_WALLS", "MAX_COPIES", "MAX_TESTS", "Family", "Run", "Strategy", "DeskLayout",
           "capacity", "copies", "perimeter_strategies", "brute_force_strategies", "lay_out_desks"]

MAX_BRUTE_FORCE_WALLS = 4
"""Rooms with more walls than this get no brute-force search (MSU: 3⁴ = 81 is
manageable, 3⁵ = 243 is not)."""

MAX_COPIES = 64
"""Most copies of a perimeter row per room."""

MAX_TESTS = 500
"""Most desk poses one search tests (each a family test: desk, chair, passage). The
shipped office demos need at most about 360; a hall-sized office would need thousands,
most of them in the brute force, so the search stops there with the best layout so far
(:attr:`DeskLayout.cut_short`)."""

OVERHANG = 0.5
"""Share of its width a desk may hang past the end of its wall in the relaxed
left-right layout."""

_TOLERANCE = 1e-9

Mode = Literal["wall", "bank"]


@dataclass(frozen=True)
class Family:
    """One copy of a perimeter row: the desk and its descendants, renamed."""

    desk: ItemSpec
    children: tuple[ItemSpec, ...]

    @property
    def specs(self) -> tuple[ItemSpec, ...]:
        return (self.desk, *self.children)


def _renamed(spec: ItemSpec, copy: int) -> ItemSpec:
    if copy == 1:
        return spec
    rule = spec.rule
    parent = None if rule.pair_with is None else f"{rule.pair_with}#{copy}"
    return replace(spec, rule=replace(rule, name=f"{rule.name}#{copy}", pair_with=parent))


def copies(desk: ItemSpec, descendants: Sequence[ItemSpec], count: int) -> list[Family]:
    """``count`` families: the row's own (copy 1, names unchanged), then ``name#k``.

    Examples
    --------
    >>> from cga.operations.furniture.rules import FurnitureRule
    >>> desk = ItemSpec(FurnitureRule("Office", "desk", is_along_wall=True), "desk", (1, 1, 1))
    >>> chair = ItemSpec(FurnitureRule("Office", "chair", has_pair=True, pair_with="desk"),
    ...                  "chair", (1, 1, 1))
    >>> [[s.name for s in f.specs] for f in copies(desk, [chair], 2)]
    [['desk', 'chair'], ['desk#2', 'chair#2']]
    >>> copies(desk, [chair], 2)[1].children[0].rule.pair_with
    'desk#2'
    """
    return [Family(_renamed(desk, k), tuple(_renamed(c, k) for c in descendants))
            for k in range(1, count + 1)]


@dataclass(frozen=True)
class Run:
    """Desks along one wall: a row backed against it (``"wall"``) or banks standing
    out from it (``"bank"``), filled from the wall's ``end`` (else its start)."""

    edge: Edge
    mode: Mode
    from_end: bool = False
    overhang: bool = False

    @property
    def descending(self) -> bool:
        """Whether filling goes from the high to the low coordinate along the wall."""
        axis = self.edge.axis
        assert axis is not None
        first, last = ((self.edge.end, self.edge.start) if self.from_end
                       else (self.edge.start, self.edge.end))
        return first[axis] > last[axis]


@dataclass(frozen=True)
class Strategy:
    """A named sequence of runs."""

    name: str
    runs: tuple[Run, ...]


@dataclass(frozen=True)
class DeskLayout:
    """The winning layout: its strategy, how many desks it seats, every pose (desks
    and children, placement order) and whether the search stopped at
    :data:`MAX_TESTS` before trying every strategy."""

    strategy: str
    count: int
    poses: tuple[tuple[ItemSpec, Pose], ...]
    cut_short: bool = False


def _door_point(door: OpeningStrip) -> np.ndarray:
    """The middle of a door's opening on the room's side of its wall."""
    return (np.asarray(door.start) + np.asarray(door.along) * door.width / 2
            + np.asarray(door.normal) * door.face)


def _door_edge(edges: Sequence[Edge], door: OpeningStrip | None) -> int:
    """Index of the wall holding ``door`` (the longest wall when there is none)."""
    if door is None:
        return max(range(len(edges)), key=lambda i: (edges[i].length, -i))
    point = tuple(_door_point(door))
    return min(range(len(edges)), key=lambda i: edges[i].distance_to(point))


def _walk(edges: Sequence[Edge], first: int, step: int) -> list[int]:
    """Edge indices from the one after ``first`` round the ring (``step`` ±1), ending
    with ``first``."""
    n = len(edges)
    return [(first + step * k) % n for k in range(1, n + 1)]


def perimeter_strategies(edges: Sequence[Edge], door: OpeningStrip | None,
                         desk_width: float) -> list[Strategy]:
    """The rotation (clockwise, counter-clockwise, longest first) and left-right (strict,
    relaxed) strategies; see the module docstring. ``edges`` run counter-clockwise
    (:func:`.placement.room_edges`); slanted ones take no desks."""
    straight = [i for i, e in enumerate(edges) if e.axis is not None]
    long_enough = {i for i in straight if edges[i].length >= desk_width - _TOLERANCE}
    d = _door_edge(edges, door)
    ccw = [i for i in _walk(edges, d, 1) if i in long_enough]
    cw = [i for i in _walk(edges, d, -1) if i in long_enough]
    longest = sorted(long_enough, key=lambda i: (-edges[i].length, _walk(edges, d, 1).index(i)))
    out = [Strategy("clockwise", tuple(Run(edges[i], "wall", from_end=True) for i in cw)),
           Strategy("counter-clockwise", tuple(Run(edges[i], "wall") for i in ccw)),
           Strategy("longest first", tuple(Run(edges[i], "wall") for i in longest))]
    origin = _door_point(door) if door is not None else np.asarray(edges[d].start)
    along, normal = edges[d].direction, edges[d].normal

    def height(point: tuple[float, float]) -> tuple[float, float]:  # "bottom up"
        offset = np.subtract(point, origin)
        return (round(float(np.dot(offset, normal)), 9), abs(float(np.dot(offset, along))))

    def side_runs(pool: Sequence[int], overhang: bool) -> tuple[Run, ...]:
        sides = {i: float(np.dot(np.add(edges[i].start, edges[i].end) / 2 - origin, along))
                 for i in pool}
        left = [i for i in _walk(edges, d, -1) if i in sides and sides[i] <= 0]
        right = [i for i in _walk(edges, d, 1) if i in sides and sides[i] > 0]
        return tuple(Run(edges[i], "wall", from_end=height(edges[i].end) < height(edges[i].start),
                         overhang=overhang) for i in left + right)

    out.append(Strategy("left-right strict", side_runs(sorted(long_enough), False)))
    out.append(Strategy("left-right relaxed", side_runs(straight, True)))
    return out


def brute_force_strategies(edges: Sequence[Edge], door: OpeningStrip | None,
                           desk_width: float) -> list[Strategy]:
    """Every combination of none / facing the wall / back to back over the walls long
    enough for a desk (rows first, then banks), for a room of at most
    :data:`MAX_BRUTE_FORCE_WALLS` walls.

    Raises
    ------
    ValueError
        The room has more walls: the search would grow as 3ⁿ.
    """
    if len(edges) > MAX_BRUTE_FORCE_WALLS:
        raise ValueError(f"brute-force desk layouts are for rooms of at most "
                         f"{MAX_BRUTE_FORCE_WALLS} walls, got {len(edges)}")
    d = _door_edge(edges, door)
    usable = [i for i in _walk(edges, d, 1)
              if edges[i].axis is not None and edges[i].length >= desk_width - _TOLERANCE]
    out = []
    for modes in itertools.product(("none", "wall", "bank"), repeat=len(usable)):
        if all(m == "none" for m in modes):
            continue
        runs = tuple(Run(edges[i], m) for want in ("wall", "bank")  # type: ignore[arg-type]
                     for i, m in zip(usable, modes) if m == want)
        out.append(Strategy("brute force " + "/".join(modes), runs))
    return out


class _Filler:
    """Lays families out along runs in a placer's layout (one strategy at a time)."""

    def __init__(self, placer: Placer, families: Sequence[Family]):
        self.placer = placer
        self.layout = placer.layout
        self.families = families
        self.desk = families[0].desk  # the desk to seat next
        self.tests = 0  # desk poses tested so far (at most MAX_TESTS)
        # runs laid so far → the poses of the families they seated: the filling is
        # deterministic, so strategies sharing their first runs share that result
        self._seated: dict[tuple[Run, ...], tuple[tuple[Pose, ...], ...]] = {(): ()}

    def run(self, strategy: Strategy) -> tuple[int, list[tuple[ItemSpec, Pose]]]:
        """Lay ``strategy`` out, record the poses, take everything out again."""
        runs = strategy.runs
        done = max(k for k in range(len(runs) + 1) if runs[:k] in self._seated)
        for family, poses in zip(self.families, self._seated[runs[:done]]):
            for spec, pose in zip(family.specs, poses):
                self.layout.add(spec, pose)
        count = len(self._seated[runs[:done]])
        for k in range(done, len(runs)):
            count = self._fill(runs[k], count)
            self._seated[runs[:k + 1]] = tuple(
                tuple(self.layout.placed[s.name][1] for s in f.specs)
                for f in self.families[:count])
        placed = [(s, self.layout.placed[s.name][1]) for f in self.families[:count]
                  for s in f.specs]
        for spec, _ in placed:
            self.layout.remove(spec.name)
            self.placer.sides.pop(spec.name, None)
        return count, placed

    def _fill(self, run: Run, count: int) -> int:
        """Seat families from number ``count`` on along ``run``; the new count."""
        if count == len(self.families) or self.exhausted:
            return count
        self.desk = self.families[count].desk
        for pose in self._poses(run):
            if self.exhausted:
                break
            self.tests += 1
            if self.placer.seat_family(self.desk, pose):
                count += 1
                if count == len(self.families):
                    break
                self.desk = self.families[count].desk
        return count

    @property
    def exhausted(self) -> bool:
        """Whether the search has tested :data:`MAX_TESTS` poses."""
        return self.tests >= MAX_TESTS

    def _poses(self, run: Run) -> Iterator[Pose]:
        """Candidate poses for :attr:`desk` along ``run``, in filling order; the free
        stretches are recomputed after each desk the caller seats (lazily)."""
        return self._row(run) if run.mode == "wall" else self._banks(run)

    def _row(self, run: Run) -> Iterator[Pose]:
        desk = self.desk  # copies share one size; only the name changes
        edge = run.edge
        axis = edge.axis
        assert axis is not None
        rotation = quarter_turn_towards(edge.normal)
        body = desk.parts(rotation)[0].box
        _, fixed = flush(flush_box(desk, rotation), edge.normal, edge.line)
        lo, hi = edge.span[0] - body[axis], edge.span[1] - body[axis + 2]
        if run.overhang:
            extra = OVERHANG * (body[axis + 2] - body[axis])
            lo, hi = lo - extra, hi + extra
        tried: set[float] = set()
        while lo <= hi + _TOLERANCE:
            intervals = self.layout.free_intervals(
                self.desk, rotation, axis, fixed, lo, hi,
                self.placer.related.get(self.desk.name, frozenset()))
            values = sorted({v for a, b in intervals for v in (a, (a + b) / 2, b)} - tried,
                            reverse=run.descending)
            if not values:
                return
            before = len(self.layout.placed)
            for value in values:
                tried.add(value)
                yield _at(axis, value, fixed, rotation)
                if len(self.layout.placed) > before:  # seated: go on past it
                    lo, hi = (lo, value) if run.descending else (value, hi)
                    break
            else:
                return

    def _banks(self, run: Run) -> Iterator[Pose]:
        desk = self.desk
        edge = run.edge
        axis = edge.axis
        assert axis is not None
        unit = np.zeros(2)
        unit[axis] = 1.0
        facing = (quarter_turn_towards(unit), quarter_turn_towards(-unit))
        depth, reach = desk.depth, desk.depth + desk.rule.clearance_front
        normal_axis = 1 - axis
        _, fixed0 = flush(flush_box(desk, facing[0]), edge.normal, edge.line)
        pitch = (desk.width + desk.rule.clearance_side) * edge.normal[normal_axis]
        lo, hi = edge.span[0] + reach, edge.span[1] - reach
        count = int(math.floor((hi - lo) / (2 * reach) + _TOLERANCE)) + 1 if hi >= lo else 0
        centres = [lo + 2 * reach * k for k in range(count)]
        for centre in (reversed(centres) if run.descending else centres):
            for level in range(MAX_COPIES):
                fixed = fixed0 + pitch * level
                before = len(self.layout.placed)
                yield _at(axis, centre + depth / 2, fixed, facing[0])
                yield _at(axis, centre - depth / 2, fixed, facing[1])
                if len(self.layout.placed) == before:
                    break


def capacity(run: Run, desk: ItemSpec, edges: Sequence[Edge]) -> int:
    """Most desks ``run`` can seat, from the geometry alone: an upper bound that lets
    :func:`lay_out_desks` skip strategies that cannot beat the best so far.

    A row's desk bodies stand side by side within the wall's span (plus the overhang at
    both ends), so at most ``span / desk width`` of them; a bank seats two desks per
    level at each of its centres, its levels a pitch apart within the room's extent
    across the wall (``edges`` bound the room).

    Examples
    --------
    >>> from cga.operations.furniture.rules import FurnitureRule
    >>> desk = ItemSpec(FurnitureRule("Office", "desk", is_along_wall=True), "desk", (1.2, 1, 0.6))
    >>> wall = Edge((0.0, 0.0), (5.0, 0.0))
    >>> capacity(Run(wall, "wall"), desk, [wall])
    4
    >>> capacity(Run(wall, "wall", overhang=True), desk, [wall])  # 0.6 m over each end
    5
    """
    axis = run.edge.axis
    assert axis is not None
    length = run.edge.span[1] - run.edge.span[0]
    if run.mode == "wall":
        if run.overhang:
            length += 2 * OVERHANG * desk.width
        return min(MAX_COPIES, int(math.floor(length / desk.width + 1e-6)))
    reach = desk.depth + desk.rule.clearance_front
    if length < 2 * reach - _TOLERANCE:
        return 0
    centres = int(math.floor((length - 2 * reach) / (2 * reach) + _TOLERANCE)) + 1
    across = [c for e in edges for c in (e.start[1 - axis], e.end[1 - axis])]
    levels = int(math.floor((max(across) - min(across))
                            / (desk.width + desk.rule.clearance_side) + 1e-6)) + 1
    return min(MAX_COPIES, 2 * centres * levels)


def _at(axis: int, value: float, fixed: float, rotation: int) -> Pose:
    return Pose(value, fixed, rotation) if axis == 0 else Pose(fixed, value, rotation)


def lay_out_desks(placer: Placer, families: Sequence[Family],
                  doors: Sequence[OpeningStrip]) -> DeskLayout:
    """Seat as many of ``families`` as the best strategy can, in ``placer``'s layout.

    Parameters
    ----------
    placer:
        The room's placer; its layout holds the items placed so far.
    families:
        The copies of the perimeter row (:func:`copies`), in naming order.
    doors:
        The room's doors; the first is the door the walks start from.

    Returns
    -------
    DeskLayout
        The winning strategy and its poses, already added to the layout (none when no
        desk fits anywhere).

    Notes
    -----
    Each strategy costs one free-interval sweep and one family test per desk; the brute
    force adds up to 80 strategies for a room of four walls. A strategy is skipped when
    its walls cannot hold more desks than the best so far (:func:`capacity`, and for
    the brute force what each wall seats alone), and the search stops once every copy
    is seated (:data:`MAX_COPIES` in a large room): the result is the one the full
    search gives, since only a strictly larger count replaces the best. Past
    :data:`MAX_TESTS` tested poses the search stops with the best layout so far (the
    strategy under way seats the desks it had seated), so a room costs at most that
    many family tests.
    """
    if not families:
        return DeskLayout("none", 0, ())
    edges = placer.edges
    desk = families[0].desk
    door = doors[0] if doors else None
    filler = _Filler(placer, families)
    best = DeskLayout("none", 0, ())
    perimeter = perimeter_strategies(edges, door, desk.width)
    brute = (brute_force_strategies(edges, door, desk.width)
             if len(edges) <= MAX_BRUTE_FORCE_WALLS else [])
    # per run: what its wall can hold at most, then (brute force) what it seats alone
    bound = {run: capacity(run, desk, edges) for s in perimeter + brute for run in s.runs}
    for k, strategy in enumerate(perimeter + brute):
        if best.count == len(families):
            break  # every copy seated: no strategy can do better
        runs = strategy.runs
        is_brute = k >= len(perimeter)
        alone = is_brute and len(runs) == 1
        # a wall that seats nothing alone seats nothing after others either: the same
        # combination with it left empty was tried before
        if is_brute and not alone and any(bound[r] == 0 for r in runs):
            continue
        # nor can a strategy whose walls hold no more than the best so far win (the
        # brute force's single walls are laid out anyway: they give the bounds above)
        if not alone and min(len(families), sum(bound[r] for r in runs)) <= best.count:
            continue
        count, poses = filler.run(strategy)
        if alone:
            bound[runs[0]] = count
        if count > best.count:
            best = DeskLayout(strategy.name, count, tuple(poses))
        if filler.exhausted:
            best = replace(best, cut_short=True)
            break
    for spec, pose in best.poses:
        placer.layout.add(spec, pose)
    return best
