"""The typing process of the thesis (§3.3, §5.2.2, Algorithms 2 and 11) on abstract rooms.

Phases, as in the thesis:

1. the first rule is drawn by ``Prob`` (a uniform number ``u``; rules with ``Prob ≥ u``
   qualify, one of them is taken at random) and put on a room big enough for it, chosen
   at random with a preference for rooms whose size rank matches the rule's;
2. the remaining mandatory rules are placed on free rooms that are big enough and adjoin
   a room of a listed type; when one cannot be placed, the correction backtracker
   revisits earlier placements (:mod:`.backtrack`);
3. optional rules, and further rooms of types whose ``appearance`` allows more than
   one, fill the rooms that remain, round by round in table order, each on a free room
   that is big enough and adjoins a listed type (preferring rooms whose size rank
   matches the rule's, with random jitter);
4. rooms still free get the default type ``Commonroom``.

A floor with fewer rooms than mandatory rules cannot hold them all; then as many rules
as fit are placed, the ``isOutsideConnected`` rule first and the others in table order,
and the skipped ones are reported instead of failing.

The rooms are a :class:`~.backtrack.RoomSet` (areas, door-capable adjacency, rooms that
can take the front door), so this module knows nothing of walls or polygons; all
randomness comes from the ``rng`` argument.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from cga.errors import NoSolutionError

from .backtrack import (Placement, RoomSet, RuleSpec, Unplaceable, place_rules,
                        size_preferences)
from .explain import explain_failure, static_reasons
from .rules import DEFAULT_TYPE, RuleTable, TypeRule

__all__ = ["TypingNote", "Typing", "assign_types", "draw_first_rule"]


@dataclass(frozen=True)
class TypingNote:
    """A message about the typing; ``room`` is a room id when the note is about one."""

    level: Literal["info", "warning"]
    message: str
    room: int | None = None


@dataclass(frozen=True)
class Typing:
    """The outcome: a type per room (in :class:`RoomSet` order).

    ``mandatory`` maps each placed mandatory type to its room index; ``exempt`` names the
    mandatory type left without a listed neighbour (None normally); ``skipped`` lists the
    mandatory types a too-small floor could not hold; ``backtracks`` counts the
    correction's undone placements.
    """

    types: tuple[str, ...]
    mandatory: dict[str, int]
    exempt: str | None
    skipped: tuple[str, ...]
    backtracks: int
    notes: tuple[TypingNote, ...]


def draw_first_rule(rules: Sequence[TypeRule], rng: np.random.Generator) -> int:
    """Index of the rule placed first (thesis Algorithm 2, lines 2–10).

    A uniform number ``u`` is drawn; rules with ``Prob ≥ u`` qualify and one of them is
    chosen uniformly. When none qualifies (every ``Prob`` is below ``u``), the rules
    with the highest ``Prob`` do.
    """
    chance = rng.random()
    eligible = [k for k, rule in enumerate(rules) if chance <= rule.prob]
    if not eligible:
        top = max(rule.prob for rule in rules)
        eligible = [k for k, rule in enumerate(rules) if rule.prob == top]
    return eligible[int(rng.integers(len(eligible)))]


def assign_types(rooms: RoomSet, table: RuleTable, rng: np.random.Generator, *,
                 area_scale: float = 1.0, pinned: Mapping[int, str] | None = None) -> Typing:
    """Type every room by the table's rules.

    Parameters
    ----------
    rooms:
        Areas in m², door-capable adjacency, rooms able to take the front door (None
        when this floor gets none) and room ids for messages.
    table:
        The parsed rules.
    rng:
        The only source of randomness.
    area_scale:
        m² per area unit of the table's ``Size`` column (``units²`` of the grammar).
    pinned:
        Rooms whose type is fixed beforehand (room index → type): corridors and halls
        carved by ``make_floor`` take the table's circulation type. They count for their
        rule and as neighbours, and need no neighbour themselves.

    Returns
    -------
    Typing

    Raises
    ------
    NoSolutionError
        The floor has at least as many rooms as mandatory rules but no placement
        satisfies them; the message says which rule failed and why, in numbers.

    References
    ----------
    Thesis §3.3 and §5.2.2, Algorithms 2 (processRules) and 11 (assignRules).
    """
    pinned = dict(pinned or {})
    fixed_types = set(pinned.values())
    mandatory = tuple(r for r in table.mandatory if r.type not in fixed_types)
    fixed_specs = [RuleSpec(type=t, min_area=0.0, neighbours=frozenset(),
                            outside=_is_outside(table, t), pinned=i) for i, t in pinned.items()]
    specs = fixed_specs + [_spec(r, area_scale) for r in mandatory]
    notes: list[TypingNote] = []
    if len(rooms) < len(specs):
        kept = _rules_that_fit(rooms, specs, rng)
        skipped = tuple(s.type for k, s in enumerate(specs) if k not in kept)
        placed_names = ", ".join(specs[k].type for k in kept) or "none"
        notes.append(TypingNote("warning", (
            f"{len(rooms)} room{'s' if len(rooms) != 1 else ''} for {len(specs)} mandatory "
            f"rules: placed {placed_names}; skipped {', '.join(skipped)}")))
        specs = [specs[k] for k in kept]
        first = _priority(specs)[0] if specs else 0
    else:
        skipped = ()
        first = 0 if fixed_specs or not mandatory else draw_first_rule(mandatory, rng)
    result = place_rules(rooms, specs, first=first, rng=rng)
    if isinstance(result, Unplaceable):
        raise _no_solution(rooms, specs, result, table)
    notes += _placement_notes(rooms, specs, result)
    types: list[str | None] = [None] * len(rooms)
    for spec, room in zip(specs, result.rooms):
        types[room] = spec.type
    _fill_optional(rooms, table, types, rng, area_scale=area_scale, skipped=set(skipped))
    for i in pinned:  # a pinned type not in the table still names its room
        types[i] = pinned[i]
    leftover = [i for i, t in enumerate(types) if t is None]
    if leftover:
        names = ", ".join(rooms.name(i) for i in leftover)
        notes.append(TypingNote("info", f"{names} got the default type {DEFAULT_TYPE}: no "
                                        "rule with rooms left to give fits there"))
    final = tuple(t if t is not None else DEFAULT_TYPE for t in types)
    return Typing(types=final,
                  mandatory={spec.type: room for spec, room in zip(specs, result.rooms)},
                  exempt=None if result.exempt is None else specs[result.exempt].type,
                  skipped=skipped, backtracks=result.backtracks, notes=tuple(notes))


def _spec(rule: TypeRule, area_scale: float) -> RuleSpec:
    return RuleSpec(type=rule.type, min_area=rule.size * area_scale,
                    neighbours=frozenset(rule.placement), outside=rule.outside,
                    max_area=math.inf if rule.max_size is None else rule.max_size * area_scale,
                    needs_window=rule.needs_window)


def _is_outside(table: RuleTable, type_name: str) -> bool:
    rule = table.rule_for(type_name)
    return rule is not None and rule.outside


def _fits(rooms: RoomSet, i: int, rule: TypeRule, area_scale: float) -> bool:
    """Whether room ``i`` has the size (and outer wall) the rule asks for."""
    area = rooms.areas[i]
    if area < rule.size * area_scale:
        return False
    if rule.max_size is not None and area > rule.max_size * area_scale:
        return False
    return not rule.needs_window or rooms.outer is None or i in rooms.outer


def _priority(specs: Sequence[RuleSpec]) -> list[int]:
    """The front-door rule first, then table order."""
    order = list(range(len(specs)))
    return sorted(order, key=lambda k: (not specs[k].outside, k))


def _rules_that_fit(rooms: RoomSet, specs: Sequence[RuleSpec],
                    rng: np.random.Generator) -> list[int]:
    """Mandatory rules (indices, table order) that a floor with too few rooms can hold:
    taken in priority order, each kept if it can be placed together with those kept."""
    kept: list[int] = []
    for k in _priority(specs):
        if len(kept) == len(rooms):
            break
        trial = sorted(kept + [k])
        subset = [specs[j] for j in trial]
        if isinstance(place_rules(rooms, subset, first=_priority(subset)[0], rng=rng),
                      Placement):
            kept = trial
    return kept


def _placement_notes(rooms: RoomSet, specs: Sequence[RuleSpec],
                     placement: Placement) -> list[TypingNote]:
    notes: list[TypingNote] = []
    if placement.first_failure is not None:
        stuck = placement.first_failure.rooms
        moved = [f"{spec.type} {rooms.name(before)} → {rooms.name(after)}"
                 for spec, before, after in zip(specs, stuck, placement.rooms)
                 if 0 <= before != after]
        notes.append(TypingNote("info", (
            f"correction: {explain_failure(rooms, specs, placement.first_failure)}; fixed "
            f"after {placement.backtracks} backtracking step"
            f"{'s' if placement.backtracks != 1 else ''}"
            + (f" by moving {'; '.join(moved)}" if moved else ""))))
    if placement.exempt is not None:
        spec = specs[placement.exempt]
        room = placement.rooms[placement.exempt]
        providers = [s.type for s in specs if s is not spec and s.type in spec.neighbours]
        if providers:
            notes.append(TypingNote("warning", (
                f"no typing gives every mandatory rule a listed neighbour; {spec.type} in "
                f"{rooms.name(room)} has none (it lists {', '.join(sorted(spec.neighbours))})"),
                room=_room_id(rooms, room)))
        else:
            notes.append(TypingNote("info", (
                f"{spec.type} starts the typing without a neighbour: it lists only "
                f"{', '.join(sorted(spec.neighbours))}, which no other placed mandatory "
                "rule provides"), room=_room_id(rooms, room)))
    return notes


def _room_id(rooms: RoomSet, i: int) -> int:
    return rooms.ids[i] if rooms.ids is not None else i


def _fill_optional(rooms: RoomSet, table: RuleTable, types: list[str | None],
                   rng: np.random.Generator, *, area_scale: float, skipped: set[str]) -> None:
    """Phase 3: optional rules and further rooms of repeatable types, round by round in
    table order; each takes its most preferred free room that is big enough and adjoins
    a listed type (:func:`~.backtrack.size_preferences` over the whole table)."""
    counts: dict[str, int] = {}
    for t in types:
        if t is not None:
            counts[t] = counts.get(t, 0) + 1
    pool = [r for r in table.rules if r.type not in skipped]
    preferences = size_preferences(rooms.areas, [r.size for r in pool], rng)
    while any(t is None for t in types):
        progress = False
        for rule, preference in zip(pool, preferences):
            if counts.get(rule.type, 0) >= rule.appearance:
                continue
            room = next((i for i in preference
                         if types[i] is None and _fits(rooms, i, rule, area_scale)
                         and any(types[j] in rule.placement for j in rooms.adjacency[i])),
                        None)
            if room is None:
                continue
            types[room] = rule.type
            counts[rule.type] = counts.get(rule.type, 0) + 1
            progress = True
        if not progress:
            return


def _no_solution(rooms: RoomSet, specs: Sequence[RuleSpec], result: Unplaceable,
                 table: RuleTable) -> NoSolutionError:
    reasons = static_reasons(rooms, specs)
    if not reasons:
        deepest = max(result.failures, key=lambda f: sum(r >= 0 for r in f.rooms),
                      default=None)
        if deepest is not None:
            reasons = [explain_failure(rooms, specs, deepest)]
    areas = ", ".join(f"{a:.1f}" for a in sorted(rooms.areas, reverse=True))
    reasons.append("to fix it, lower a Size, widen a Neighbours list or make a rule optional "
                   "(additionRoom=1)")
    return NoSolutionError(
        f"{table.file}: no room typing satisfies every mandatory rule "
        f"({', '.join(s.type for s in specs)}) on {len(rooms)} rooms of {areas} m²", reasons)
