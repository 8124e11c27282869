"""The rendered 3D view: a z-buffered picture where near surfaces hide far ones."""

from __future__ import annotations

import io

import numpy as np
import trimesh
from PIL import Image

from cga.export.view import render_view
from cga.scene import Scene, SceneNode


def _box(extents, center, rgb) -> SceneNode:
    mesh = trimesh.creation.box(extents=extents)
    mesh.apply_translation(center)
    mesh.visual.face_colors = [*rgb, 255]
    return SceneNode(path=f"box{rgb}", kind="mass", mesh=mesh)


def _pixels(png: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).reshape(-1, 3)


def _share(pixels: np.ndarray, rgb) -> float:
    """Fraction of pixels whose hue matches ``rgb``'s dominant channel clearly."""
    channel = int(np.argmax(rgb))
    others = [c for c in range(3) if c != channel]
    dominant = pixels[:, channel].astype(int) - pixels[:, others].max(axis=1) > 60
    return float(dominant.mean())


def test_view_draws_the_geometry():
    scene = Scene(name="t", seed=0, units=1.0, terminals=[])
    png = render_view(scene, [_box((2, 2, 2), (0, 1, 0), (220, 30, 30))], width=300)
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    assert _share(_pixels(png), (220, 30, 30)) > 0.05


def test_near_box_hides_the_box_behind_it():
    scene = Scene(name="t", seed=0, units=1.0, terminals=[])
    # Camera looks from +x+z (azimuth 35°): the green box at +x+z is in front of the red one.
    red = _box((1, 1, 1), (0, 0.5, 0), (220, 30, 30))
    green = _box((3, 3, 3), (2.0, 1.5, 2.5), (30, 200, 30))
    alone = _share(_pixels(render_view(scene, [red], width=300)), (220, 30, 30))
    hidden = _share(_pixels(render_view(scene, [red, green], width=300)), (220, 30, 30))
    reversed_order = _share(_pixels(render_view(scene, [green, red], width=300)), (220, 30, 30))
    assert alone > 0.02
    assert hidden < 0.2 * alone  # the red box is (mostly) hidden whatever the draw order
    assert reversed_order == hidden
