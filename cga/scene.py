"""The Scene: one object with everything a consumer of a build needs.

The evaluator derives a shape tree; :func:`cga.pipeline.build` collects its terminal shapes
into a Scene: the floor plans (rooms, walls, doors, windows, furniture) and any other
terminal geometry (masses and faces of grammars that do not make floors). Exporters and
checks read a Scene and nothing upstream of it.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, TypeVar, cast

from .model import Diagnostic, FloorPlan
from .report import CheckReport
from .shape import Shape

_T = TypeVar("_T")

if TYPE_CHECKING:  # pragma: no cover
    import trimesh

    import numpy as np

    from cga.appearance import Appearance, Light, Material
    from cga.difficulty import DifficultyReport
    from cga.georeference import Georeference
    from cga.operations.furniture.library import ModelGeometry, ModelLibrary

    from .doors import DoorLeaf
    from .mesh import TriangleMesh

__all__ = ["ItemInfo", "MeshArrays", "NodeKind", "Scene", "SceneNode"]

NodeKind = Literal["wall", "slab", "ceiling", "roof", "stair", "rail", "furniture", "mass", "face"]
"""What a scene node is; exporters colour and label by it."""


@dataclass(frozen=True)
class ItemInfo:
    """The facts about a furniture item that the checks and exporters need beside its mesh.

    ``model`` is the model's canonical name and ``model_path`` the OBJ file it was loaded
    from; ``room``, ``name``, ``parent`` and ``rotation`` (quarter turns about +y) come
    from the plan's :class:`~cga.model.FurnitureItem`; ``density`` (kg/m³) from the model
    file and ``mass`` (kg) is the posed parts' volume × density. ``convex_parts`` is False
    when some part of the model is not a closed convex solid (physics then decomposes the
    mesh itself). ``geometry`` is the model's parts in its own frame and ``pose`` the 4×4
    matrix taking them to the item's place (:func:`cga.meshing.items.item_transform`), so
    physics measures each model once and moves the result (None when the node was made
    otherwise).
    """

    model: str
    model_path: Path
    room: int
    name: str
    parent: str | None
    rotation: int
    density: float
    mass: float
    convex_parts: bool
    geometry: "ModelGeometry | None" = field(default=None, compare=False, repr=False)
    pose: "np.ndarray | None" = field(default=None, compare=False, repr=False)

    def labels(self) -> dict[str, Any]:
        """The semantic labels stored with the item's glTF node (JSON values; the model
        file's path is left out, so files do not depend on where models are installed)."""
        return {"model": self.model, "room": self.room, "name": self.name,
                "parent": self.parent, "rotation": self.rotation, "density": self.density,
                "mass": self.mass, "convex_parts": self.convex_parts}


@dataclass(frozen=True, eq=False, slots=True)
class MeshArrays:
    """A triangle mesh as plain arrays: ``vertices`` ``float[n, 3]`` and ``faces``
    ``int[m, 3]`` (indices into ``vertices``, counter-clockwise seen from outside).

    A furniture item's posed parts are kept like this rather than as trimesh objects,
    which cost far more to make than the checks that read them (a house has about a
    thousand parts); a consumer that needs mesh operations builds the trimesh object
    itself. The arrays may be shared with the model library, so treat them as read-only.
    """

    vertices: "np.ndarray"
    faces: "np.ndarray"


@dataclass(frozen=True)
class SceneNode:
    """A named piece of output geometry, in world coordinates (metres, y up).

    ``mesh`` is a :class:`cga.mesh.TriangleMesh` in a build (arrays; trimesh's other
    attributes made on demand), or any :class:`trimesh.Trimesh` a caller builds a node
    from: consumers read only ``vertices``, ``faces`` and ``bounds`` on the hot path.

    ``path`` is the semantic node name, e.g. ``floor1/room3_Kitchen/wall2`` or
    ``floor0/room1_Livingroom/furniture/sofa``; ``kind`` is a :data:`NodeKind`. ``parts``
    are the convex pieces of a furniture item as arrays (:class:`MeshArrays`; physics uses
    them as a compound body); ``static`` bodies do not move.
    ``item`` describes a furniture node (None for every other kind); ``extras`` are the
    labels of the other kinds (wall id, floor, shape path, ...), written to the glTF as
    they are. ``door`` is set on a door leaf: its hinge, angle and collision box
    (:mod:`cga.doors`). ``materials`` are the node's distinct materials and
    ``face_materials`` the index into them of each triangle (:mod:`cga.appearance.dress`;
    empty and None before dressing).
    """

    path: str
    kind: NodeKind
    mesh: "TriangleMesh | trimesh.Trimesh"
    extras: dict[str, Any] = field(default_factory=dict)
    static: bool = True
    parts: tuple[MeshArrays, ...] = ()
    item: ItemInfo | None = None
    door: "DoorLeaf | None" = None
    materials: tuple["Material", ...] = ()
    face_materials: "np.ndarray | None" = field(default=None, compare=False, repr=False)

    @property
    def labels(self) -> dict[str, Any]:
        """Every semantic label of the node: its extras and, for an item, its facts."""
        return {**self.extras, **self.item.labels()} if self.item is not None else self.extras

    @property
    def convex_parts(self) -> bool:
        """Whether ``parts`` are convex solids a physics engine can use as they are."""
        return self.item is None or self.item.convex_parts


@dataclass
class Scene:
    """The result of a build.

    ``terminals`` are the leaves of the shape tree in derivation order; those with a
    ``plan`` are storeys, the rest plain geometry. ``checks`` is filled by the physics
    and navigability checks (check name → report object); ``timings`` maps stage name →
    seconds. ``difficulty`` holds the measured difficulty (:mod:`cga.difficulty`),
    set by the build after the checks. ``library`` is the
    build's furniture model library (the one ``add_furniture`` sized items with); the
    meshing layer poses its models. ``appearance`` says which materials and lights the
    build has (:mod:`cga.appearance`; None: the shipped tables, neutral). :attr:`nodes`
    are the build's meshes, made once, and :attr:`lights` its ceiling lights.
    ``georeference`` places the plan in the world when the lot came from a GeoJSON file.
    """

    name: str
    seed: int
    units: float
    terminals: list[Shape]
    source: Path | None = None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)
    checks: dict[str, CheckReport] = field(default_factory=dict)
    difficulty: "DifficultyReport | None" = None
    library: "ModelLibrary | None" = None
    appearance: "Appearance | None" = None
    georeference: "Georeference | None" = None
    _nodes: tuple[SceneNode, ...] | None = field(default=None, repr=False, compare=False)
    _lights: tuple["Light", ...] | None = field(default=None, repr=False, compare=False)
    _shared: dict[Hashable, Any] = field(default_factory=dict, init=False, repr=False,
                                         compare=False)

    @property
    def nodes(self) -> tuple[SceneNode, ...]:
        """Every mesh of the build (:func:`cga.meshing.scene_nodes`), made on first use and
        kept: the checks and every exporter read these same nodes."""
        if self._nodes is None:
            from .meshing import scene_nodes

            self._nodes = tuple(scene_nodes(self))
        return self._nodes

    def shared(self, key: Hashable, make: Callable[[], _T]) -> _T:
        """``make()``, made on first use under ``key`` and kept: what several exporters
        derive from the finished build alike (the robot formats' world)."""
        if key not in self._shared:
            self._shared[key] = make()
        return cast(_T, self._shared[key])

    @property
    def lights(self) -> tuple["Light", ...]:
        """The ceiling lights of every room (:mod:`cga.appearance.lights`), made on first
        use and kept."""
        if self._lights is None:
            from .appearance import scene_lights

            self._lights = tuple(scene_lights(self.floors, self.looks(), self.seed))
        return self._lights

    def looks(self) -> "Appearance":
        """The build's appearance: ``appearance``, else the shipped tables, neutral."""
        if self.appearance is None:
            from .appearance import shipped_appearance

            return shipped_appearance()
        return self.appearance

    @property
    def floors(self) -> list[FloorPlan]:
        """Floor plans ordered by floor index."""
        plans = [s.plan for s in self.terminals if s.plan is not None]
        return sorted(plans, key=lambda p: p.index)

    @property
    def masses(self) -> list[Shape]:
        """Terminal shapes that are plain geometry (not storeys)."""
        return [s for s in self.terminals if s.plan is None]

    def all_diagnostics(self) -> list[Diagnostic]:
        """Build diagnostics followed by those recorded on each floor plan."""
        out = list(self.diagnostics)
        for plan in self.floors:
            out.extend(plan.diagnostics)
        return out
