"""V-HACD decompositions: hulls cover the mesh without sticking out, and are cached."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from scipy.spatial import Delaunay

from cga.checks import vhacd


def _l_shape() -> trimesh.Trimesh:
    bar = trimesh.creation.box(extents=(1.0, 0.2, 1.0))
    post = trimesh.creation.box(extents=(0.2, 1.0, 1.0))
    post.apply_translation((0.4, 0.5, 0.0))
    return trimesh.boolean.union([bar, post], engine="manifold")


def test_cache_dir_follows_the_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("CGA_CACHE_DIR", str(tmp_path))
    assert vhacd.cache_dir() == tmp_path / "vhacd"
    monkeypatch.delenv("CGA_CACHE_DIR")
    assert vhacd.cache_dir().parts[-3:] == (".cache", "cga", "vhacd")


def test_key_ignores_translation_but_not_shape():
    mesh = _l_shape()
    moved = mesh.copy().apply_translation((3.25, 0.5, -7.125))
    turned = mesh.copy().apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, (0, 1, 0)))
    assert vhacd.cache_key(mesh) == vhacd.cache_key(moved)
    assert vhacd.cache_key(mesh) != vhacd.cache_key(turned)


def test_convex_mesh_is_returned_unchanged(tmp_path):
    box = trimesh.creation.box(extents=(1, 2, 3))
    assert vhacd.convex_decomposition(box, cache=tmp_path) == (box,)
    assert not list(tmp_path.iterdir())


def test_hulls_are_convex_cover_the_mesh_and_stay_inside_its_bounds(tmp_path):
    mesh = _l_shape().apply_translation((5.0, 0.0, 2.0))
    hulls = vhacd.convex_decomposition(mesh, cache=tmp_path)
    assert len(hulls) >= 2
    assert all(h.is_convex and h.is_watertight for h in hulls)
    lo, hi = mesh.bounds
    for hull in hulls:
        assert np.all(hull.bounds[0] >= lo - 1e-6) and np.all(hull.bounds[1] <= hi + 1e-6)
    # The L is covered: a lattice of points inside its two boxes lies in the hulls.
    axis = np.linspace(0.02, 0.98, 9)
    bar = np.stack(np.meshgrid(axis - 0.5, axis * 0.2 - 0.1, axis - 0.5), -1).reshape(-1, 3)
    post = np.stack(np.meshgrid(axis * 0.2 + 0.3, axis * 0.9 + 0.1, axis - 0.5), -1).reshape(-1, 3)
    points = np.concatenate([bar, post]) + (5.0, 0.0, 2.0)
    covered = np.zeros(len(points), dtype=bool)
    for hull in hulls:
        covered |= Delaunay(hull.vertices).find_simplex(points) >= 0
    assert covered.mean() > 0.95


def test_second_decomposition_reads_the_cache(tmp_path, monkeypatch):
    mesh = _l_shape()
    first = vhacd.convex_decomposition(mesh, cache=tmp_path)
    files = list(tmp_path.glob("*.obj"))
    assert [f.stem for f in files] == [vhacd.cache_key(mesh)]

    def fail(_mesh):
        raise AssertionError("V-HACD ran although the decomposition was cached")

    monkeypatch.setattr(vhacd, "_decompose", fail)
    moved = mesh.copy().apply_translation((1.0, 2.0, 3.0))
    second = vhacd.convex_decomposition(moved, cache=tmp_path)
    assert len(second) == len(first)
    for a, b in zip(first, second):
        assert np.allclose(a.bounds + (1.0, 2.0, 3.0), b.bounds, atol=1e-5)


def test_empty_mesh_is_rejected(tmp_path):
    with pytest.raises(ValueError, match="without faces"):
        vhacd.convex_decomposition(trimesh.Trimesh(), cache=tmp_path)
