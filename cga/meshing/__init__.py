"""The meshing layer: the only place where the build's plans and shapes become meshes.

Operations produce data (shapes, floor plans); :func:`scene_nodes` turns a
:class:`~cga.scene.Scene` into named world-space meshes (:class:`~cga.scene.SceneNode`)
once per build, through :attr:`Scene.nodes <cga.scene.Scene.nodes>`. Checks and exporters
read those nodes and never mesh again (docs/architecture.md, "Meshing").

* :mod:`.shapes`: terminal masses and faces of massing grammars;
* :mod:`.solids`: a storey's walls (openings cut), floor slab and roof slab;
* :mod:`.stairs`: the stair leaving a storey and the rail of the stairwell arriving on it;
* :mod:`.items`: furniture items, their library models posed in the world.

The storey modules are imported only when a scene has floors, so massing builds never
load manifold3d or the model library.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from cga.model import Diagnostic
from cga.scene import Scene, SceneNode

from .shapes import face_mesh, footprint_mesh, mass_mesh, shape_node

if TYPE_CHECKING:  # pragma: no cover
    from cga.operations.furniture.library import ModelLibrary

    from .facades import StoreyCutter

__all__ = ["face_mesh", "footprint_mesh", "mass_mesh", "scene_nodes", "shape_node"]


def scene_nodes(scene: Scene, library: "ModelLibrary | None" = None) -> list[SceneNode]:
    """Every mesh of the build, in derivation order.

    Use :attr:`Scene.nodes <cga.scene.Scene.nodes>`, which calls this once per scene.

    Parameters
    ----------
    scene:
        The build's scene.
    library:
        Furniture models; default: ``scene.library`` (the models ``add_furniture``
        placed), else the grammar's folders, then the shipped models.

    Returns
    -------
    list of SceneNode
        Masses and faces named by shape path (fitted to the storeys with interiors:
        their rooms and openings cut out, :mod:`.facades`); for each storey its floor solids
        (walls, slab, roof), its stair and stairwell rail, then its furniture; every
        node dressed with its materials (:mod:`cga.appearance.dress`).
    """
    from cga.appearance.dress import dress_nodes

    nodes: list[SceneNode] = []
    cutters = None
    for shape in scene.terminals:
        if shape.plan is None:
            if cutters is None:  # massing builds (no floors) never load manifold3d
                cutters = _storey_cutters(scene)
            node = _fitted(shape_node(shape), cutters, scene)
            if node is not None:
                nodes.append(node)
            continue
        from .items import item_node
        from .solids import floor_nodes
        from .stairs import stair_nodes

        library = library or scene.library or _grammar_library(scene)
        nodes.extend(floor_nodes(shape.plan))
        nodes.extend(stair_nodes(shape.plan))
        nodes.extend(item_node(item, shape.plan, library) for item in shape.plan.furniture)
    return dress_nodes(nodes, scene.floors, scene.looks().palette(scene.seed), library)


def _storey_cutters(scene: Scene) -> "list[StoreyCutter]":
    if not scene.floors:
        return []
    from .facades import storey_cutters

    return storey_cutters(scene.floors)


def _fitted(node: SceneNode, cutters: "list[StoreyCutter]", scene: Scene) -> SceneNode | None:
    """A mass or face with the storeys' rooms and openings cut out (:mod:`.facades`); a
    piece left with nothing is dropped, with a diagnostic."""
    if not cutters:
        return node
    from .facades import fit_facade

    fitted = fit_facade(node, cutters)
    if fitted is None:
        scene.diagnostics.append(Diagnostic(
            "warning", "meshing", f"{node.path} left out: it lies wholly inside the rooms or "
            f"the door and window openings of a storey with an interior"))
    return fitted


def _grammar_library(scene: Scene) -> "ModelLibrary":
    """The models of a scene built without a library: the grammar's folders, then the
    shipped models."""
    from cga.operations.furniture.library import default_library, grammar_model_dirs

    return default_library(grammar_model_dirs(scene.source) if scene.source is not None else [])
