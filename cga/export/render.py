"""``<name>.render/``: camera views and top-down maps for perception training (docs/render.md).

The build's own scene is rendered (:mod:`cga.render`) with the default
:class:`~cga.render.placement.RenderOptions`; ``cga render FILE.scene.json`` renders a
finished build with other options.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from cga.scene import Scene, SceneNode

__all__ = ["export_render"]


def export_render(scene: Scene, nodes: Sequence[SceneNode], out_dir: Path, name: str) -> list[Path]:
    """Write ``<out_dir>/<name>.render/`` (views, maps, ``index.json``)."""
    # imported here: the renderer uses cga.export's JSON and number helpers
    from cga.render import RenderOptions, inputs_from_scene, write_render

    return write_render(inputs_from_scene(scene, list(nodes)), RenderOptions(), Path(out_dir), name)
