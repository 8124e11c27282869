"""The furniture solver: furnish every typed room of a floor by its rules.

Per room (thesis algorithms 5-7, docs/furniture.md):

1. the items that are not children, corner items or rugs get random start positions and
   are spread by separation steering (:mod:`.steering`) for ``steering_iterations``
   rounds; corner items keep their random start, which picks their first corner;
2. the rules are applied in table order (a child right after its parent when the parent
   comes later in the table) by :class:`.placement.Placer`; an item that cannot be
   placed is left out with the reason;
3. if something was left out, the room is solved again from new random starts, up to
   ``attempts`` times in all, and the layout that places the most items is kept (the
   first of equals); after :data:`PATIENCE` attempts in a row that place no more, the
   room stops retrying. The thesis instead nudged the blocked item step by step for
   ``clearanceTries`` steps; with exact geometry a nudge cannot help, a new start can.

Every solid item must leave a passage ``passage_width`` wide between the room's doors
and keep most of the room reachable (:mod:`.passage`); a pose that breaks this is
rejected like a collision.

A row with ``layout`` = ``perimeter`` gets as many copies as fit along the walls
(:mod:`.desks`, the MSU office desk layouts), laid out when the loop reaches the row.
Each item stands at its own size (``sizeJitter``, :mod:`.variation`); with ``disorder``
the movable items of the finished layout are turned and shifted a little, each pose
tested like any other (:mod:`.disorder`).

Doors and windows get their detail items (:mod:`.details`). The solver is a pure
function of its inputs and the random stream.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from shapely.geometry import Polygon

from cga.model import Diagnostic, FloorPlan, FurnitureItem

from .clearance import Keepout, OpeningStrip, door_keepouts, door_strips, window_strips
from .details import detail_items
from .disorder import disturb
from .desks import MAX_COPIES, MAX_TESTS, DeskLayout, Family, copies, lay_out_desks
from .layout import ItemSpec, Layout, Pose
from .passage import PASSAGE_WIDTH, Passage
from .placement import Edge, Placer, room_edges
from .rules import FurnitureRules
from .steering import Flock
from .variation import jittered_size

__all__ = ["CROWDING", "PATIENCE", "RoomSite", "RoomResult", "furnish_room", "furnish_plan"]

STAGE = "add_furniture"
PATIENCE = 5
"""Consecutive attempts without placing more items after which a room stops retrying."""


@dataclass(frozen=True)
class RoomSite:
    """What the solver needs to know about a room: its free floor, the door zones in it,
    its windows and its doors."""

    id: int
    interior: Polygon
    keepouts: tuple[Keepout, ...] = ()
    windows: tuple[OpeningStrip, ...] = ()
    doors: tuple[OpeningStrip, ...] = ()

    @classmethod
    def from_plan(cls, plan: FloorPlan, room_id: int) -> "RoomSite":
        room = plan.room(room_id)
        return cls(room_id, room.interior, tuple(door_keepouts(plan, room_id)),
                   tuple(window_strips(plan, room_id)), tuple(door_strips(plan, room_id)))


@dataclass(frozen=True)
class RoomResult:
    """The items placed in a room, ``(item, reason)`` for each one left out and the
    perimeter rows whose desk layout search stopped at :data:`.desks.MAX_TESTS`."""

    items: tuple[FurnitureItem, ...]
    left_out: tuple[tuple[str, str], ...]
    cut_short: tuple[str, ...] = ()


CROWDING = 2.0
"""How many times over the solid items before an item may cover a room's free floor
before it is left out unsolved: items cannot overlap, so past 1 some must fail, and 2
leaves room for earlier items that fail and free their share."""


def _within_floor(site: RoomSite, specs: Sequence[ItemSpec]
                  ) -> tuple[list[ItemSpec], list[tuple[str, str]]]:
    """``specs`` without the solid items whose footprint, added to those of all solid
    items before them, exceeds :data:`CROWDING` × the room's free floor, and
    ``(name, reason)`` for each item left out (non-colliding items such as rugs cover
    nothing and are always kept)."""
    floor = site.interior.area
    kept: list[ItemSpec] = []
    crowded: list[tuple[str, str]] = []
    covered = 0.0
    for spec in specs:
        if spec.rule.non_collision:
            kept.append(spec)
            continue
        covered += spec.width * spec.depth
        if covered > CROWDING * floor:
            crowded.append((spec.name, f"the items before it already need {CROWDING:g} times "
                                       f"the room's free floor ({floor:.1f} m²)"))
        else:
            kept.append(spec)
    return kept, crowded


@dataclass(frozen=True)
class _Copies:
    """The perimeter rows of a room: head name → its families (:mod:`.desks`), and the
    names of the extra copies (``#2`` on), which the solver only places through them."""

    families: Mapping[str, Sequence[Family]]
    extra: frozenset[str]


def _with_copies(site: RoomSite, specs: Sequence[ItemSpec]) -> tuple[list[ItemSpec], _Copies]:
    """``specs`` with the copies of every ``layout`` = ``perimeter`` row (and of its
    children) right after the row's own family; as many as could cover the free floor
    with desks, at most :data:`.desks.MAX_COPIES`."""
    heads = [s for s in specs if s.rule.layout == "perimeter"]
    if not heads:
        return list(specs), _Copies({}, frozenset())
    children: dict[str, list[ItemSpec]] = {}
    for spec in specs:
        if spec.rule.pair_with is not None:
            children.setdefault(spec.rule.pair_with, []).append(spec)

    def descendants(name: str) -> list[ItemSpec]:
        return [d for c in children.get(name, []) for d in (c, *descendants(c.name))]

    families: dict[str, list[Family]] = {}
    for head in heads:
        count = min(MAX_COPIES, max(1, int(site.interior.area // (head.width * head.depth))))
        families[head.name] = copies(head, descendants(head.name), count)
    out: list[ItemSpec] = []
    for spec in specs:
        out.append(spec)
        if spec.name in families:
            out.extend(c for family in families[spec.name][1:] for c in family.specs)
    extra = frozenset(c.name for fs in families.values() for f in fs[1:] for c in f.specs)
    return out, _Copies(families, extra)


_Movers = tuple[list[str], Flock]
"""The names of the items steering spreads and their :class:`.steering.Flock`."""


def _movers(site: RoomSite, specs: Sequence[ItemSpec], groups: _Copies) -> _Movers | None:
    """The items that get steered start positions (None: none), made once per room: every
    attempt starts the same items afresh."""
    movers = [s for s in specs if s.rule.pair_with is None and not s.rule.non_collision
              and s.name not in groups.families and s.name not in groups.extra]
    if not movers:
        return None
    half = np.array([(s.width / 2, s.depth / 2) for s in movers])
    movable = np.array([not s.rule.is_in_corner for s in movers])
    flock = Flock(site.interior, half, np.hypot(half[:, 0], half[:, 1]), movable)
    return [s.name for s in movers], flock


def _starts(movers: _Movers | None, rng: np.random.Generator, iterations: int
            ) -> dict[str, tuple[float, float]]:
    if movers is None:
        return {}
    names, flock = movers
    positions = flock.steer(flock.random_start(rng), iterations)
    return {name: (float(p[0]), float(p[1])) for name, p in zip(names, positions)}


def _solve_once(site: RoomSite, specs: Sequence[ItemSpec], rng: np.random.Generator,
                iterations: int, room: tuple[Layout, list[Edge], _Movers | None],
                groups: _Copies,
                desk_layouts: dict[tuple[str, tuple[tuple[str, Pose], ...]], DeskLayout],
                to_beat: int | None = None) -> tuple[Placer, list[tuple[str, str]]]:
    """One attempt; ``room`` is the room's empty layout, its edges and the items that get
    steered starts, made once.

    ``to_beat`` is the number of items the best attempt so far placed (None: this is the
    first). The solver keeps an attempt only if it places more, so once the items placed
    and those still to come cannot add up to more, the rest is passed over
    (:meth:`.placement.Placer.pass_over`, which draws what placing them would): the room's
    result and the random stream are those of running the attempt to its end. In a room
    that keeps leaving an item out, the attempts after the first are most of its cost.
    Rooms with perimeter rows run to the end: their desk layouts, made in any attempt,
    are reported (``cut_short``)."""
    starts = _starts(room[2], rng, iterations)
    layout = room[0].emptied()
    placer = Placer(layout, specs, rng, room[1])
    left_out = []
    if groups.families:
        to_beat = None
    for index, spec in enumerate(specs):
        if spec.name in groups.extra:
            continue
        if spec.name in groups.families:
            # the same items placed before give the same desks: lay them out once
            key = (spec.name, tuple(sorted((name, pose)
                                           for name, (_, pose) in layout.placed.items())))
            desks = desk_layouts.get(key)
            if desks is None:
                desks = desk_layouts[key] = lay_out_desks(placer, groups.families[spec.name],
                                                          site.doors)
            else:
                for item, pose in desks.poses:
                    layout.add(item, pose)
        reason = placer.place(spec, starts.get(spec.name))
        if reason is None:
            continue
        left_out.append((spec.name, reason))
        later = specs[index + 1:]
        if to_beat is not None and (len(layout.placed) + sum(s.name not in layout.placed
                                                             for s in later) <= to_beat):
            for other in later:
                placer.pass_over(other)
            break
    return placer, left_out


class _Unbeatable:
    """Whether an attempt's result can be beaten at all, as far as the room itself tells
    (:meth:`.placement.Placer.never_fits`): when every item it left out is a corner or
    wall item the room blocks everywhere, or a child of one, no later attempt can place
    more, and the solver stops retrying (half a house's furnishing was attempts after
    the first that placed no more).

    Stopping early leaves the room's random stream where it is, so only rooms that draw
    nothing after their attempts are judged: no item disordered (``disorder``, a row's
    own), no desk rows (whose layouts of every attempt are reported). The items are
    tested on an empty layout of the room when first left out."""

    def __init__(self, room: tuple[Layout, list[Edge], _Movers | None],
                 specs: Sequence[ItemSpec], groups: _Copies, disorder: float):
        noisy = any((disorder if s.rule.disorder is None else s.rule.disorder) > 0
                    for s in specs)
        self.judged = not (noisy or groups.families or groups.extra)
        self.room, self.specs = room, specs
        self.by_name = {s.name: s for s in specs}
        self._never: dict[str, bool] = {}
        self._probe: Placer | None = None

    def __call__(self, left_out: Sequence[tuple[str, str]]) -> bool:
        return self.judged and all(self._never_placed(name) for name, _ in left_out)

    def _never_placed(self, name: str) -> bool:
        spec = self.by_name[name]
        if spec.rule.pair_with is not None:
            return self._never_placed(spec.rule.pair_with)
        never = self._never.get(name)
        if never is None:
            if self._probe is None:
                self._probe = Placer(self.room[0].emptied(), self.specs,
                                     np.random.default_rng(0), self.room[1])
            never = self._never[name] = self._probe.never_fits(spec)
        return never


def furnish_room(site: RoomSite, specs: Sequence[ItemSpec], rng: np.random.Generator, *,
                 steering_iterations: int = 10, attempts: int = 20,
                 patience: int = PATIENCE, passage_width: float = PASSAGE_WIDTH,
                 disorder: float = 0.0) -> RoomResult:
    """Place ``specs`` (in placement order) in one room.

    Parameters
    ----------
    site:
        The room.
    specs:
        The items, children after their parents (:meth:`.rules.FurnitureRules.for_room`).
    rng:
        The random stream (start positions, free items).
    steering_iterations:
        Rounds of separation steering.
    attempts:
        Solves from fresh random starts while items are left out (at least one).
    patience:
        Consecutive attempts without improvement after which the room stops retrying.
    passage_width:
        Width (m) of the passage every solid item must leave between the room's doors
        (:mod:`.passage`); 0 switches the rule off.
    disorder:
        Noise in [0, 1] turning and shifting the movable items of the finished layout
        (:mod:`.disorder`); 0 leaves it tidy.

    Returns
    -------
    RoomResult
        Items in placement order and the reasons for those left out.

    Raises
    ------
    ValueError
        ``passage_width`` is negative or ``disorder`` is outside [0, 1].

    Notes
    -----
    One attempt costs O(n · (w + k)) shapely queries for n items, w walls and k
    obstacles near a candidate strip, and steering O(n²); a full room of a dozen items
    takes milliseconds. Items whose solid footprints, with those of the items before
    them, would cover the room's free floor :data:`CROWDING` times over cannot all
    stand and are left out before solving (:func:`_within_floor`), so the work per room
    is bounded by its floor area and the cost of a table grows linearly with its rows.
    The passage rule adds a shapely difference and a few predicates per pose that is
    otherwise free.
    """
    if passage_width < 0:
        raise ValueError(f"passage_width must not be negative, got {passage_width:g}")
    if not 0 <= disorder <= 1:
        raise ValueError(f"disorder must be in [0, 1], got {disorder:g}")
    specs, crowded = _within_floor(site, specs)
    specs, groups = _with_copies(site, specs)
    passage = Passage(site.interior, site.doors, passage_width) if passage_width > 0 else None
    room = (Layout(site.interior, list(site.keepouts), list(site.windows), passage),
            room_edges(site.interior), _movers(site, specs, groups))
    best: tuple[Placer, list[tuple[str, str]]] | None = None
    desk_layouts: dict[tuple[str, tuple[tuple[str, Pose], ...]], DeskLayout] = {}
    unbeatable = _Unbeatable(room, specs, groups, disorder)
    stale = 0
    for _ in range(max(1, attempts)):
        placer, left_out = _solve_once(site, specs, rng, steering_iterations, room, groups,
                                       desk_layouts,
                                       None if best is None else len(best[0].layout.placed))
        if best is None or len(placer.layout.placed) > len(best[0].layout.placed):
            best, stale = (placer, left_out), 0
        else:
            stale += 1
        if not left_out or stale >= patience or unbeatable(best[1]):
            break
    assert best is not None
    placer, left_out = best
    movable = {s.name for s in specs if s.rule.movable(s.model)}
    disturb(placer.layout, specs, movable, placer.related, rng, disorder)
    placed = placer.layout.placed
    left_out = [*left_out, *crowded]
    items = tuple(
        FurnitureItem(name=spec.name, model=spec.model, room=site.id,
                      position=(pose.x, pose.z), rotation=pose.rotation % 4, size=spec.size,
                      parent=spec.rule.pair_with, non_collision=spec.rule.non_collision,
                      yaw=pose.yaw)
        for spec, pose in (placed[s.name] for s in specs if s.name in placed))
    cut_short = sorted({row for (row, _), d in desk_layouts.items() if d.cut_short})
    return RoomResult(items, tuple(left_out), tuple(cut_short))


def furnish_plan(plan: FloorPlan, rules: FurnitureRules,
                 models: Mapping[str, tuple[str, tuple[float, float, float]]],
                 rng: np.random.Generator, *, steering_iterations: int = 10,
                 attempts: int = 20, passage_width: float = PASSAGE_WIDTH,
                 disorder: float = 0.0
                 ) -> tuple[tuple[FurnitureItem, ...], tuple[Diagnostic, ...]]:
    """Furnish every typed room of ``plan`` but its stair core, and add the door and
    window details.

    Parameters
    ----------
    plan:
        A typed floor (rooms with types, doors, windows).
    rules:
        The furniture table with distances in metres.
    models:
        Rule name → (model name, model size in metres) for every placeable rule.
    rng:
        The floor's random stream; each room gets its own child stream (in room-id
        order), so a room's layout does not depend on how the others went. The sizes of
        its items (``sizeJitter``, :mod:`.variation`) come from a child of the room's
        stream, so they do not shift the layout's own draws.
    steering_iterations, attempts, passage_width, disorder:
        See :func:`furnish_room`.

    Returns
    -------
    (furniture, diagnostics)
        Detail items first, then each room's furniture; one warning per item left out,
        naming the item, the room and the reason.
    """
    # the stair core holds flights and landings, never furniture (DESIGN §12)
    rooms = sorted((r for r in plan.rooms if r.type is not None and r.id != plan.core_room),
                   key=lambda r: r.id)
    streams = rng.spawn(len(rooms)) if rooms else []
    furniture: list[FurnitureItem] = list(detail_items(plan, rules))
    diagnostics: list[Diagnostic] = []
    for room, stream in zip(rooms, streams):
        assert room.type is not None
        room_rules = rules.for_room(room.type)
        if not room_rules:
            continue
        sizes = stream.spawn(1)[0]
        specs = [ItemSpec(rule, models[rule.name][0],
                          jittered_size(models[rule.name][1], rule.size_jitter, sizes))
                 for rule in room_rules]
        result = furnish_room(RoomSite.from_plan(plan, room.id), specs, stream,
                              steering_iterations=steering_iterations, attempts=attempts,
                              passage_width=passage_width, disorder=disorder)
        furniture.extend(result.items)
        for name, reason in result.left_out:
            diagnostics.append(Diagnostic("warning", STAGE,
                                          f"{name} left out of {room.label}: {reason}",
                                          floor=plan.index, room=room.id))
        for name in result.cut_short:
            diagnostics.append(Diagnostic(
                "info", STAGE, f"{name} rows in {room.label}: the desk layout search stopped "
                f"after {MAX_TESTS} tested poses with the best layout so far",
                floor=plan.index, room=room.id))
    return tuple(furniture), tuple(diagnostics)
