"""Collision shapes for Bullet-based consumers: the physics check and the robot exports.

Bullet (pybullet, and simulators that load our URDF/SDF through it) gives every shape a
1 mm collision margin: a shape acts as if inflated by it. An item standing exactly on
the floor, or flush against a wall, would then start 2 mm "deep" in it and the contact
solver would push it about. Shrinking each convex part of an item by
:data:`CONTACT_SHRINK` per face cancels that: with the margins added back the item
touches exactly. Both the check and the exports build item bodies from
:func:`collision_parts` shrunk with :func:`shrink_part`, so what is checked is what is
exported.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    import trimesh

    from cga.scene import SceneNode

__all__ = ["BULLET_MARGIN", "CONTACT_SHRINK", "collision_parts", "shrink_part"]

BULLET_MARGIN = 0.001
"""m: Bullet's collision margin around every shape (convex hulls, triangle meshes)."""

CONTACT_SHRINK = 2 * BULLET_MARGIN
"""m: how far each face of an item's convex parts is moved in; other simulators see
items 2 mm smaller than drawn, well below any placement tolerance."""


def shrink_part(vertices: np.ndarray, by: float = CONTACT_SHRINK) -> np.ndarray:
    """A convex part's vertices scaled about its box centre so each axis-aligned face
    moves in by ``by`` (exact for box parts; a part thinner than four times ``by`` keeps
    at least half its size)."""
    vertices = np.asarray(vertices, dtype=float)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    centre, extent = (lo + hi) / 2, hi - lo
    scale = np.maximum(extent - 2 * by, extent / 2) / np.maximum(extent, 1e-12)
    return (vertices - centre) * scale + centre


def collision_parts(node: "SceneNode", cache_dir: Path | None = None) -> list["trimesh.Trimesh"]:
    """An item's convex collision parts: its model's parts, or a V-HACD decomposition
    (cached on disk, :mod:`cga.checks.vhacd`) when it has none or its model says they
    are not convex (``ItemInfo.convex_parts`` False, e.g. a user's single-group OBJ)."""
    parts = [p for p in node.parts if len(p.faces)]
    if parts and node.convex_parts:
        return parts
    from cga.checks.vhacd import convex_decomposition  # pybullet only when needed

    return list(convex_decomposition(node.mesh, cache=cache_dir))
