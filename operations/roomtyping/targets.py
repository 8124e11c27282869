"""The room areas a typing table asks for, to aim a floor's cuts at (DESIGN §11).

When a layout has no typing, ``type_rooms`` re-draws the floor with cut positions aimed
at areas (:func:`cga.operations.floorplan.treemap.partition_to_areas`). The areas come
from the table: one room per mandatory rule at its ``Size`` (circulation rules are
carved by ``make_floor`` and left out), then optional rules and repeatable types (the
roomiest while the rules' ``maxSize`` cannot fill the floor, then in table order) until
every room has an area; the floor's spare area is shared in
proportion, never pushing a room past its rule's ``maxSize`` while another can grow.
"""

from __future__ import annotations

from .rules import RuleTable, TypeRule

__all__ = ["redraw_count", "target_areas"]

_FLOOR = 1.0
"""Area (m²) given to a room no rule sizes, before the spare area is shared."""

_MARGIN = 0.92
"""Rooms are first grown to this fraction of their rule's ``maxSize``."""

_MANY_TIMES = 2.0
"""How many times the grammar's room count a floor must hold rooms of the table's
typical size for :func:`redraw_count` to draw more."""


def target_areas(table: RuleTable, count: int, free_area: float, area_scale: float) -> list[float]:
    """``count`` areas (m²) summing to ``free_area``, one per room the floor should have.

    Examples
    --------
    >>> from cga.operations.roomtyping.rules import parse_rule_table
    >>> table = parse_rule_table("Type;Size;Prob;Neighbours;isOutsideConnected;appearance;additionRoom\\n"
    ...                          "Living;20;1;Bath;true;1;0\\nBath;5;0;Living;0;1;0")
    >>> [round(a) for a in target_areas(table, 2, 50.0, 1.0)]
    [40, 10]
    """
    rules = [r for r in table.mandatory if not r.circulation]
    sized: list[TypeRule | None] = list(rules[:count])
    counts = {r.type: 1 for r in rules[:count]}
    extra = [r for r in table.rules if not r.circulation]
    while len(sized) < count:
        open_ = [r for r in extra if counts.get(r.type, 0) < r.appearance]
        if not open_:
            sized += [None] * (count - len(sized))
            break
        room_left = free_area - sum(_cap(r, area_scale) for r in sized if r is not None)
        # while the caps cannot fill the floor, add the roomiest rule; then table order
        rule = max(open_, key=lambda r: _cap(r, area_scale)) if room_left > 0 else open_[0]
        sized.append(rule)
        counts[rule.type] = counts.get(rule.type, 0) + 1
    wanted = [max(r.size * area_scale, _FLOOR) if r else _FLOOR for r in sized]
    caps = [_cap(r, area_scale) if r else float("inf") for r in sized]
    # aim a little under the caps first: cuts land on a grid, near corners, never exact
    areas = _share_spare(wanted, [c * _MARGIN for c in caps], free_area, overflow=False)
    return _share_spare(areas, caps, free_area, overflow=True)


def redraw_count(table: RuleTable, count: int, free_area: float, area_scale: float, *,
                 attempt: int = 1, attempts: int = 1) -> int:
    """How many rooms re-draw ``attempt`` (1 to ``attempts``) aims at: the grammar's
    ``count``, unless the free floor holds fewer rooms of the table's typical size (the
    mean of its mandatory rules' ``Size``..``maxSize`` midpoints, twice ``Size`` where
    no ``maxSize``), or more than :data:`_MANY_TIMES` as many. Then the first half of
    the re-draws still aim at ``count`` (a floor that types with the grammar's count
    keeps it), and each later one nearer as many as the floor holds (at least one per
    mandatory rule, at most as many as the table's ``appearance`` limits can type), the
    last at that number itself.

    The house demo's six rooms on a 20 × 15 m lot are 20–50 m² each: no re-draw with six
    can give a bathroom of at most 9 m² or a kitchen of at most 18 m², and the build
    fails; with the ten to thirteen the floor holds it is a house. The apartment block's
    eight rooms a storey on 12 × 9 m leave none of the 16 m² its living room needs; five
    do. On the lots they were written for the demos hold their counts.

    Examples
    --------
    >>> from cga.operations.roomtyping.rules import parse_rule_table
    >>> table = parse_rule_table("Type;Size;Prob;Neighbours;isOutsideConnected;appearance;"
    ...                          "additionRoom;maxSize\\nLiving;16;1;Bath;true;1;0;24\\n"
    ...                          "Bath;4;0;Living;0;2;0;8\\nGuest;9;0;Living;0;3;1;")
    >>> [redraw_count(table, 3, area, 1.0, attempt=12, attempts=12)
    ...  for area in (20.0, 60.0, 150.0)]
    [2, 3, 6]
    """
    rules = [r for r in table.mandatory if not r.circulation]
    if not rules:
        return count
    typical = sum((r.size + (r.max_size if r.max_size is not None else 2 * r.size)) / 2
                  for r in rules) * area_scale / len(rules)
    holds = int(free_area / typical)
    if holds < count:  # as many as it holds, but a room for each mandatory rule
        aim = min(count, max(holds, len(rules)))
    elif holds > _MANY_TIMES * count:
        aim = min(holds, sum(r.appearance for r in table.rules if not r.circulation))
    else:
        return count
    if attempts <= 1:
        return aim
    first = attempts // 2  # the grammar's own count first: the floor is seldom that far off
    if attempt <= first:
        return count
    return round(count + (aim - count) * (attempt - first) / (attempts - first))


def _cap(rule: TypeRule, area_scale: float) -> float:
    return rule.max_size * area_scale if rule.max_size is not None else float("inf")


def _share_spare(wanted: list[float], caps: list[float], total: float, *,
                 overflow: bool) -> list[float]:
    """Grow the areas in proportion until they sum to ``total``, capped rooms stopping at
    their cap (water filling); with no room left to grow, the capped ones grow too when
    ``overflow``, else the areas stay short of ``total``."""
    areas = list(wanted)
    spare = total - sum(areas)
    if spare <= 0:
        return [a * total / sum(areas) for a in areas]
    for _ in range(len(areas) + 1):
        open_ = [i for i, a in enumerate(areas) if a < caps[i] - 1e-9]
        if not open_ or spare <= 1e-9:
            break
        weight = sum(areas[i] for i in open_)
        step = spare
        for i in open_:
            step = min(step, (caps[i] - areas[i]) * weight / areas[i])
        for i in open_:
            areas[i] += step * areas[i] / weight
        spare -= step
    if spare > 1e-9 and overflow:
        areas = [a + spare * a / sum(areas) for a in areas]
    return areas
