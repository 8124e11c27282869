"""``make_floor(split, wallWidth, numWindows>windowWidth>windowHigh, doorWidth, doorHeight)``.

Partitions a storey into rooms (docs/architecture.md, "Floor plans", thesis §5.1): the
floor slice's footprint is cut by a randomised BSP over a half-edge structure into
``split + 1`` rooms, outer walls get their windows, and the shape passes on unchanged with a
:class:`cga.model.FloorPlan` attached. Doors come later (``type_rooms``), and the 3D
walls and slabs are made from the final plan at meshing time
(:func:`cga.meshing.solids.floor_nodes`).

Stairs (DESIGN §12): a storey of a stack of several (``repeated_split("y", ...)`` sets
the ``floors`` attribute) first reserves the building's stair core, one rectangle in the
same place on every storey (:func:`cga.operations.stairs.core_for_storey`), kept clear
of the storey's corridors and next to them when it can be. The core is the first fixed
face of the partition (never cut), a circulation room typed ``Stair``; the partition is
redrawn when its landing has no wall for a door. ``stair="none"`` builds storeys
without one.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from shapely.geometry import Polygon
from shapely.geometry.polygon import orient

from cga.errors import DerivationError
from cga.model import Diagnostic, FloorPlan, FloorSettings, StairCore
from cga.randomness import stream
from cga.shape import Mass, Shape

from cga.operation import PARALLEL_SPINES_USED, Child, Operation, OperationContext, Param, is_number

if TYPE_CHECKING:
    from .floorplan.bsp import FixedFace, Partition
    from .floorplan.circulation import CorridorSpec

# The partition, circulation, stair and door modules are imported where a floor is made
# (``apply`` and its helpers), not here: ``cga check`` loads this module for its
# parameters and value checks only, and those imports are a fifth of its start-up.

__all__ = ["MIN_CORRIDOR_WIDTH", "MakeFloor", "floor_settings"]

MIN_CORRIDOR_WIDTH = 1.2
"""Least corridor width (m): two people pass, a wheelchair turns (docs/architecture.md)."""


class MakeFloor(Operation):
    """Floor slice → the same slice with a floor plan of ``split + 1`` rooms."""

    name = "make_floor"
    params = (
        Param("split", "count", doc="number of BSP cuts; rooms = split + 1"),
        Param("wallWidth", "length", doc="wall thickness"),
        Param("windows", "tuple", items=("count", "length", "length"),
              doc="numWindows>windowWidth>windowHigh: windows per outer wall segment, size"),
        Param("doorWidth", "length", doc="door width (used by type_rooms)"),
        Param("doorHeight", "length", doc="door height (used by type_rooms)"),
        Param("min_room_width", "length", default=2.4, keyword_only=True,
              doc="no room narrower than this anywhere (m)"),
        Param("min_room_area", "area", default=6.0, keyword_only=True,
              doc="no room smaller than this (m²)"),
        Param("cut_range", "range", default=(0.35, 0.65), keyword_only=True,
              doc="cut position drawn from this fraction of a room's extent; (0.5, 0.5) "
                  "is the thesis' partition: mid cuts, alternating axes (Algorithm 8)"),
        Param("same_layout", "bool", default=False, keyword_only=True,
              doc="every floor made by this rule gets the same layout"),
        Param("window_sill", "length", default=0.9, keyword_only=True,
              doc="height of the window bottoms above the floor (m)"),
        Param("corridor", "string", default="none", keyword_only=True,
              doc="circulation carved before the rooms: 'none', 'spine' (double-loaded "
                  "corridor along the long axis), 'hall' (across the short axis, from the "
                  "front wall) or 'centre_line' (through every wing of an L/U/T)"),
        Param("corridor_width", "length", default=1.2, keyword_only=True,
              doc="corridor width between wall centre lines (m, at least 1.2 m)"),
        Param("corridor_position", "number", default=0.5, keyword_only=True,
              doc="where a spine or hall runs across the building (0..1, 0.5: middle)"),
        Param("min_room_depth", "length", default=2.5, keyword_only=True,
              doc="least depth of the rooms between corridor and outer wall (m)"),
        Param("max_room_depth", "length", default=6.0, keyword_only=True,
              doc="spine: a building deeper than two bands of rooms this deep and the "
                  "corridor gets parallel spines joined by a cross corridor (m)"),
        Param("n_left", "count", default=0, keyword_only=True,
              doc="spine: rooms of equal width on the low side (0: the BSP decides)"),
        Param("n_right", "count", default=0, keyword_only=True,
              doc="spine: rooms of equal width on the high side (0: the BSP decides)"),
        Param("stair", "string", default="U", keyword_only=True,
              doc="stair between the storeys of a stack: 'U' (half landing), 'straight' "
                  "(two storeys) or 'none'"),
        Param("stair_width", "length", default=1.0, keyword_only=True,
              doc="clear width of each flight (m)"),
        Param("max_rise", "length", default=0.19, keyword_only=True,
              doc="highest riser allowed (m)"),
        Param("min_going", "length", default=0.25, keyword_only=True,
              doc="shallowest tread allowed (m)"),
    )
    doc = ("make_floor(split, wallWidth, numWindows>windowWidth>windowHigh, doorWidth, "
           "doorHeight): partition a floor into split + 1 rooms")

    def check_values(self, args: dict[str, Any], units: float) -> None:
        count, window_width, window_height = args["windows"]
        named = {"wallWidth": args["wallWidth"], "windowWidth": window_width,
                 "windowHigh": window_height, "doorWidth": args["doorWidth"],
                 "doorHeight": args["doorHeight"]}
        for name, value in named.items():
            if is_number(value) and not value > 0:
                raise DerivationError(f"make_floor {name} must be positive, got {value / units:g}")
        sill = args["window_sill"]
        if is_number(sill) and not sill >= 0:
            raise DerivationError(f"window_sill must not be negative, got {sill / units:g}")
        lo, hi = args["cut_range"]
        if is_number(lo) and is_number(hi) and not 0 < lo <= hi < 1:
            raise DerivationError(f"cut_range must satisfy 0 < lo ≤ hi < 1, got ({lo:g}, {hi:g})")
        min_width, min_area, wall = args["min_room_width"], args["min_room_area"], args["wallWidth"]
        if is_number(min_width) and is_number(wall) and not min_width > 2 * wall:
            raise DerivationError(
                f"min_room_width ({min_width / units:g}) must be more than twice wallWidth "
                f"({wall / units:g}), or rooms have no floor left")
        if is_number(min_area) and not min_area >= 0:
            raise DerivationError(f"min_room_area must not be negative, got {min_area / units ** 2:g}")

    def apply(self, shape: Shape, args: dict[str, Any], ctx: OperationContext) -> list[Child]:
        from .floorplan.assemble import plan_from_dcel
        from .floorplan.bsp import partition
        from .floorplan.errors import PartitionError
        from .floorplan.layout import LayoutRecipe
        from .floorplan.openings import window_shortfall
        from .floorplan.tiling import tile_with_fixed_faces
        from .floorplan.treemap import thesis_partition
        from .roomtyping.doors import DOOR_MARGIN

        self.check_values(args, ctx.units)
        mass = shape.geometry
        if not isinstance(mass, Mass) or mass.height <= 0:
            raise DerivationError(
                "make_floor works on a storey (a mass with height), not on this shape",
                hint='cut the body into storeys first: repeated_split("y", floorHeight){...}')
        settings = floor_settings(args, mass.height, ctx.units)
        footprint = _footprint(mass.footprint)
        split = args["split"]
        lo, hi = args["cut_range"]
        min_width, min_area = args["min_room_width"], args["min_room_area"]
        rng = stream(ctx.seed, ("make_floor", shape.symbol)) if args["same_layout"] else ctx.rng
        index = int(shape.attrs.get("floor", 0))
        ring = list(footprint.exterior.coords)[:-1]
        spec = _corridor(args, ctx.units)
        if not ctx.parallel_spines:
            spec = replace(spec, max_depth=math.inf)
        fixed = _corridor_faces(ring, spec, footprint, ctx, index)
        if _on_parallel_spines(ring, spec, fixed):
            ctx.cache[PARALLEL_SPINES_USED] = True
        try:
            core = _core(shape, args, ctx, footprint, mass.height, settings,
                         [Polygon(f.polygon) for f in fixed])
        except DerivationError as error:
            if spec.n_left and spec.n_right:  # the core keeps clear of those rooms too
                error.add_hint("n_left and n_right fill both sides of the corridor with rooms "
                               "the stair core must keep clear of: set one of them to 0 so "
                               "the core has a side to stand in")
            raise
        rooms_fixed = sum(not f.circulation for f in fixed)
        if core is not None:
            fixed = [_core_face(core, fixed), *fixed]
        # Rooms besides the circulation and the core: split + 1; fixed rooms and free
        # pieces count.
        cuts = split
        if fixed:
            pieces = tile_with_fixed_faces(ring, [f.polygon for f in fixed])[1]
            cuts = max(0, split + 1 - pieces - rooms_fixed)
        door_reach = settings.door_width + 2 * (DOOR_MARGIN + settings.wall_thickness)
        thesis = (lo, hi) == (0.5, 0.5)
        if thesis and fixed:
            raise DerivationError("the thesis' partition (cut_range = (0.5, 0.5)) has no "
                                  "corridors or stair core; use another cut_range, or "
                                  'stair = "none" for a single storey')
        for _ in range(_CORE_ATTEMPTS):
            try:
                if thesis:
                    result = thesis_partition(ring, split)
                else:
                    result = partition(ring, cuts, rng, min_width=min_width, min_area=min_area,
                                       cut_range=(lo, hi), fixed=fixed, min_contact=door_reach)
            except PartitionError as error:
                raise DerivationError(f"make_floor cannot cut this footprint into rooms: {error}",
                                      hint=_footprint_hint(footprint)) from None
            try:
                plan = plan_from_dcel(result.dcel, settings=settings, index=index,
                                      elevation=mass.base, height=mass.height,
                                      circulation=result.circulation)
            except PartitionError as error:
                raise DerivationError(f"the floor is too narrow for its walls: {error}") from None
            if core is None:
                break
            plan = plan.with_stair_core(core)
            if _core_has_door(plan):
                break
        else:
            raise DerivationError(
                f"no partition of floor {index} in {_CORE_ATTEMPTS} tries leaves a wall at the "
                f"stair landing long enough for a {settings.door_width / ctx.units:g} door",
                hint="make the doors narrower or the rooms fewer")
        if result.shortfall is not None:
            ctx.report(Diagnostic("warning", "make_floor",
                                  f"made {_rooms_made(result, core)} rooms instead of {split + 1}: "
                                  f"{result.shortfall}", floor=index))
        windows = window_shortfall(plan.walls, settings, index)
        if windows is not None:
            ctx.report(windows)
        if not thesis:  # the thesis' partition is the same every time: nothing to re-draw
            plan = plan.with_changes(layout=LayoutRecipe(
                tuple(ring), split + 1, tuple(fixed), min_width, min_area, door_reach, settings,
                index, mass.base, mass.height, ctx.seed,
                ("make_floor", shape.symbol) if args["same_layout"] else ("make_floor", *shape.path),
                core=core))
        return [Child(successor=0, geometry=mass, scope=shape.scope, plan=plan)]


_CORE_ATTEMPTS = 8


def _corridor_faces(ring: list[tuple[float, float]], spec: CorridorSpec, footprint: Polygon,
                    ctx: OperationContext, index: int) -> list[FixedFace]:
    """The corridor's fixed faces (:func:`.floorplan.circulation.circulation_faces`).

    A straight ``spine`` or ``hall`` runs wall to wall across the footprint's bounding
    box, which an L, U or T footprint does not fill: there the corridor follows the
    footprint's centre line instead, with a warning, so a grammar written for a
    rectangle builds on an L-shaped lot (``--lot``) instead of failing. A building too
    shallow for rooms on both sides of it gets it along one outer wall instead
    (single-loaded, as narrow terraced houses and gallery-access flats are laid out),
    also with a warning.

    Raises
    ------
    DerivationError
        Neither corridor fits the footprint.
    """
    from .floorplan.circulation import CirculationError, circulation_faces

    try:
        return circulation_faces(ring, spec)
    except CirculationError as error:
        straight_failed = error
    fallbacks: list[tuple[CorridorSpec, str]] = []
    if spec.mode in ("spine", "hall"):
        if footprint.area < footprint.envelope.area - 1e-6:
            fallbacks.append((replace(spec, mode="centre_line"), (
                f"a straight {spec.mode} corridor does not fit this footprint "
                f"({straight_failed}); the corridor follows the footprint's centre line "
                "instead (corridor = \"centre_line\")")))
        fallbacks.append((replace(spec, single_loaded=True), (
            f"{straight_failed}, so the {spec.mode} runs along the outer wall with rooms "
            "on one side only (single-loaded)")))
    for fallback, message in fallbacks:
        try:
            fixed = circulation_faces(ring, fallback)
        except CirculationError:
            continue
        ctx.report(Diagnostic("warning", "make_floor", message, floor=index))
        return fixed
    raise DerivationError(f"make_floor cannot carve a {spec.mode} corridor: {straight_failed}",
                          hint=_footprint_size(footprint)) from None


def _on_parallel_spines(ring: list[tuple[float, float]], spec: CorridorSpec,
                        corridor: list[FixedFace]) -> bool:
    """Whether ``corridor`` is a ladder of parallel spines (``max_room_depth``) where
    the options without that limit give one spine."""
    from .floorplan.circulation import CirculationError, circulation_faces

    if not math.isfinite(spec.max_depth):
        return False
    try:
        return circulation_faces(ring, replace(spec, max_depth=math.inf)) != corridor
    except CirculationError:
        return False


def _rooms_made(result: Partition, core: StairCore | None) -> int:
    """Rooms of a partition as ``split`` counts them: without corridors, halls and the core."""
    return len(result.dcel.faces) - len(result.circulation) - (core is not None)
"""Partitions drawn (from the storey's stream) until the stair landing has a door site."""


def _core(shape: Shape, args: dict[str, Any], ctx: OperationContext, footprint: Polygon,
          height: float, settings: FloorSettings, corridors: list[Polygon]) -> StairCore | None:
    """The building's stair core when this storey is one of a stack of several."""
    from .stairs import STAIR_KINDS, StairParams, core_for_storey

    storeys = int(shape.attrs.get("floors", 1))
    args = {**{p.name: p.default for p in MakeFloor.params if p.name.startswith(("stair", "max_", "min_"))},
            **args}  # callers of apply() that predate the stair keywords
    kind = str(args["stair"])
    match = {k.lower(): k for k in STAIR_KINDS}.get(kind.lower())
    if match is None:
        raise DerivationError(f"stair must be one of {', '.join(map(repr, STAIR_KINDS))}, "
                              f"got {kind!r}")
    if storeys < 2 or match == "none":
        return None
    if match == "straight" and storeys > 2:
        raise DerivationError(
            f"a straight stair joins two storeys, but this building has {storeys}",
            hint='use stair = "U": U stairs (half landing) stack through any number of storeys')
    params = StairParams(kind=match, width=args["stair_width"], max_rise=args["max_rise"],  # type: ignore[arg-type]
                         min_going=args["min_going"])
    return core_for_storey(ctx.cache, ctx.seed, footprint, height, storeys, params,
                           wall=settings.wall_thickness, door_width=settings.door_width,
                           min_width=args["min_room_width"], corridors=corridors)


def _core_face(core: StairCore, fixed: list[FixedFace]) -> FixedFace:
    """The core as the partition's first fixed face, never cut. It is not marked as
    circulation for the partition, which would keep every room in touch with it: rooms
    reach the stair through the halls and rooms next to its landing; the core's room is
    flagged as circulation afterwards (:meth:`FloorPlan.with_stair_core`).

    Raises
    ------
    DerivationError
        The building's core (placed by its first storey) overlaps this storey's corridor.
    """
    from .floorplan.bsp import FixedFace

    for face in fixed:
        if Polygon(face.polygon).intersection(core.polygon).area > 1e-9:
            raise DerivationError(
                f"the building's stair core ({_bounds(core.polygon)}) overlaps this storey's "
                f"{face.kind}: every storey of a stack must leave the core's place free",
                hint="give the storeys the same corridor option, or stair = \"none\"")
    ring = list(orient(core.polygon, sign=1.0).exterior.coords)[:-1]
    return FixedFace(tuple((float(x), float(z)) for x, z in ring), circulation=False, kind="core")


def _bounds(polygon: Polygon) -> str:
    x0, z0, x1, z1 = polygon.bounds
    return f"x {x0:.2f}..{x1:.2f}, z {z0:.2f}..{z1:.2f}"


def _core_has_door(plan: FloorPlan) -> bool:
    """Whether a door fits between the stair landing and a neighbouring room."""
    from .roomtyping.doors import door_spans
    from .roomtyping.room_graph import door_sites
    from .stairs.access import core_door_spans

    spans = core_door_spans(plan, door_spans(plan))
    sites = door_sites(plan, spans, plan.settings.door_width)
    return any(plan.core_room in pair for pair in sites.inner)


def _corridor(args: dict[str, Any], units: float) -> CorridorSpec:
    """The corridor options, checked (docs/architecture.md, "Floor plans")."""
    from .floorplan.circulation import CORRIDOR_MODES, CorridorSpec

    mode = str(args["corridor"]).lower()
    if mode not in CORRIDOR_MODES:
        raise DerivationError(f"corridor must be one of {', '.join(map(repr, CORRIDOR_MODES))}, "
                              f"got {args['corridor']!r}")
    width, position, depth = args["corridor_width"], args["corridor_position"], args["min_room_depth"]
    if not width >= MIN_CORRIDOR_WIDTH - 1e-9:
        raise DerivationError(f"corridor_width must be at least {MIN_CORRIDOR_WIDTH / units:g} "
                              f"({MIN_CORRIDOR_WIDTH:g} m), got {width / units:g}")
    if not 0.0 <= position <= 1.0:
        raise DerivationError(f"corridor_position is a fraction between 0 and 1, got {position:g}")
    if not depth > 0:
        raise DerivationError(f"min_room_depth must be positive, got {depth / units:g}")
    if (args["n_left"] or args["n_right"]) and mode != "spine":
        raise DerivationError("n_left and n_right count rooms along a corridor=\"spine\"")
    # callers of apply() that predate max_room_depth; never below the least depth
    deepest = max(args.get("max_room_depth", math.inf), depth)
    return CorridorSpec(mode, width, position, depth, args["n_left"], args["n_right"],  # type: ignore[arg-type]
                        max_depth=deepest)


def floor_settings(args: dict[str, Any], storey: float, units: float) -> FloorSettings:
    """Floor settings from a floor operation's ``wallWidth``, ``windows``,
    ``window_sill``, ``doorWidth`` and ``doorHeight`` (checked by ``check_values``),
    checked against the storey height (``make_floor``, ``usar_floor``)."""
    count, window_width, window_height = args["windows"]
    settings = FloorSettings(wall_thickness=args["wallWidth"], windows_per_wall=count,
                             window_width=window_width, window_height=window_height,
                             window_sill=args["window_sill"], door_width=args["doorWidth"],
                             door_height=args["doorHeight"])
    clear = storey - settings.slab_thickness
    walls = (f"the walls are {clear / units:g} high (storey {storey / units:g} minus a "
             f"{settings.slab_thickness / units:g} floor slab)")
    if settings.door_height >= clear:
        raise DerivationError(f"doorHeight {settings.door_height / units:g} does not fit: {walls}")
    top = settings.window_sill + window_height
    if count > 0 and top >= clear:
        raise DerivationError(
            f"windows do not fit: sill {settings.window_sill / units:g} + windowHigh "
            f"{window_height / units:g} = {top / units:g}, but {walls}",
            hint="lower windowHigh or window_sill, or make the storeys taller")
    return settings


def _footprint(polygon: Polygon) -> Polygon:
    """The footprint counter-clockwise, without repeated or collinear vertices."""
    if polygon.interiors:
        raise DerivationError("make_floor needs a footprint without holes (courtyards are not supported)")
    clean = orient(polygon.simplify(0.0), sign=1.0)
    if not isinstance(clean, Polygon) or not clean.is_valid or clean.area <= 0:
        raise DerivationError("make_floor needs a simple, non-empty footprint polygon")
    return clean


def _footprint_size(footprint: Polygon) -> str:
    """What the footprint is, for messages about footprints make_floor refuses."""
    minx, minz, maxx, maxz = footprint.bounds
    return (f"the footprint is {maxx - minx:.4g} m x {maxz - minz:.4g} m with "
            f"{len(footprint.exterior.coords) - 1} corners")


def _footprint_hint(footprint: Polygon) -> str:
    """:func:`_footprint_size` and what makes a footprint the partition takes."""
    return (f"{_footprint_size(footprint)}; give the storey a larger lot, without corners "
            "closer than a micrometre")
