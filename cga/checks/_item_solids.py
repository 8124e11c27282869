"""Furniture items as rigid bodies: mass properties and collision shapes, measured once
per model and moved by each item's pose.

An item is its model's convex parts under an affine map ``x ↦ A x + t``
(:func:`cga.meshing.items.item_transform`: a per-axis scale, a turn about +y, a move).
Such a map multiplies every volume by ``|det A|`` and takes each centre of mass ``c`` to
``A c + t``, so the parts' volume-weighted centre of mass, measured once in the model's
frame, gives every item's by one matrix product; no item needs its own mass-property
pass over posed triangles. The body's collision shape, the parts about that centre,
shrunk by :data:`cga.collision.CONTACT_SHRINK` per face (:func:`cga.collision.shrink_part`),
depends on ``A`` only, not on where the item stands: items of one model, size and turn
share one shape, within a build and (through a bounded in-process cache) across builds.

A node without model facts (``ItemInfo.geometry`` None) or whose model is not made of
convex parts (decomposed by V-HACD in world coordinates, :mod:`cga.checks.vhacd`) is
measured in world coordinates as it is, with ``A`` the identity.
"""

from __future__ import annotations

import hashlib
import weakref
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np
import shapely

from cga.collision import collision_parts, shrink_part
from cga.mesh import area_centroid, volume_and_centre
from cga.scene import SceneNode

from ._bullet import obj_text

__all__ = ["ItemShape", "Solid", "item_solid", "item_shape", "measure"]

FOOT = 0.005
"""m: an item stands on its vertices within this height of its lowest point."""

_SHAPE_CACHE = 1024
"""Distinct (model, size, turn) shapes kept in memory between builds."""


@dataclass(frozen=True, eq=False)
class Solid:
    """Convex parts (vertex and face arrays, one frame) and their centre of mass.

    ``centroid`` is the parts' volume-weighted centre of mass, or, when no part encloses
    a volume, the mean of their area centroids. ``volume`` is their total volume (m³).
    ``shared``: the solid is a model's, in the model's frame, shared by its items.
    """

    parts: tuple[tuple[np.ndarray, np.ndarray], ...]
    centroid: np.ndarray
    volume: float
    shared: bool = False


@dataclass(frozen=True)
class ItemShape:
    """A body's collision shape about its centre of mass, and what the check reads of it.

    ``text`` is the shrunk parts as OBJ text (one object per part, the form pybullet
    reads as a compound of convex hulls) and ``name`` a hash of it. ``lowest`` is the
    height of the lowest vertex above the centre of mass (negative); ``support_gap`` the
    plan distance (m) from the centre of mass to the hull of the points the item stands
    on (its vertices within :data:`FOOT` of the lowest), 0 when over it.
    """

    text: str
    name: str
    lowest: float
    support_gap: float


def measure(parts: Sequence[tuple[np.ndarray, np.ndarray]], *, shared: bool = False) -> Solid:
    """The centre of mass and volume of convex parts, by the divergence theorem on each
    part's triangles (:func:`cga.mesh.volume_and_centre`; a part's area centroid stands
    in when it encloses no volume)."""
    arrays = tuple((np.asarray(v, dtype=float), np.asarray(f, dtype=np.int64)) for v, f in parts)
    volumes, centres = [], []
    for vertices, faces in arrays:
        volume, centre = volume_and_centre(vertices[faces])
        volume = max(volume, 0.0)
        if not volume > 0:
            centre = area_centroid(vertices[faces])
        volumes.append(volume)
        centres.append(centre)
    weights = np.array(volumes)
    total = float(weights.sum())
    if not total > 0:
        weights = np.ones(len(arrays))
    centroid = (np.array(centres) * weights[:, None]).sum(axis=0) / weights.sum()
    return Solid(arrays, centroid, total, shared)


_MODEL_SOLIDS: "weakref.WeakKeyDictionary[object, Solid]" = weakref.WeakKeyDictionary()
"""The solid of each loaded model geometry (kept while the geometry is)."""


def item_solid(node: SceneNode,
               cache_dir: Path | None = None) -> tuple[Solid, np.ndarray, np.ndarray]:
    """An item's solid and the affine map ``(A, t)`` that places it.

    A node posed from a model made of convex parts gets the model's solid (measured on
    first use, then shared); any other node its collision parts measured where they are
    (``A`` the identity, ``t`` zero). A model whose parts enclose no volume is measured
    posed too: area centroids do not follow a per-axis scale.
    """
    item = node.item
    geometry = item.geometry if item is not None else None
    if (geometry is not None and item is not None and item.pose is not None
            and node.convex_parts and any(len(f) for f in geometry.faces)):
        solid = _MODEL_SOLIDS.get(geometry)
        if solid is None:
            solid = measure([(v, f) for v, f in zip(geometry.vertices, geometry.faces) if len(f)],
                            shared=True)
            _MODEL_SOLIDS[geometry] = solid
        if solid.volume > 0:
            pose = np.asarray(item.pose, dtype=float)
            return solid, pose[:3, :3], pose[:3, 3]
    parts = collision_parts(node, cache_dir)
    solid = measure([(p.vertices, p.faces) for p in parts])
    return solid, np.eye(3), np.zeros(3)


def item_shape(solid: Solid, linear: np.ndarray) -> ItemShape:
    """The collision shape of ``solid`` mapped by ``linear`` about its centre of mass;
    a model's (shared) solid has its shapes kept in an in-process cache."""
    if solid.shared:
        return _cached_shape(solid, np.ascontiguousarray(linear, dtype=float).tobytes())
    return _shape(solid, linear)


@lru_cache(maxsize=_SHAPE_CACHE)
def _cached_shape(solid: Solid, linear: bytes) -> ItemShape:
    return _shape(solid, np.frombuffer(linear, dtype=float).reshape(3, 3))


def _shape(solid: Solid, linear: np.ndarray) -> ItemShape:
    moved = [((vertices - solid.centroid) @ linear.T, faces) for vertices, faces in solid.parts]
    text = obj_text([_Arrays(shrink_part(v), f) for v, f in moved])
    points = np.concatenate([v for v, _ in moved])
    lowest = float(points[:, 1].min())
    feet = points[points[:, 1] <= lowest + FOOT][:, [0, 2]]
    gap = float(shapely.MultiPoint(feet).convex_hull.distance(shapely.Point(0.0, 0.0)))
    return ItemShape(text, hashlib.sha1(text.encode()).hexdigest(), lowest, gap)


@dataclass(frozen=True)
class _Arrays:
    vertices: np.ndarray
    faces: np.ndarray
