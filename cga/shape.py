"""Shapes of the derivation tree: a scope, a geometry and attributes.

All geometry is stored in metres in the world frame of docs/architecture.md ("Units and
frames"): ``y`` is up and floor plans live in the x–z plane (2D plan coordinates are
``(x, z)``). The grammar's ``units`` only matter at the boundary: the evaluator converts
length arguments to metres and reports scope attributes back in grammar units.

Shapes are immutable: an operation returns new shapes and never edits its input.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Literal, Mapping

import numpy as np
from shapely.geometry import Polygon

if TYPE_CHECKING:  # pragma: no cover - import for type hints only
    from .model import FloorPlan

__all__ = ["FaceKind", "Scope", "Mass", "Face", "Geometry", "Shape"]


FaceKind = Literal["side", "top", "bottom"]
"""Which face of a mass a face shape is."""

@dataclass(frozen=True)
class Scope:
    """An oriented box: ``origin`` (3,), ``axes`` rows are the unit x, y, z axes, ``size`` (3,).

    Masses keep world-aligned scopes; faces from ``component_split`` get a scope whose
    x axis runs along the face and whose z axis is the outward normal (CGA convention).
    """

    origin: tuple[float, float, float]
    axes: tuple[tuple[float, float, float], ...] = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    size: tuple[float, float, float] = (0.0, 0.0, 0.0)

    @property
    def sx(self) -> float:
        return self.size[0]

    @property
    def sy(self) -> float:
        return self.size[1]

    @property
    def sz(self) -> float:
        return self.size[2]


@dataclass(frozen=True)
class Mass:
    """A vertical prism: a footprint polygon in the x–z plane, a base height and a height.

    The lot is a mass of height 0. ``extrude`` gives it height; splits along x/z cut the
    footprint, splits along y cut the height.
    """

    footprint: Polygon
    base: float = 0.0
    height: float = 0.0

    def scope(self) -> Scope:
        minx, minz, maxx, maxz = self.footprint.bounds
        return Scope(origin=(minx, self.base, minz), size=(maxx - minx, self.height, maxz - minz))


@dataclass(frozen=True)
class Face:
    """A planar polygon in 3D (from ``component_split``): vertices (N, 3), counter-clockwise
    seen from outside, so the right-hand normal points outward."""

    vertices: tuple[tuple[float, float, float], ...]
    kind: FaceKind

    def normal(self) -> np.ndarray:
        pts = np.asarray(self.vertices, dtype=float)
        n = np.zeros(3)
        for a, b in zip(pts, np.roll(pts, -1, axis=0)):  # Newell's method
            n += np.cross(a, b)
        length = np.linalg.norm(n)
        return n / length if length > 0 else n


Geometry = Mass | Face


@dataclass(frozen=True)
class Shape:
    """A node of the shape tree.

    ``path`` names the node from the root, e.g. ``("Lot", "Body", "Floor[1]")``; it names
    the glTF node and seeds the shape's random stream, so it must not depend on anything
    but the rules that lead to the shape. ``attrs`` holds ``floor`` and ``index``;
    ``plan`` is set once ``make_floor`` has partitioned the shape into rooms.
    """

    symbol: str
    path: tuple[str, ...]
    scope: Scope
    geometry: Geometry
    attrs: Mapping[str, Any] = field(default_factory=dict)
    plan: "FloorPlan | None" = None

    def derive(self, **changes: Any) -> "Shape":
        """A copy with some fields changed (operations never mutate shapes)."""
        return replace(self, **changes)

    @property
    def path_name(self) -> str:
        return "/".join(self.path)
