"""Convex decomposition (V-HACD) of user models that are not made of convex parts, cached.

Shipped furniture models are built from convex parts, which physics uses directly. A
user's own model may be one concave mesh (an L-shaped desk, a chair as one surface);
the physics check then needs convex pieces that cover it. pybullet ships V-HACD
(Mamou and Ghorbel 2009), which takes a few tenths of a second per mesh, so results are
kept on disk, keyed by a hash of the mesh, and reused by every later build.

V-HACD voxelises the mesh, so its hulls stick out of the surface by up to one voxel
(about 1 cm on a 1 m model), more than the 5 mm the physics check tolerates. Each hull
is therefore intersected with the original solid (or, when the mesh is not watertight,
with its bounding box) and replaced by the convex hull of that intersection.

Cache: ``$CGA_CACHE_DIR/vhacd`` when ``CGA_CACHE_DIR`` is set, else
``~/.cache/cga/vhacd``; one OBJ file per mesh (one object per hull), written atomically,
safe to delete at any time.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from pathlib import Path

import numpy as np
import trimesh

from cga.cache import cache_root
from cga.fsutil import atomic_write
from cga.manifold import manifold3d

from ._bullet import obj_objects, obj_text, pybullet, quiet_output
from ._solids import as_manifold, as_mesh

__all__ = ["VHACD_PARAMETERS", "cache_dir", "cache_key", "convex_decomposition"]

VHACD_PARAMETERS: dict[str, float | int] = {
    "resolution": 100_000,
    "concavity": 0.0025,
    "maxNumVerticesPerCH": 64,
    "minVolumePerCH": 0.0001,
}
"""Keyword arguments given to ``pybullet.vhacd`` (part of the cache key)."""

_FORMAT = "cga-vhacd-1"
"""Version of the cache format and post-processing; part of the cache key."""

_DECIMALS = 6
"""Vertices are rounded to a micrometre before hashing, so a model placed anywhere
(translated) hashes the same."""


def cache_dir() -> Path:
    """The folder holding decompositions: ``$CGA_CACHE_DIR/vhacd`` or ``~/.cache/cga/vhacd``."""
    return cache_root() / "vhacd"


def cache_key(mesh: trimesh.Trimesh) -> str:
    """SHA-256 of the mesh (moved so its bounding box is centred on the origin) and the
    V-HACD parameters; equal for two placements of a model that differ by a translation."""
    vertices, _ = _centred(mesh)
    digest = hashlib.sha256()
    digest.update(_FORMAT.encode())
    digest.update(repr(sorted(VHACD_PARAMETERS.items())).encode())
    digest.update(np.ascontiguousarray(vertices, dtype="<f8").tobytes())
    digest.update(np.ascontiguousarray(mesh.faces, dtype="<i8").tobytes())
    return digest.hexdigest()


def convex_decomposition(mesh: trimesh.Trimesh, *,
                         cache: Path | None = None) -> tuple[trimesh.Trimesh, ...]:
    """Convex pieces covering ``mesh``, in the mesh's own coordinates.

    Parameters
    ----------
    mesh
        A triangle mesh (world or model coordinates).
    cache
        Folder of cached decompositions; :func:`cache_dir` when omitted.

    Returns
    -------
    tuple of trimesh.Trimesh
        Convex hulls. A mesh that is already a closed convex solid is returned as is,
        without running V-HACD.

    Raises
    ------
    ValueError
        ``mesh`` has no faces, or V-HACD produced no hull for it.

    Notes
    -----
    A cache miss runs V-HACD (about 0.2 s for a furniture-sized mesh at the default
    resolution); a hit reads one small file.
    """
    if len(mesh.faces) == 0:
        raise ValueError("cannot decompose a mesh without faces")
    if mesh.is_watertight and mesh.is_convex:
        return (mesh,)
    vertices, centre = _centred(mesh)
    folder = cache if cache is not None else cache_dir()
    path = folder / f"{cache_key(mesh)}.obj"
    if path.is_file():
        hulls = obj_objects(path.read_text(encoding="utf-8"))
    else:
        local = trimesh.Trimesh(vertices=vertices, faces=mesh.faces, process=False)
        hulls = _decompose(local)
        atomic_write(path, obj_text([trimesh.convex.convex_hull(h) for h in hulls]))
    pieces = tuple(trimesh.convex.convex_hull(h + centre) for h in hulls)
    if not pieces:
        raise ValueError("V-HACD produced no convex hull for the mesh")
    return pieces


def _centred(mesh: trimesh.Trimesh) -> tuple[np.ndarray, np.ndarray]:
    """The mesh's vertices moved so its bounding box is centred on the origin (rounded),
    and the centre that was removed."""
    lo, hi = mesh.bounds
    centre = (lo + hi) / 2
    return np.round(np.asarray(mesh.vertices) - centre, _DECIMALS), centre


def _decompose(mesh: trimesh.Trimesh) -> list[np.ndarray]:
    """Run V-HACD on ``mesh`` and clip each hull to the mesh; vertex arrays of the hulls."""
    pb = pybullet()
    with tempfile.TemporaryDirectory(prefix="cga-vhacd-") as tmp:
        source, target, log = (os.path.join(tmp, n) for n in ("in.obj", "out.obj", "log.txt"))
        Path(source).write_text(obj_text([mesh]), encoding="utf-8")
        with quiet_output():
            pb.vhacd(source, target, log, **VHACD_PARAMETERS)
        raw = obj_objects(Path(target).read_text(encoding="utf-8")) if os.path.isfile(target) else []
    bound = as_manifold(mesh)
    if bound is None:
        lo, hi = mesh.bounds
        bound = manifold3d.Manifold.cube(tuple(hi - lo)).translate(tuple(lo))
    hulls = []
    for points in raw:
        if len(points) < 4:
            continue
        clipped = manifold3d.Manifold.hull_points(points.astype(np.float64)) ^ bound
        if clipped.is_empty() or clipped.volume() <= 0:
            continue
        hulls.append(np.asarray(as_mesh(clipped.hull()).vertices))
    return hulls
