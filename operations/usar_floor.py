"""``usar_floor(difficulty, catalogue, wallWidth, doorWidth, doorHeight)``.

The UvA adaptive map generator (Zwennes 2011; DESIGN §13; docs/difficulty.md) as a
floor operation: the storey's rectangular footprint is cut into a grid of hallway-wide
cells (``cell``, default 2.4 m), laid out by the paper's five difficulty-driven rules
(:mod:`.usar.generator`) and assembled into a typed floor with doorways
(:mod:`.usar.plan`). The rooms come from a catalogue CSV (:mod:`.usar.catalogue`, the
paper's 20 rooms shipped as ``usar_rooms.csv``) whose ``Furniture`` column names the
room type of a furniture table, so ``add_furniture("furniture_usar.csv", ...)``
furnishes the floor next. ``difficulty`` is usually a grammar variable, set from the
command line with ``--set difficulty=7``.
"""

from __future__ import annotations

import math
from typing import Any

from cga.errors import DerivationError
from cga.operation import CheckContext, Child, Operation, OperationContext, Param, is_number
from cga.shape import Mass, Shape

from .make_floor import floor_settings
from .usar.catalogue import CatalogueRoom, load_catalogue

__all__ = ["MAX_GRID_CELLS", "MIN_CELL", "UsarFloor"]

MAX_GRID_CELLS = 40
"""Most cells along one side of the grid (the plan's walls grow with the square of the
regions)."""

MIN_CELL = 1.2
"""Least cell size (m): a hallway a robot and a person pass in."""


class UsarFloor(Operation):
    """Storey → the same storey with a UvA grid floor, typed, with doorways."""

    name = "usar_floor"
    params = (
        Param("difficulty", "number", doc="d in [0, 10]: drives spacing, rooms, doorways, cycles"),
        Param("catalogue", "path", doc="room catalogue CSV (Name;Width;Depth;Difficulty;Furniture)"),
        Param("wallWidth", "length", doc="wall thickness"),
        Param("doorWidth", "length", doc="doorway width"),
        Param("doorHeight", "length", doc="doorway height"),
        Param("cell", "length", default=2.4, keyword_only=True,
              doc="grid cell: the hallway width (m; the footprint is divided into whole cells)"),
        Param("windows", "tuple", items=("count", "length", "length"), default=(0, 1.2, 1.2),
              keyword_only=True, doc="numWindows>windowWidth>windowHigh per outer wall segment"),
        Param("window_sill", "length", default=0.9, keyword_only=True,
              doc="height of the window bottoms above the floor (m)"),
    )
    doc = ('usar_floor(difficulty, "usar_rooms.csv", wallWidth, doorWidth, doorHeight, '
           'cell=2.4): the UvA adaptive map generator on a grid of hallway-wide cells')

    def check_values(self, args: dict[str, Any], units: float) -> None:
        d = args["difficulty"]
        if is_number(d) and not 0 <= d <= 10:
            raise DerivationError(f"difficulty must be a number from 0 to 10, got {d:g}")
        for name in ("wallWidth", "doorWidth", "doorHeight"):
            value = args[name]
            if is_number(value) and not value > 0:
                raise DerivationError(f"usar_floor {name} must be positive, got {value / units:g}")
        cell, wall = args["cell"], args["wallWidth"]
        if is_number(cell) and not cell >= MIN_CELL - 1e-9:
            raise DerivationError(f"cell must be at least {MIN_CELL / units:g} "
                                  f"({MIN_CELL:g} m), got {cell / units:g}")
        door = args["doorWidth"]
        if is_number(cell) and is_number(wall) and is_number(door) and \
                door + wall + 0.2 > cell:
            raise DerivationError(
                f"a {door / units:g} wide doorway does not fit a cell of {cell / units:g} "
                f"with walls {wall / units:g} thick", hint="widen cell or narrow doorWidth")

    def check_files(self, args: dict[str, Any], ctx: CheckContext) -> None:
        if isinstance(args["catalogue"], str):
            _catalogue(ctx.resolve(args["catalogue"], "rules"), ctx.cache)

    def apply(self, shape: Shape, args: dict[str, Any], ctx: OperationContext) -> list[Child]:
        self.check_values(args, ctx.units)
        mass = shape.geometry
        if not isinstance(mass, Mass) or mass.height <= 0:
            raise DerivationError(
                "usar_floor works on a storey (a mass with height), not on this shape",
                hint='cut the body into storeys first: repeated_split("y", floorHeight){...}')
        minx, minz, maxx, maxz = mass.footprint.bounds
        if abs(mass.footprint.area - (maxx - minx) * (maxz - minz)) > 1e-6:
            raise DerivationError("usar_floor needs an axis-aligned rectangular footprint "
                                  "(the paper's grid)")
        cell = args["cell"]
        columns, rows = math.floor((maxx - minx) / cell + 1e-9), math.floor((maxz - minz) / cell + 1e-9)
        if min(columns, rows) < 4 or max(columns, rows) > MAX_GRID_CELLS:
            raise DerivationError(
                f"the footprint is {maxx - minx:.4g} m x {maxz - minz:.4g} m: {columns} x {rows} "
                f"cells of {cell:g} m; usar_floor needs 4 to {MAX_GRID_CELLS} cells per side",
                hint="change the lot or the cell size")
        from .usar.generator import generate  # with networkx: not needed by `cga check`
        from .usar.plan import plan_from_layout

        settings = floor_settings(args, mass.height, ctx.units)
        catalogue = _catalogue(ctx.resolve(args["catalogue"], "rules"), ctx.cache)
        layout = generate(columns, rows, float(args["difficulty"]), catalogue, ctx.rng)
        plan = plan_from_layout(layout, (minx, minz), ((maxx - minx) / columns, (maxz - minz) / rows),
                                settings, ctx.rng, index=int(shape.attrs.get("floor", 0)),
                                elevation=mass.base, height=mass.height)
        return [Child(successor=0, geometry=mass, scope=shape.scope, plan=plan)]


def _catalogue(path: Any, cache: dict[str, Any]) -> tuple[CatalogueRoom, ...]:
    """Parse each catalogue once per build."""
    key = f"usar_floor:{path}"
    if key not in cache:
        cache[key] = load_catalogue(path)
    return cache[key]
