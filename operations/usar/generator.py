"""The UvA adaptive indoor map generator on a grid of hallway-wide cells.

Zwennes (2011, "Adaptive Indoor Map Generator for USARSim", §3–4) extends the USARSim
World Generator with five rules driven by a difficulty ``d`` ∈ [0, 10]:

1. **hallway spacing** per axis ``(0.06·d + 0.2)·size + N(0, 1)·0.1·size``, rounded,
   clamped to [3, size]; hallways fill every column (row) whose index the spacing
   divides (``hallwayRule``);
2. **rooms** from a catalogue, column by column from the top left (``roomRule``): at each
   empty cell a room is drawn with probability ``P(r) = ISE(r) / Σ ISE``,
   ``ISE(r) = 1 / ((d − diff(r))² + 1)``; a room that does not fit is drawn again (here:
   the draw is restricted to the rooms that fit, the same distribution); after the
   column, the generator moves right by the widest room placed in it;
3. **open areas**: the cells that jump skips stay empty and become hallway floor;
4. **doorways**: each side of each room gets a doorway in its middle with probability
   ``d/16 + 0.375``;
5. **cycle prevention** with probability ``1 − d/10``: for every column just before a
   vertical hallway (the paper's "column dividable by horizontalSpacing − 1", read as
   ``(x + 1) mod spacing = 0``) and every hallway row, the hallway cell is removed; one
   random removed cell per column is put back.

Here ``size`` is the number of cells per axis minus one (the distance between the first
and the last possible hallway), which gives the paper's "at least two hallways per
direction" when the spacing is clamped to ``size``. Cells are labelled in
``GridLayout.cells``; the floor is assembled from it by :mod:`.plan`.

Deviations, all to keep every room reachable as a built floor must be (the paper notes
rooms without doorways are unreachable):

* a removed hallway cell is not solid: the hallway ends in a wall across it (the plan has
  no solid cells), which blocks the hallway exactly as the removal does;
* when cycle prevention fires, an open area opens onto the hallways by one side only
  (otherwise a cut hallway would be joined again through the open area);
* a room (or open area) that its doorways leave cut off gets one more doorway towards
  reached space (``Link.kind == "repair"``), counted separately from the drawn ones.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import networkx as nx
import numpy as np

from .catalogue import CatalogueRoom

__all__ = ["HALL", "CUT", "OPEN", "EMPTY", "Placement", "Region", "Link", "Doorway",
           "GridLayout", "hallway_spacing", "room_weights", "expected_room_difficulty",
           "doorway_probability", "cycle_prevention_probability", "generate"]

HALL, CUT, OPEN, EMPTY = -1, -2, -3, -4
"""Cell labels besides room numbers (≥ 0): hallway, removed hallway, open area, empty."""

Side = Literal["north", "south", "west", "east"]
"""A room side: north is low z (row 0), west low x (column 0)."""


def hallway_spacing(difficulty: float, size: int, gaussian: float) -> int:
    """``(0.06·d + 0.2)·size + gaussian·0.1·size``, rounded, clamped to [3, size]."""
    raw = (0.06 * difficulty + 0.2) * size + gaussian * 0.1 * size
    return int(min(max(round(raw), 3), size))


def room_weights(catalogue: Sequence[CatalogueRoom], difficulty: float) -> np.ndarray:
    """``P(r) = ISE(r) / Σ ISE`` with ``ISE(r) = 1 / ((d − diff(r))² + 1)``."""
    ise = np.array([1.0 / ((difficulty - r.difficulty) ** 2 + 1.0) for r in catalogue])
    return ise / ise.sum()


def expected_room_difficulty(catalogue: Sequence[CatalogueRoom], difficulty: float) -> float:
    """``Σ P(r)·diff(r)``: the mean annotated difficulty of a drawn room when every room
    fits (no size-fit bias)."""
    weights = room_weights(catalogue, difficulty)
    return float(sum(w * r.difficulty for w, r in zip(weights, catalogue)))


def doorway_probability(difficulty: float) -> float:
    """``d/16 + 0.375``."""
    return difficulty / 16 + 0.375


def cycle_prevention_probability(difficulty: float) -> float:
    """``1 − d/10``."""
    return 1.0 - difficulty / 10


@dataclass(frozen=True)
class Placement:
    """Room number ``index`` of catalogue entry ``room`` at column ``x``, row ``y``."""

    index: int
    room: CatalogueRoom
    x: int
    y: int

    @property
    def rect(self) -> tuple[int, int, int, int]:
        """``(x0, y0, x1, y1)`` in cells, exclusive ends."""
        return (self.x, self.y, self.x + self.room.width, self.y + self.room.depth)


@dataclass(frozen=True)
class Region:
    """A rectangle of the floor: a room, a vertical hallway, a hallway segment between
    two vertical ones, or a piece of an open area. ``number`` indexes ``regions``;
    rooms come first, so a room's region number is its placement index."""

    number: int
    kind: Literal["room", "hallway", "segment", "open"]
    rect: tuple[int, int, int, int]


@dataclass(frozen=True)
class Doorway:
    """One draw of the doorway rule: ``room``'s ``side``, whether it ``opened``, and the
    region behind the side's middle (None: the map's edge)."""

    room: int
    side: Side
    opened: bool
    towards: int | None


@dataclass(frozen=True)
class Link:
    """A way between regions ``a`` and ``b`` through their shared wall at ``at``
    (cell units, on the wall line): a room ``doorway``, a hallway ``opening`` (as wide
    as the wall allows) or a ``repair`` doorway that keeps a region reachable."""

    a: int
    b: int
    kind: Literal["doorway", "opening", "repair"]
    at: tuple[float, float]


@dataclass(frozen=True)
class GridLayout:
    """A generated map: ``cells[row, column]`` holds a room number or a label."""

    difficulty: float
    cells: np.ndarray
    spacing: tuple[int, int]
    rooms: tuple[Placement, ...]
    regions: tuple[Region, ...]
    doorways: tuple[Doorway, ...]
    links: tuple[Link, ...]
    cycle_prevention: bool
    removed: tuple[tuple[int, int], ...]
    """Hallway cells ``(x, y)`` cycle prevention removed (after the put-backs)."""

    @property
    def columns(self) -> int:
        return int(self.cells.shape[1])

    @property
    def rows(self) -> int:
        return int(self.cells.shape[0])

    @property
    def entry(self) -> int:
        """The region of the first vertical hallway (column 0), where the front door is."""
        return next(r.number for r in self.regions if r.kind == "hallway" and r.rect[0] == 0)

    def hallway_graph(self) -> nx.MultiGraph:
        """Hallway, segment and open-area regions joined by their openings."""
        graph = nx.MultiGraph()
        graph.add_nodes_from(r.number for r in self.regions if r.kind != "room")
        graph.add_edges_from((k.a, k.b) for k in self.links if k.kind == "opening")
        return graph

    def region_graph(self) -> nx.MultiGraph:
        """Every region joined by every link."""
        graph = nx.MultiGraph()
        graph.add_nodes_from(r.number for r in self.regions)
        graph.add_edges_from((k.a, k.b) for k in self.links)
        return graph


def generate(columns: int, rows: int, difficulty: float, catalogue: Sequence[CatalogueRoom],
             rng: np.random.Generator) -> GridLayout:
    """Generate a map of ``columns`` × ``rows`` cells at ``difficulty``.

    Parameters
    ----------
    columns, rows
        Cells along x and z (at least 4 each).
    difficulty
        ``d`` in [0, 10].
    catalogue
        The rooms that may be placed.
    rng
        The random stream (spacing, rooms, doorways, cycle prevention, in that order).

    Returns
    -------
    GridLayout

    Raises
    ------
    ValueError
        Fewer than 4 cells on an axis, or ``difficulty`` outside [0, 10].

    Notes
    -----
    O(cells × catalogue) for the room rule; the rest is linear in the cells.
    """
    if columns < 4 or rows < 4:
        raise ValueError(f"the grid needs at least 4 x 4 cells, got {columns} x {rows}")
    if not 0 <= difficulty <= 10:
        raise ValueError(f"difficulty must be in [0, 10], got {difficulty}")
    sx = hallway_spacing(difficulty, columns - 1, float(rng.standard_normal()))
    sy = hallway_spacing(difficulty, rows - 1, float(rng.standard_normal()))
    cells = np.full((rows, columns), EMPTY, dtype=np.int64)
    cells[:, ::sx] = HALL
    cells[::sy, :] = HALL
    rooms = _place_rooms(cells, catalogue, room_weights(catalogue, difficulty), rng)
    cells[cells == EMPTY] = OPEN
    doorway_p = doorway_probability(difficulty)
    draws = [(p, side, bool(rng.random() < doorway_p)) for p in rooms for side in _SIDES]
    fired = bool(rng.random() < cycle_prevention_probability(difficulty))
    removed = _prevent_cycles(cells, sx, sy, rng) if fired else []
    regions = _regions(cells, rooms, sx)
    region_of = np.full(cells.shape, -1, dtype=np.int64)
    for region in regions:
        x0, y0, x1, y1 = region.rect
        region_of[y0:y1, x0:x1] = region.number
    doorways, links = [], []
    for placement, side, opened in draws:
        at, behind = _side_middle(placement, side, region_of)
        towards = None if behind is None else int(region_of[behind[1], behind[0]])
        doorways.append(Doorway(placement.index, side, opened, towards))
        if opened and towards is not None:
            links.append(Link(placement.index, towards, "doorway", at))
    links.extend(_openings(regions, region_of, cells, fired, rng))
    layout = GridLayout(difficulty, cells, (sx, sy), tuple(rooms), tuple(regions),
                        tuple(doorways), tuple(links), fired, tuple(removed))
    return _repaired(layout, region_of)


_SIDES: tuple[Side, ...] = ("north", "south", "west", "east")


def _place_rooms(cells: np.ndarray, catalogue: Sequence[CatalogueRoom], weights: np.ndarray,
                 rng: np.random.Generator) -> list[Placement]:
    """The paper's ``roomRule``: down each column, then right by the widest room."""
    rows, columns = cells.shape
    placed: list[Placement] = []
    x = 0
    while x < columns:
        y, widest = 0, 0
        while y < rows:
            if cells[y, x] != EMPTY:
                y += 1
                continue
            fits = [i for i, r in enumerate(catalogue)
                    if x + r.width <= columns and y + r.depth <= rows
                    and bool((cells[y:y + r.depth, x:x + r.width] == EMPTY).all())]
            if not fits:
                y += 1
                continue
            p = weights[fits] / weights[fits].sum()
            room = catalogue[fits[int(rng.choice(len(fits), p=p))]]
            placement = Placement(len(placed), room, x, y)
            placed.append(placement)
            cells[y:y + room.depth, x:x + room.width] = placement.index
            y += room.depth
            widest = max(widest, room.width)
        x += max(widest, 1)
    return placed


def _prevent_cycles(cells: np.ndarray, sx: int, sy: int,
                    rng: np.random.Generator) -> list[tuple[int, int]]:
    """Remove the hallway cell before each vertical hallway on every hallway row; put
    one back per column. Returns the cells left removed."""
    rows, columns = cells.shape
    removed: list[tuple[int, int]] = []
    for x in range(sx - 1, columns - 1, sx):
        column = [(x, y) for y in range(0, rows, sy) if cells[y, x] == HALL]
        if not column:
            continue
        back = column[int(rng.integers(len(column)))]
        for cell in column:
            if cell != back:
                cells[cell[1], cell[0]] = CUT
                removed.append(cell)
    return removed


def _regions(cells: np.ndarray, rooms: Sequence[Placement], sx: int) -> list[Region]:
    """Rooms, vertical hallways (whole columns), hallway segments (runs of a hallway
    row between vertical hallways, removed cells included) and open-area rectangles."""
    rows, columns = cells.shape
    regions = [Region(p.index, "room", p.rect) for p in rooms]
    for x in range(0, columns, sx):
        regions.append(Region(len(regions), "hallway", (x, 0, x + 1, rows)))
    corridor = (cells == HALL) | (cells == CUT)
    corridor[:, ::sx] = False
    for y in range(rows):
        x = 0
        while x < columns:
            if not corridor[y, x]:
                x += 1
                continue
            end = x
            while end < columns and corridor[y, end]:
                end += 1
            regions.append(Region(len(regions), "segment", (x, y, end, y + 1)))
            x = end
    taken = cells != OPEN
    for y in range(rows):
        for x in range(columns):
            if taken[y, x]:
                continue
            x1 = x
            while x1 < columns and not taken[y, x1]:
                x1 += 1
            y1 = y + 1
            while y1 < rows and not taken[y1, x:x1].any():
                y1 += 1
            taken[y:y1, x:x1] = True
            regions.append(Region(len(regions), "open", (x, y, x1, y1)))
    return regions


def _side_middle(p: Placement, side: Side,
                 region_of: np.ndarray) -> tuple[tuple[float, float], tuple[int, int] | None]:
    """The point of the doorway on ``side`` (cell units, on the side's line) and the cell
    behind it (None off the map). The middle of an even side lies between two cells; if
    they belong to different regions the doorway moves to the centre of the second."""
    x0, y0, x1, y1 = p.rect
    rows, columns = region_of.shape
    along_x = side in ("north", "south")
    lo, hi = (x0, x1) if along_x else (y0, y1)
    line = {"north": y0, "south": y1, "west": x0, "east": x1}[side]
    behind_line = line - 1 if side in ("north", "west") else line
    if not (0 <= behind_line < (rows if along_x else columns)):
        return ((lo + hi) / 2, line) if along_x else (line, (lo + hi) / 2), None
    mid = (lo + hi) / 2
    second = (lo + hi) // 2
    if (hi - lo) % 2 == 0:
        first = second - 1
        a = region_of[behind_line, first] if along_x else region_of[first, behind_line]
        b = region_of[behind_line, second] if along_x else region_of[second, behind_line]
        if a != b:
            mid = second + 0.5
    cell = (second, behind_line) if along_x else (behind_line, second)
    return ((mid, float(line)) if along_x else (float(line), mid)), cell


def _shared(a: Region, b: Region) -> tuple[tuple[float, float], float] | None:
    """Midpoint and length of the wall two rectangles share (None if they only touch
    at a corner or not at all)."""
    ax0, ay0, ax1, ay1 = a.rect
    bx0, by0, bx1, by1 = b.rect
    if ax1 == bx0 or bx1 == ax0:
        lo, hi = max(ay0, by0), min(ay1, by1)
        if hi > lo:
            return ((float(ax1 if ax1 == bx0 else ax0), (lo + hi) / 2), float(hi - lo))
    if ay1 == by0 or by1 == ay0:
        lo, hi = max(ax0, bx0), min(ax1, bx1)
        if hi > lo:
            return (((lo + hi) / 2, float(ay1 if ay1 == by0 else ay0)), float(hi - lo))
    return None


def _adjacent_pairs(region_of: np.ndarray, blocked: set[tuple[int, int]]) -> set[tuple[int, int]]:
    """Pairs of regions with a shared cell edge that is not in ``blocked`` (cell pairs
    encoded as flat indices)."""
    pairs = set()
    rows, columns = region_of.shape
    flat = region_of.ravel()
    for step, (r1, c1) in ((1, (rows, columns - 1)), (columns, (rows - 1, columns))):
        index = np.arange(rows * columns).reshape(rows, columns)[:r1, :c1].ravel()
        for i, j in zip(index, index + step):
            a, b = int(flat[i]), int(flat[j])
            if a != b and (int(i), int(j)) not in blocked:
                pairs.add((min(a, b), max(a, b)))
    return pairs


def _openings(regions: Sequence[Region], region_of: np.ndarray, cells: np.ndarray,
              fired: bool, rng: np.random.Generator) -> list[Link]:
    """Openings between touching hallway regions; a removed cell's far edge stays shut.
    When cycle prevention fired, the openings are a spanning forest: all hallway-line
    openings (a tree by construction), then open-area openings in random order, each
    kept only if it joins two parts not yet joined."""
    columns = cells.shape[1]
    blocked = {(int(y * columns + x), int(y * columns + x + 1))
               for y, x in zip(*np.nonzero(cells == CUT)) if x + 1 < columns}
    kinds = {r.number: r.kind for r in regions}
    pairs = sorted(p for p in _adjacent_pairs(region_of, blocked)
                   if kinds[p[0]] != "room" and kinds[p[1]] != "room")
    if fired:
        lines = [p for p in pairs if "open" not in (kinds[p[0]], kinds[p[1]])]
        rest = [p for p in pairs if p not in lines]
        order = [rest[i] for i in rng.permutation(len(rest))]
        forest = nx.utils.UnionFind()
        kept = []
        for a, b in lines + order:
            if forest[a] != forest[b]:
                forest.union(a, b)
                kept.append((a, b))
        pairs = kept
    links = []
    for a, b in pairs:
        shared = _shared(regions[a], regions[b])
        if shared is not None:
            links.append(Link(a, b, "opening", shared[0]))
    return links


def _repaired(layout: GridLayout, region_of: np.ndarray) -> GridLayout:
    """Add a doorway from each cut-off region to reached space, nearest first."""
    graph = layout.region_graph()
    reached = nx.node_connected_component(graph, layout.entry)
    links = list(layout.links)
    regions = layout.regions
    pairs = _adjacent_pairs(region_of, set())
    while len(reached) < len(regions):
        candidates = []
        for a, b in sorted(pairs):
            if (a in reached) != (b in reached):
                shared = _shared(regions[a], regions[b])
                if shared is not None:
                    candidates.append((-shared[1], a, b, shared[0]))
        if not candidates:
            break
        _, a, b, at = min(candidates)
        links.append(Link(a, b, "repair", at))
        graph.add_edge(a, b)
        reached = nx.node_connected_component(graph, layout.entry)
    return GridLayout(layout.difficulty, layout.cells, layout.spacing, layout.rooms,
                      layout.regions, layout.doorways, tuple(links), layout.cycle_prevention,
                      layout.removed)
