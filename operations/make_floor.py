"""``make_floor(split, wallWidth, numWindows>windowWidth>windowHigh, doorWidth, doorHeight)``.

Partitions a storey into rooms (docs/architecture.md, "Floor plans", thesis §5.1): the
floor slice's footprint is cut by a randomised BSP over a half-edge structure into
``split + 1`` rooms, outer walls get their windows, and the shape passes on unchanged with a
:class:`cga.model.FloorPlan` attached. Doors come later (``type_rooms``), and the 3D
walls and slabs are made from the final plan at meshing time
(:func:`cga.meshing.solids.floor_nodes`).
"""

from __future__ import annotations

from typing import Any

from shapely.geometry import Polygon
from shapely.geometry.polygon import orient

from cga.errors import DerivationError
from cga.model import Diagnostic, FloorSettings
from cga.randomness import stream
from cga.shape import Mass, Shape

from cga.operation import Child, Operation, OperationContext, Param, is_number
from .floorplan.assemble import plan_from_dcel
from .floorplan.bsp import partition
from .floorplan.layout import LayoutRecipe
from .floorplan.treemap import thesis_partition
from .floorplan.circulation import (CORRIDOR_MODES, CirculationError, CorridorSpec,
                                    circulation_faces)
from .floorplan.errors import PartitionError
from .floorplan.tiling import tile_with_fixed_faces
from .roomtyping.doors import DOOR_MARGIN

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
        Param("n_left", "count", default=0, keyword_only=True,
              doc="spine: rooms of equal width on the low side (0: the BSP decides)"),
        Param("n_right", "count", default=0, keyword_only=True,
              doc="spine: rooms of equal width on the high side (0: the BSP decides)"),
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
        try:
            fixed = circulation_faces(ring, spec)
        except CirculationError as error:
            raise DerivationError(f"make_floor cannot carve a {spec.mode} corridor: {error}",
                                  hint=_footprint_hint(footprint)) from None
        # Rooms besides the circulation: split + 1; fixed rooms and free pieces count.
        cuts = split
        if fixed:
            pieces = tile_with_fixed_faces(ring, [f.polygon for f in fixed])[1]
            cuts = max(0, split + 1 - pieces - sum(not f.circulation for f in fixed))
        door_reach = settings.door_width + 2 * (DOOR_MARGIN + settings.wall_thickness)
        thesis = (lo, hi) == (0.5, 0.5)
        if thesis and fixed:
            raise DerivationError("the thesis' partition (cut_range = (0.5, 0.5)) has no "
                                  "corridors; use another cut_range with corridor")
        try:
            if thesis:
                result = thesis_partition(ring, split)
            else:
                result = partition(ring, cuts, rng, min_width=min_width, min_area=min_area,
                                   cut_range=(lo, hi), fixed=fixed, min_contact=door_reach)
        except PartitionError as error:
            raise DerivationError(f"make_floor cannot cut this footprint into rooms: {error}",
                                  hint=_footprint_hint(footprint)) from None
        if result.shortfall is not None:
            ctx.report(Diagnostic("warning", "make_floor",
                                  f"made {len(result.dcel.faces)} rooms instead of {split + 1}: "
                                  f"{result.shortfall}", floor=index))
        try:
            plan = plan_from_dcel(result.dcel, settings=settings, index=index,
                                  elevation=mass.base, height=mass.height,
                                  circulation=result.circulation)
        except PartitionError as error:
            raise DerivationError(f"the floor is too narrow for its walls: {error}") from None
        if not thesis:  # the thesis' partition is the same every time: nothing to re-draw
            plan = plan.with_changes(layout=LayoutRecipe(
                tuple(ring), split + 1, tuple(fixed), min_width, min_area, door_reach, settings,
                index, mass.base, mass.height, ctx.seed,
                ("make_floor", shape.symbol) if args["same_layout"] else ("make_floor", *shape.path)))
        return [Child(successor=0, geometry=mass, scope=shape.scope, plan=plan)]


def _corridor(args: dict[str, Any], units: float) -> CorridorSpec:
    """The corridor options, checked (docs/architecture.md, "Floor plans")."""
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
    return CorridorSpec(mode, width, position, depth, args["n_left"], args["n_right"])  # type: ignore[arg-type]


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


def _footprint_hint(footprint: Polygon) -> str:
    """What the footprint is, for messages about footprints the partition refuses."""
    minx, minz, maxx, maxz = footprint.bounds
    return (f"the footprint is {maxx - minx:.4g} m x {maxz - minz:.4g} m with "
            f"{len(footprint.exterior.coords) - 1} corners; give the storey a larger lot, "
            f"without corners closer than a micrometre")
