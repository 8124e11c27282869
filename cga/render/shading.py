"""The colour image: the scene's surface colours lit by a headlight and a sun.

:func:`surface_colors` and :func:`node_colors` are the one place the renderer reads a
surface's colour: a glb primitive's material, or a scene node's materials
(:mod:`cga.appearance`).
:class:`Shader` is Lambertian with two lights and no shadows: a headlight at the camera
(every visible surface is lit, as by a robot's lamp) and a sun from above, plus ambient
light. It is a readable picture for people and detectors, not a photoreal one.
"""

from __future__ import annotations

import numpy as np
import trimesh

from cga.export.palette import face_colors, node_face_colors
from cga.scene import SceneNode

from .raycast import Hits, RayScene

__all__ = ["surface_colors", "node_colors", "Shader", "SKY"]

SKY = np.array([0.80, 0.86, 0.93])
"""Colour of a pixel whose ray leaves the building (through a window or from above)."""

_SUN = np.array([0.35, 0.85, 0.4]) / np.linalg.norm([0.35, 0.85, 0.4])
_AMBIENT, _HEADLIGHT, _SUNLIGHT = 0.3, 0.55, 0.25


def surface_colors(mesh: trimesh.Trimesh, kind: str) -> np.ndarray:
    """``float[faces, 3]`` sRGB base colour of each triangle of a node's mesh: the mesh's
    own colours (a furniture model's, a glb material's), else its kind's
    (:func:`cga.export.palette.face_colors`)."""
    return face_colors(mesh, kind)


def node_colors(node: SceneNode) -> np.ndarray:
    """``float[faces, 3]`` sRGB base colour of each triangle of a scene node: its
    materials' when it is dressed (:func:`cga.export.palette.node_face_colors`)."""
    return node_face_colors(node)


class Shader:
    """Colours rays that hit a :class:`RayScene`.

    The ambient and sun terms depend on the triangle only and are computed once per
    triangle; per pixel there is only the headlight's ``|n·d|``.
    """

    def __init__(self, rays: RayScene):
        sun = np.abs(rays.normals @ _SUN)  # both sides lit: open meshes show their backs
        base = rays.face_color * 255.0
        self._lit = (base * (_AMBIENT + _SUNLIGHT * sun)[:, None]).astype(np.float32)
        self._headlit = (base * _HEADLIGHT).astype(np.float32)
        self._normals = rays.normals.astype(np.float32)

    def __call__(self, hits: Hits, directions: np.ndarray) -> np.ndarray:
        """``uint8[n, 3]`` colour of each ray: its triangle's colour, lit; :data:`SKY`
        where nothing was hit."""
        out = np.empty((len(hits.triangle), 3), dtype=np.float32)
        out[:] = SKY * 255.0
        hit = np.flatnonzero(hits.hit)
        tri = hits.triangle[hit]
        view = directions[hit].astype(np.float32)
        facing = np.abs(np.einsum("ij,ij->i", self._normals[tri], view))
        facing /= np.sqrt(np.einsum("ij,ij->i", view, view))
        out[hit] = self._lit[tri] + self._headlit[tri] * facing[:, None]
        np.minimum(out, 255.0, out=out)
        return (out + 0.5).astype(np.uint8)
