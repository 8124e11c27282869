"""The stair between two consecutive storeys, laid out in the building's core.

In the core frame (:class:`cga.model.StairCore`: ``u`` along the flights from the
landing end, ``v`` across), with landing depth ``D``, flight width ``w``, well ``g``
and flight run ``r``:

* U stair (half landing): flight A climbs along ``v ∈ [0, w]`` from ``u = D`` to the
  half landing ``u ∈ [D + r, 2D + r]``; flight B climbs back along
  ``v ∈ [w + g, 2w + g]`` and arrives at ``u = D``, beside where A started. Both floor
  landings are the strip ``u ∈ [0, D]``, so the same core stacks through any number of
  storeys, each storey's flights one storey above the last.
* straight stair: one flight from the bottom landing ``u ∈ [0, D]`` to the top landing
  ``u ∈ [D + r, 2D + r]`` on the floor above; it serves two storeys.

The stairwell cut into the upper floor's slab is the stair's outline without the floor
landings, so the stair and the hole above it have the same footprint.
"""

from __future__ import annotations

from cga.errors import DerivationError
from cga.model import Flight, FloorPlan, Stair, StairCore

__all__ = ["landing_rect", "stair_between"]


def landing_rect(core: StairCore, top: bool, margin: float = 0.0):
    """The floor landing of the core: the bottom landing (``top=False``) or the top one,
    grown by ``margin`` on its three sides away from the flights (``margin`` = the wall
    thickness reaches the core's wall centre lines)."""
    d, w = core.landing_depth, core.interior_width
    if top and core.kind == "straight":
        return core.rect(d + core.run, 2 * d + core.run + margin, -margin, w + margin)
    return core.rect(-margin, d, -margin, w + margin)


def stair_between(core: StairCore, lower: FloorPlan, upper: FloorPlan, stair_id: int) -> Stair:
    """The stair from ``lower`` up to ``upper`` in ``core``.

    Raises
    ------
    DerivationError
        The floors are not as far apart as the core's stair climbs (storeys of different
        heights share one core).
    """
    climb = upper.floor_y - lower.floor_y
    if abs(climb - core.risers * core.rise) > 1e-6:
        raise DerivationError(
            f"floors {lower.index} and {upper.index} are {climb:.3f} m apart, but their stair "
            f"core was sized for {core.risers * core.rise:.3f} m: storeys sharing a stair must "
            "be equally high")
    d, w, g, r = core.landing_depth, core.width, core.well, core.run
    m = core.flight_risers
    base = lower.floor_y
    first = Flight(start=core.at(d, w / 2), direction=core.u, width=w, base_y=base,
                   risers=m, rise=core.rise, going=core.going)
    if core.kind == "U":
        back = (-core.u[0], -core.u[1])
        second = Flight(start=core.at(d + r, w + g + w / 2), direction=back, width=w,
                        base_y=first.top_y, risers=m, rise=core.rise, going=core.going)
        flights: tuple[Flight, ...] = (first, second)
        half = core.rect(d + r, 2 * d + r, 0.0, core.interior_width)
        polygon = core.rect(d, 2 * d + r, 0.0, core.interior_width)
        points = (core.at(d / 2, w / 2), core.at(d / 2, w + g + w / 2))
    else:
        flights, half = (first,), None
        polygon = first.polygon()
        points = (core.at(d / 2, w / 2), core.at(d + r + d / 2, w / 2))
    if lower.core_room is None or upper.core_room is None:
        raise ValueError("both floors of a stair must have a core room")
    return Stair(id=stair_id, floors=(lower.index, upper.index), kind=core.kind,
                 polygon=polygon, landings=(landing_rect(core, False), landing_rect(core, True)),
                 landing_points=points, flights=flights, half_landing=half,
                 rooms=(lower.core_room, upper.core_room), width=w, rise=core.rise,
                 going=core.going, risers=core.risers, bottom_y=base, top_y=upper.floor_y)
