"""Explaining, in numbers, why the mandatory rules do not fit a floor.

A failed search leaves its deepest dead end (:class:`~.backtrack.Failure`): the rules
placed so far and the rule that found no room. :func:`explain_failure` turns it into a
sentence a rule author can act on ("Bedroom needs ≥ 12.0 m²; the largest free room next
to a Livingroom has 9.4 m²"); :func:`static_reasons` finds obstacles that hold whatever
the arrangement (a rule bigger than every room, too few big rooms, rules that can never
meet a listed neighbour), which are stated first because they are the real cause.
"""

from __future__ import annotations

import math

from collections.abc import Sequence

from .backtrack import Failure, RoomSet, RuleSpec

__all__ = ["explain_failure", "static_reasons"]


def _area(value: float) -> str:
    return f"{value:.1f} m²"


def _fits(rooms: RoomSet, rule: RuleSpec, i: int) -> bool:
    """Whether room ``i`` is big enough for ``rule`` (and can take the front door if the
    rule's room gets it)."""
    if rooms.areas[i] < rule.min_area:
        return False
    return not (rule.outside and rooms.entrances is not None and i not in rooms.entrances)


def _a(name: str) -> str:
    """``name`` with its indefinite article ("a Kitchen", "an Office")."""
    return f"{'an' if name[:1].lower() in 'aeiou' else 'a'} {name}"


def _either(names: Sequence[str]) -> str:
    names = list(names)
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " or " + names[-1]


def _listed(rule: RuleSpec, rules: Sequence[RuleSpec]) -> list[str]:
    """The rule's neighbour types that a mandatory rule provides (else all it lists)."""
    provided = [r.type for r in rules if r.type in rule.neighbours and r is not rule]
    return provided or sorted(rule.neighbours)


def explain_failure(rooms: RoomSet, rules: Sequence[RuleSpec], failure: Failure) -> str:
    """Say in numbers why the search got stuck at ``failure``.

    Examples: ``Bedroom needs ≥ 12.0 m²; the largest free room next to a Livingroom has
    9.4 m²`` or ``Kitchen needs a Livingroom neighbour; free rooms adjoin only Bathroom,
    Bedroom``. The placements made so far are named first.
    """
    type_at = {room: rules[k].type for k, room in enumerate(failure.rooms) if room >= 0}
    placed = ", ".join(f"{t} in {rooms.name(i)}" for i, t in type_at.items())
    prefix = f"with {placed}: " if placed else ""
    if failure.kind == "crowded":
        names = [rules[k].type for k in failure.rules]
        where = ", ".join(rooms.name(i) for i in failure.candidates) or "no room"
        return (f"{prefix}{_and(names)} each need one of {where} (the free rooms big enough "
                f"and beside a listed type or a room where one could go), which are too few")
    rule = rules[failure.rules[0]]
    if failure.kind == "stranded":
        return prefix + _stranded(rooms, rules, rule, failure, type_at)
    return prefix + _no_room(rooms, rules, rule, type_at)


def _and(names: Sequence[str]) -> str:
    names = list(names)
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def _stranded(rooms: RoomSet, rules: Sequence[RuleSpec], rule: RuleSpec, failure: Failure,
              type_at: dict[int, str]) -> str:
    home = failure.rooms[failure.rules[0]]
    wanted = _listed(rule, rules)
    head = f"{rule.type} in {rooms.name(home)} needs {_a(_either(wanted))} neighbour"
    waiting = [r for k, r in enumerate(rules) if r.type in wanted and failure.rooms[k] < 0]
    if not waiting:
        return f"{head}, but {_and(wanted)} went to other rooms"
    beside = [i for i in rooms.adjacency[home] if i not in type_at]
    if not beside:
        return f"{head} but has no free neighbour left"
    smallest = min(waiting, key=lambda r: r.min_area)
    sizes = ", ".join(_area(rooms.areas[i]) for i in beside)
    return (f"{head}; its free neighbours ({sizes}) are smaller than {_a(smallest.type)} "
            f"needs ({_area(smallest.min_area)})")


def _unfit_beside(rooms: RoomSet, rule: RuleSpec, next_to: list[int], beside: str) -> str:
    """Why none of the free rooms ``next_to`` the rule's neighbours takes it, when they
    are big enough: the first of its other limits (area cap, window, front door) that
    every one of them misses."""
    smallest = min(rooms.areas[i] for i in next_to)
    if smallest > rule.max_area:
        return (f"{rule.type} may have at most {_area(rule.max_area)}; the smallest free room "
                f"next to {beside} has {_area(smallest)}")
    if rule.needs_window and rooms.outer is not None and not any(i in rooms.outer for i in next_to):
        return f"{rule.type} needs a window, but the free rooms next to {beside} have no outer wall"
    if rule.outside and rooms.entrances is not None:
        return (f"{rule.type} gets the front door, but the free rooms next to "
                f"{beside} have no outer wall long enough for a door")
    size = (f"≥ {_area(rule.min_area)}" if math.isinf(rule.max_area)
            else f"{_area(rule.min_area)}–{_area(rule.max_area)}")
    return (f"{rule.type} ({size}) fits none of the free rooms next to {beside} once the "
            "other rules are placed")


def _no_room(rooms: RoomSet, rules: Sequence[RuleSpec], rule: RuleSpec,
             type_at: dict[int, str]) -> str:
    free = [i for i in range(len(rooms)) if i not in type_at]
    if not free:
        return f"no free room is left for {rule.type}"
    entrances = rooms.entrances if rule.outside else None
    fitting = [i for i in free if _fits(rooms, rule, i)]
    if not fitting:
        if entrances is not None:
            doors = [i for i in free if i in entrances]
            if not doors:
                return (f"{rule.type} gets the front door, but no free room has an outer "
                        "wall long enough for a door")
            return (f"{rule.type} needs ≥ {_area(rule.min_area)} and an outer wall for the "
                    f"front door; the largest free room with one has "
                    f"{_area(max(rooms.areas[i] for i in doors))}")
        return (f"{rule.type} needs ≥ {_area(rule.min_area)}; the largest free room has "
                f"{_area(max(rooms.areas[i] for i in free))}")
    present = sorted({t for t in type_at.values() if t in rule.neighbours})
    next_to = [i for i in free if any(type_at.get(j) in present for j in rooms.adjacency[i])]
    if next_to:
        largest = max(rooms.areas[i] for i in next_to)
        if largest < rule.min_area:
            return (f"{rule.type} needs ≥ {_area(rule.min_area)}; the largest free room next "
                    f"to {_a(_either(present))} has {_area(largest)}")
        return _unfit_beside(rooms, rule, next_to, _a(_either(present)))
    wanted = _either(_listed(rule, rules))
    around = sorted({type_at[j] for i in fitting for j in rooms.adjacency[i] if j in type_at})
    if around:
        return (f"{rule.type} needs {_a(wanted)} neighbour; free rooms adjoin only "
                f"{', '.join(around)}")
    return (f"{rule.type} needs {_a(wanted)} neighbour; the free rooms of "
            f"≥ {_area(rule.min_area)} adjoin no typed room")


def static_reasons(rooms: RoomSet, rules: Sequence[RuleSpec]) -> list[str]:
    """Reasons that rule out every placement whatever the search does (sizes, front
    door, neighbours that cannot exist); empty when the obstacle is the arrangement."""
    reasons: list[str] = []
    largest = max(rooms.areas, default=0.0)
    nowhere = [not any(_fits(rooms, rule, i) for i in range(len(rooms))) for rule in rules]
    for rule, fits_nowhere in zip(rules, nowhere):
        if fits_nowhere:
            if rule.min_area > largest:
                reasons.append(f"{rule.type} needs ≥ {_area(rule.min_area)}; the largest room "
                               f"has {_area(largest)}")
            else:
                doors = sorted(rooms.entrances or ())
                reasons.append(
                    f"{rule.type} gets the front door, so it needs ≥ {_area(rule.min_area)} "
                    + (f"and an outer wall for the door; the largest room with one has "
                       f"{_area(max(rooms.areas[i] for i in doors))}" if doors else
                       "and an outer wall long enough for a door; no room has one"))
    needs = sorted(rules, key=lambda r: r.min_area, reverse=True)
    areas = sorted(rooms.areas, reverse=True)
    for count, rule in enumerate(needs[1:], start=2):  # one rule alone: said above
        if count <= len(areas) and areas[count - 1] < rule.min_area:
            names = ", ".join(f"{r.type} {_area(r.min_area)}" for r in needs[:count])
            big = sum(a >= rule.min_area for a in areas)
            reasons.append(f"{count} mandatory rules need rooms of at least ({names}) but only "
                           f"{big} room{'s' if big != 1 else ''} ha{'ve' if big != 1 else 's'} "
                           f"≥ {_area(rule.min_area)}")
            break
    lonely: list[str] = []
    for rule, fits_nowhere in zip(rules, nowhere):
        if rule.pinned is not None or fits_nowhere:
            continue  # a carved hall needs no neighbour; a rule that fits nowhere is said above
        partners = [r for r in rules if r is not rule and r.type in rule.neighbours]
        if any(_fits(rooms, rule, i) and _fits(rooms, p, j)
               for i in range(len(rooms)) for j in rooms.adjacency[i] for p in partners):
            continue
        if not partners:
            lonely.append(f"{rule.type} lists only {', '.join(sorted(rule.neighbours))}, "
                          "none of them a mandatory type")
        elif all(p.pinned is not None for p in partners):
            lonely.append(f"{rule.type} needs {_a(_either([p.type for p in partners]))} "
                          f"neighbour; no room of ≥ {_area(rule.min_area)} adjoins "
                          + " or ".join(f"the {p.type} ({rooms.name(p.pinned)})"
                                        for p in partners if p.pinned is not None))
        else:
            smallest = min(p.min_area for p in partners if p.pinned is None)
            lonely.append(f"{rule.type} needs {_a(_either([p.type for p in partners]))} "
                          f"neighbour; no room of ≥ {_area(rule.min_area)} adjoins a room of "
                          f"≥ {_area(smallest)}")
    if len(lonely) > 1:
        reasons.append(f"only one rule (the first placed) may go without a listed neighbour, "
                       f"but {len(lonely)} cannot have one:")
        reasons += lonely
    return reasons
