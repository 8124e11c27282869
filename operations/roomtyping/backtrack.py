"""Placing the mandatory rules: the greedy pass and the correction backtracker.

The thesis (§5.2.2, Algorithms 2, 3, 11, 12) places mandatory rules one by one, each on
a free room that is big enough and adjoins a room of a listed type, and when a rule finds
no room it "corrects" earlier decisions latest-first, moving types to other rooms and
re-placing the rules they displaced. Its correction is a single sweep and can miss a
typing that exists. Here both steps are one depth-first search:

* the greedy pass is the search's first descent: every rule takes its first candidate
  room, rooms that already satisfy the rule's neighbour requirement first, then by the
  rule's preference (:func:`size_preferences`: big rules to big rooms, with jitter);
* the correction is chronological backtracking: when a rule has no candidate left, the
  latest placement is undone and its rule moves to its next candidate room; rules placed
  after it are re-placed, exactly the thesis' "re-satisfy displaced rules", but
  exhaustively, so the search is complete: it finds a typing whenever one exists.

Pruning keeps it fast: a rule's candidates are free rooms that are big enough (and can
take the front door, for the ``isOutsideConnected`` rule) and either adjoin a room of a
listed type already or adjoin a free room where a still-unplaced listed type fits; a
placed rule still waiting for its neighbour must keep such a free room beside it; the
unplaced rules must be able to get distinct rooms from their candidates (a bipartite
matching, which covers sizes and competition for the same rooms); and the next rule is
the most constrained one (fewest candidates), so dead ends show at once.

A valid placement gives each mandatory rule its own room, big enough, adjoining a room of
one of its ``Neighbours`` types among the placed mandatory rules. When no placement
satisfies every rule, one rule may go without a neighbour, as the thesis' first rule
does (it is placed before any other room has a type); the rule hardest to satisfy is
tried first. Only if that fails too is there no typing.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

__all__ = ["RoomSet", "RuleSpec", "Placement", "Failure", "Unplaceable", "place_rules",
           "size_preferences", "PREFERENCE_JITTER"]

PREFERENCE_JITTER = 0.35
"""Random spread added to size-rank distances (ranks run from 0 to 1), for variety."""


@dataclass(frozen=True)
class RoomSet:
    """The rooms as the search sees them: areas (m²), door-capable adjacency, which
    rooms can take the front door (``entrances``; None when no front door is wanted)
    and which have an outer wall (``outer``; None: every room)."""

    areas: tuple[float, ...]
    adjacency: tuple[frozenset[int], ...]
    entrances: frozenset[int] | None = None
    ids: tuple[int, ...] | None = None
    outer: frozenset[int] | None = None

    def name(self, i: int) -> str:
        """The room's name in messages (its plan id when known)."""
        return f"room {self.ids[i] if self.ids is not None else i}"

    def __len__(self) -> int:
        return len(self.areas)


@dataclass(frozen=True)
class RuleSpec:
    """A mandatory rule as the search sees it: its type, area range (m²), the types
    it accepts as neighbour and whether its room takes the front door.

    ``needs_window`` asks for a room with an outer wall; ``pinned`` fixes the rule on one
    room (a corridor or hall carved by ``make_floor``), which needs no neighbour.
    """

    type: str
    min_area: float
    neighbours: frozenset[str]
    outside: bool = False
    max_area: float = math.inf
    needs_window: bool = False
    pinned: int | None = None


@dataclass(frozen=True)
class Failure:
    """A dead end of a search: the room of each rule placed so far (-1 when unplaced)
    and what went wrong.

    ``kind`` is ``"no-room"`` (rule ``rules[0]`` has no candidate room), ``"stranded"``
    (placed rule ``rules[0]`` can no longer get a listed neighbour) or ``"crowded"``
    (the ``rules`` all need one of the rooms in ``candidates``, which are fewer).
    """

    rooms: tuple[int, ...]
    kind: Literal["no-room", "stranded", "crowded"]
    rules: tuple[int, ...]
    candidates: tuple[int, ...] = ()


@dataclass(frozen=True)
class Placement:
    """The room of every rule (``rooms[k]`` for rule ``k``).

    ``exempt`` is the rule allowed to have no listed neighbour (None when every rule
    has one); ``first_failure`` is the greedy pass's dead end, when the correction was
    needed; ``backtracks`` counts undone placements.
    """

    rooms: tuple[int, ...]
    exempt: int | None
    first_failure: Failure | None
    backtracks: int


@dataclass(frozen=True)
class Unplaceable:
    """No placement exists; ``failures`` are the deepest dead ends of the searches."""

    failures: tuple[Failure, ...]


@dataclass
class _SearchStats:
    """What the searches of one call share: undone placements, dead ends seen."""

    backtracks: int = 0
    deepest: Failure | None = None
    deepest_depth: int = -1
    first_failure: Failure | None = None


def size_preferences(areas: Sequence[float], sizes: Sequence[float],
                     rng: np.random.Generator) -> list[list[int]]:
    """For each size, the rooms from most to least preferred, matching ranks.

    Rooms are ranked by area and sizes by value, both from 0 (largest) to 1 (smallest);
    a size prefers the rooms whose rank is closest to its own, plus a uniform jitter of
    up to :data:`PREFERENCE_JITTER`. So the rule with the largest ``Size`` (a living
    room) tends to the largest rooms and the smallest (a bathroom) to the smallest,
    while seeds still vary the layout. Preferences only order the search; they never
    exclude a room.
    """
    room_rank, size_rank = _ranks(areas), _ranks(sizes)
    noise = rng.uniform(0.0, PREFERENCE_JITTER, size=(len(sizes), len(areas)))
    return [sorted(range(len(areas)), key=lambda i: abs(room_rank[i] - size_rank[k]) + noise[k][i])
            for k in range(len(sizes))]


def _ranks(values: Sequence[float]) -> list[float]:
    """Rank of each value, 0 for the largest to 1 for the smallest (ties by position)."""
    order = sorted(range(len(values)), key=lambda i: -values[i])
    scale = max(len(values) - 1, 1)
    ranks = [0.0] * len(values)
    for position, i in enumerate(order):
        ranks[i] = position / scale
    return ranks


def _bits(mask: int) -> Iterator[int]:
    """The indices of the set bits of ``mask``, lowest first."""
    while mask:
        low = mask & -mask
        yield low.bit_length() - 1
        mask ^= low


def _crowded(domains: dict[int, int]) -> tuple[tuple[int, ...], int] | None:
    """Rules that cannot all get their own room from their candidate masks, if any.

    A bipartite matching by Kuhn's augmenting paths on bitmasks (a dozen rules at most).
    When a rule cannot be matched, the rules its failed search reached and the rooms it
    visited violate Hall's condition: more rules than rooms. Returns those rules and
    the room mask, or None when every rule can have a room of its own.
    """
    owner: dict[int, int] = {}
    visited = 0

    def augment(rule: int) -> bool:
        nonlocal visited
        for room in _bits(domains[rule] & ~visited):
            visited |= 1 << room
            if room not in owner or augment(owner[room]):
                owner[room] = rule
                return True
        return False

    for rule in domains:
        visited = 0
        if not augment(rule):
            rivals = (rule, *sorted(owner[room] for room in _bits(visited)))
            return rivals, visited
    return None


class _Masks:
    """The problem as bitmasks, shared by every search of one call: adjacency per room,
    fitting rooms per rule, listed rules per rule (``nbr``; never the rule itself)."""

    def __init__(self, rooms: RoomSet, rules: Sequence[RuleSpec]):
        n = len(rooms)
        self.n, self.m = n, len(rules)
        self.adj = [sum(1 << j for j in rooms.adjacency[i]) for i in range(n)]
        entrances = (sum(1 << i for i in rooms.entrances) if rooms.entrances is not None
                     else (1 << n) - 1)
        outer = (sum(1 << i for i in rooms.outer) if rooms.outer is not None
                 else (1 << n) - 1)
        self.fits = []
        self.loose = 0  # rules that need no neighbour (pinned ones)
        for k, rule in enumerate(rules):
            if rule.pinned is not None:
                self.fits.append(1 << rule.pinned)
                self.loose |= 1 << k
                continue
            mask = sum(1 << i for i in range(n)
                       if rule.min_area <= rooms.areas[i] <= rule.max_area)
            if rule.needs_window:
                mask &= outer
            self.fits.append(mask & entrances if rule.outside else mask)
        self.nbr = [sum(1 << j for j, other in enumerate(rules)
                        if j != k and other.type in rule.neighbours)
                    for k, rule in enumerate(rules)]

    def support(self, k: int) -> int:
        """How many (room, neighbouring room) pairs could satisfy rule k on their own."""
        partners = 0
        for j in _bits(self.nbr[k]):
            partners |= self.fits[j]
        return sum(bin(self.adj[i] & partners).count("1") for i in _bits(self.fits[k]))


class _Search:
    """One depth-first search with a fixed first rule and a fixed exempt rule."""

    def __init__(self, masks: _Masks, preference: Sequence[Sequence[int]],
                 exempt: int | None, stats: _SearchStats):
        self.m = masks.m
        self.adj, self.fits, self.nbr, self.loose = masks.adj, masks.fits, masks.nbr, masks.loose
        self.position = [{room: p for p, room in enumerate(order)} for order in preference]
        self.exempt = exempt
        self.stats = stats
        self.room_of = [-1] * masks.m
        self.free = (1 << masks.n) - 1
        self.placed = 0

    # -- state queries -------------------------------------------------------------
    def _typed_rooms(self, rule_mask: int) -> int:
        mask = 0
        for j in _bits(rule_mask & self.placed):
            mask |= 1 << self.room_of[j]
        return mask

    def _potential(self, rule_mask: int) -> int:
        """Free rooms where one of the unplaced rules in ``rule_mask`` would fit."""
        mask = 0
        for j in _bits(rule_mask & ~self.placed):
            mask |= self.fits[j]
        return mask & self.free

    def candidates(self, k: int) -> tuple[int, int]:
        """(rooms satisfying rule k now, rooms where its neighbour may still come)."""
        fitting = self.fits[k] & self.free
        if k == self.exempt or self.loose >> k & 1:
            return fitting, 0
        typed = self._typed_rooms(self.nbr[k])
        potential = self._potential(self.nbr[k])
        now = later = 0
        for i in _bits(fitting):
            if self.adj[i] & typed:
                now |= 1 << i
            elif self.adj[i] & potential:
                later |= 1 << i
        return now, later

    def stranded(self) -> int | None:
        """A placed rule that can no longer get a listed neighbour, if any."""
        for k in _bits(self.placed & ~self.loose):
            if k == self.exempt:
                continue
            room_adj = self.adj[self.room_of[k]]
            if room_adj & self._typed_rooms(self.nbr[k]):
                continue
            if not room_adj & self._potential(self.nbr[k]):
                return k
        return None

    def ordered(self, k: int, now: int, later: int) -> list[int]:
        """Candidate rooms of rule k to try: those satisfying the rule now first, each
        group in the rule's order of preference."""
        position = self.position[k]
        return sorted(_bits(now), key=position.__getitem__) + sorted(_bits(later),
                                                                      key=position.__getitem__)

    # -- search --------------------------------------------------------------------
    def _record(self, failure: Failure) -> None:
        depth = bin(self.placed).count("1")
        if self.stats.first_failure is None:
            self.stats.first_failure = failure
        if depth > self.stats.deepest_depth:
            self.stats.deepest_depth = depth
            self.stats.deepest = failure

    def _place(self, k: int, room: int) -> None:
        self.room_of[k] = room
        self.free &= ~(1 << room)
        self.placed |= 1 << k

    def _unplace(self, k: int) -> None:
        self.free |= 1 << self.room_of[k]
        self.room_of[k] = -1
        self.placed &= ~(1 << k)
        self.stats.backtracks += 1

    def run(self, first: int) -> bool:
        now, later = self.candidates(first)
        if not now | later:
            self._record(Failure(tuple(self.room_of), "no-room", (first,)))
            return False
        return self._branch(first, self.ordered(first, now, later))

    def _branch(self, k: int, rooms: list[int]) -> bool:
        for room in rooms:
            self._place(k, room)
            if self._descend():
                return True
            self._unplace(k)
        return False

    def _descend(self) -> bool:
        stranded = self.stranded()
        if stranded is not None:
            self._record(Failure(tuple(self.room_of), "stranded", (stranded,)))
            return False
        if self.placed == (1 << self.m) - 1:
            return True
        best: tuple[tuple[int, int, int], int, int, int] | None = None
        domains: dict[int, int] = {}
        for k in range(self.m):
            if self.placed >> k & 1:
                continue
            now, later = self.candidates(k)
            count = bin(now | later).count("1")
            if count == 0:
                self._record(Failure(tuple(self.room_of), "no-room", (k,)))
                return False
            domains[k] = now | later
            key = (0 if now else 1, count, k)
            if best is None or key < best[0]:
                best = (key, k, now, later)
        crowded = _crowded(domains)
        if crowded is not None:
            rivals, candidates = crowded
            self._record(Failure(tuple(self.room_of), "crowded", rivals,
                                 tuple(_bits(candidates))))
            return False
        assert best is not None
        _, k, now, later = best
        return self._branch(k, self.ordered(k, now, later))


def _exemptions(masks: _Masks, first: int) -> list[int]:
    """The rules to try as the one without a neighbour, hardest first (fewest supporting
    pairs; ties: the first rule, then table order).

    A rule without any supporting pair can only be satisfied by exemption, so it is the
    only one worth exempting; two such rules make every search futile.
    """
    tied = [k for k in range(masks.m) if not masks.loose >> k & 1]
    support = {k: masks.support(k) for k in tied}
    hopeless = [k for k in tied if support[k] == 0]
    if len(hopeless) > 1:
        return []
    if hopeless:
        return hopeless
    return sorted(tied, key=lambda k: (support[k], k != first, k))


def place_rules(rooms: RoomSet, rules: Sequence[RuleSpec], *, first: int,
                rng: np.random.Generator) -> Placement | Unplaceable:
    """Give every mandatory rule its own room (greedy pass + correction backtracking).

    Parameters
    ----------
    rooms:
        Areas, door-capable adjacency and front-door-capable rooms.
    rules:
        The mandatory rules, in table order.
    first:
        Index of the rule placed first (the thesis draws it by ``Prob``).
    rng:
        Jitters each rule's order of preference among rooms (:func:`size_preferences`),
        so seeds vary the layout.

    Returns
    -------
    Placement | Unplaceable
        The placement, or, when none exists, the deepest dead end of every search tried
        (for :func:`.explain.explain_failure`).

    Notes
    -----
    Complete: every search is exhaustive apart from pruning that only removes states
    without a valid completion, so a placement is found whenever one exists. Worst case
    exponential in the number of rules; with the pruning, floors of 12 rooms take
    milliseconds (see ``benchmarks/bench_type_rooms.py``).

    References
    ----------
    Thesis §5.2.2, Algorithms 3 (fixTyping) and 12 (checkRooms).
    """
    if not rules:
        return Placement(rooms=(), exempt=None, first_failure=None, backtracks=0)
    preference = size_preferences(rooms.areas, [r.min_area for r in rules], rng)
    masks = _Masks(rooms, rules)
    stats = _SearchStats()
    failures: list[Failure] = []
    exempt: int | None = None
    options: list[int] | None = None  # computed once the search without exemption fails
    while True:
        search = _Search(masks, preference, exempt, stats)
        if search.run(first if exempt is None else exempt):
            return Placement(rooms=tuple(search.room_of), exempt=exempt,
                             first_failure=stats.first_failure, backtracks=stats.backtracks)
        if stats.deepest is not None:
            failures.append(stats.deepest)
        stats.deepest, stats.deepest_depth = None, -1
        if options is None:
            options = _exemptions(masks, first)
        if not options:
            return Unplaceable(tuple(failures))
        exempt = options.pop(0)
