"""One ray cast per pixel gives depth, semantic class, instance and shade at once.

The scene's meshes are joined into one triangle soup kept with per-triangle labels
(class, instance, colour, unit normal). Embree (through ``embreex``, the binding trimesh's
``ray_pyembree`` uses) finds the first triangle each ray hits; everything else is a
per-pixel gather from the triangle arrays, vectorised in numpy. Embree works in single
precision (vertices are stored relative to the scene's centre, a few micrometres apart
at building scale), so the hit distance is recomputed in double precision as the
intersection of the ray with the hit triangle's plane: depth is exact to well under a
millimetre (DESIGN §15: "depth and masks exact").

Class per triangle: a node's class (:func:`cga.semantics.node_class`), except that the
downward faces of a slab or of the roof slab are ``ceiling`` (a slab is the floor seen
from above and the ceiling of the storey below), docs/render.md.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import trimesh

from cga.semantics import UNLABELLED, class_id

__all__ = ["Surface", "RayScene", "Hits"]

_CEILING_SIDE = -0.5
"""A slab triangle whose unit normal has y below this faces down: a ceiling."""


@dataclass(frozen=True)
class Surface:
    """One scene node's world-space mesh with its labels and triangle colours (sRGB)."""

    path: str
    kind: str
    mesh: trimesh.Trimesh
    class_id: int
    instance_id: int
    colors: np.ndarray


@dataclass(frozen=True)
class Hits:
    """Per ray: the hit triangle (−1: none) and the ray parameter ``t`` (inf: none)."""

    triangle: np.ndarray
    t: np.ndarray

    @property
    def hit(self) -> np.ndarray:
        return self.triangle >= 0


class RayScene:
    """The joined triangles of some surfaces, ready for ray casting.

    Raises
    ------
    ImportError
        embreex is not installed (``pip install 'cga[render]'``).
    """

    def __init__(self, surfaces: Sequence[Surface]):
        from embreex import rtcore_scene
        from embreex.mesh_construction import TriangleMesh

        vertices, faces, classes, instances, colors = [], [], [], [], []
        offset = 0
        ceiling = class_id("ceiling")
        for surface in surfaces:
            mesh = surface.mesh
            v = np.asarray(mesh.vertices, dtype=np.float64)
            f = np.asarray(mesh.faces, dtype=np.int64)
            if len(f) == 0:
                continue
            normals = _unit_normals(v, f)
            keep = np.any(normals != 0.0, axis=1)  # degenerate triangles cannot be hit
            face_class = np.full(len(f), surface.class_id, dtype=np.uint16)
            if surface.kind in ("slab", "roof", "ceiling"):
                face_class[normals[:, 1] < _CEILING_SIDE] = ceiling
            vertices.append(v)
            faces.append(f[keep] + offset)
            classes.append(face_class[keep])
            instances.append(np.full(int(keep.sum()), surface.instance_id, dtype=np.uint32))
            colors.append(np.asarray(surface.colors, dtype=np.float32)[keep])
            offset += len(v)
        if not faces:
            vertices, faces = [np.zeros((0, 3))], [np.zeros((0, 3), dtype=np.int64)]
            classes, instances = [np.zeros(0, np.uint16)], [np.zeros(0, np.uint32)]
            colors = [np.zeros((0, 3), np.float32)]
        self.vertices = np.concatenate(vertices)
        self.faces = np.concatenate(faces)
        self.face_class = np.concatenate(classes)
        self.face_instance = np.concatenate(instances)
        self.face_color = np.concatenate(colors)
        self.normals = _unit_normals(self.vertices, self.faces)
        # each triangle's plane: n·p = offset (double precision)
        self.offsets = (np.einsum("ij,ij->i", self.vertices[self.faces[:, 0]], self.normals)
                        if len(self.faces) else np.zeros(0))
        self._centre = (self.vertices.min(axis=0) + self.vertices.max(axis=0)) / 2 \
            if len(self.vertices) else np.zeros(3)
        self._embree = None
        if len(self.faces):
            self._embree = rtcore_scene.EmbreeScene()
            TriangleMesh(scene=self._embree,
                         vertices=(self.vertices - self._centre).astype(np.float32),
                         indices=self.faces.astype(np.int32))

    def __len__(self) -> int:
        return len(self.faces)

    def cast(self, origins: np.ndarray, directions: np.ndarray, *,
             common_origin: bool = False) -> Hits:
        """The first triangle each ray meets (both sides of a triangle are hit) and the ray
        parameter of the hit, in units of each ray's own direction length.

        With ``common_origin`` every ray starts at ``origins[0]`` (a perspective camera),
        which saves a per-ray dot product.
        """
        n = len(directions)
        if self._embree is None or n == 0:
            return Hits(np.full(n, -1, dtype=np.int64), np.full(n, np.inf))
        local = (origins[:1] if common_origin else origins) - self._centre
        embree_origins = np.ascontiguousarray(
            np.broadcast_to(local, (n, 3)) if common_origin else local, dtype=np.float32)
        triangle = np.asarray(self._embree.run(
            embree_origins, np.ascontiguousarray(directions, dtype=np.float32)), dtype=np.int64)
        t = np.full(n, np.inf)
        hit = np.flatnonzero(triangle >= 0)
        tri = triangle[hit]
        normal = self.normals[tri]
        denominator = np.einsum("ij,ij->i", directions[hit], normal)
        if common_origin:
            numerator = (self.offsets - self.normals @ origins[0])[tri]
        else:
            numerator = self.offsets[tri] - np.einsum("ij,ij->i", origins[hit], normal)
        ok = np.abs(denominator) > 1e-12
        t[hit[ok]] = numerator[ok] / denominator[ok]
        triangle[hit[~ok]] = -1  # grazing a triangle edge-on: no surface seen there
        return Hits(triangle, t)

    def labels(self, hits: Hits) -> tuple[np.ndarray, np.ndarray]:
        """``(class, instance)`` per ray, 0 where nothing was hit."""
        semantic = np.full(len(hits.triangle), UNLABELLED, dtype=np.uint16)
        instance = np.zeros(len(hits.triangle), dtype=np.uint16)
        hit = hits.hit
        semantic[hit] = self.face_class[hits.triangle[hit]]
        instance[hit] = self.face_instance[hits.triangle[hit]]
        return semantic, instance


def _unit_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Unit normals of triangles by their winding; zero for degenerate ones."""
    if len(faces) == 0:
        return np.zeros((0, 3))
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    normals = np.cross(b - a, c - a)
    length = np.linalg.norm(normals, axis=1)
    ok = length > 1e-14
    normals[ok] /= length[ok, None]
    normals[~ok] = 0.0
    return normals
