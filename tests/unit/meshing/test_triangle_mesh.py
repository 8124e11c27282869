"""cga.mesh: the build's array meshes answer what trimesh answers, with the same floats.

trimesh is the independent reference here: every measure is compared with the one
trimesh computes on the same arrays, over many random meshes and solids.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st
from trimesh.triangles import mass_properties

from cga.mesh import (TriangleMesh, area_centroid, as_trimesh, is_watertight, transform_points,
                      volume_and_centre)

seeds = st.integers(min_value=0, max_value=2**32 - 1)


def random_soup(seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Random vertices and faces, some faces degenerate, some vertices unused."""
    rng = np.random.default_rng(seed)
    vertices = rng.normal(size=(int(rng.integers(4, 40)), 3)) * rng.uniform(0.01, 10)
    faces = rng.integers(0, len(vertices) - 1, size=(int(rng.integers(1, 60)), 3))
    faces[: int(rng.integers(0, 3))] = [0, 0, 1]  # zero-area triangles
    return vertices, faces


def random_solid(seed: int) -> trimesh.Trimesh:
    """A closed solid: a box, a sphere or a capsule, scaled, turned and moved."""
    rng = np.random.default_rng(seed)
    maker = [trimesh.creation.box, trimesh.creation.icosphere, trimesh.creation.capsule][seed % 3]
    solid = maker()
    matrix = trimesh.transformations.random_rotation_matrix(rng.random(3))
    matrix[:3, :3] *= rng.uniform(0.1, 4.0)
    matrix[:3, 3] = rng.normal(size=3) * 5
    solid.apply_transform(matrix)
    return solid


@settings(max_examples=100, deadline=None)
@given(seeds)
def test_measures_match_trimesh(seed):
    vertices, faces = random_soup(seed)
    ours, theirs = TriangleMesh(vertices, faces), trimesh.Trimesh(vertices, faces, process=False)
    assert np.array_equal(ours.bounds, theirs.bounds)
    assert np.array_equal(ours.extents, theirs.extents)
    assert np.array_equal(ours.face_normals, theirs.face_normals)
    assert np.array_equal(ours.triangles_center, theirs.triangles_center)
    assert np.array_equal(ours.triangles, theirs.triangles)
    assert ours.is_watertight == theirs.is_watertight
    assert np.array_equal(area_centroid(ours.triangles), theirs.centroid)


@settings(max_examples=60, deadline=None)
@given(seeds)
def test_solid_volume_centre_and_closure_match_trimesh(seed):
    solid = random_solid(seed)
    props = mass_properties(solid.triangles, skip_inertia=True)
    volume, centre = volume_and_centre(solid.triangles)
    assert volume == float(props.volume)
    assert np.array_equal(centre, props.center_mass)
    assert is_watertight(solid.faces) and solid.is_watertight
    assert not is_watertight(solid.faces[1:])  # one triangle missing opens three edges


@settings(max_examples=100, deadline=None)
@given(seeds)
def test_transform_points_is_trimesh_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(int(rng.integers(0, 30)), 3)) * 10
    matrix = np.eye(4)
    if seed % 4:  # every fourth case: the identity, which trimesh returns unchanged
        matrix[:3, :3] = rng.normal(size=(3, 3))
        matrix[:3, 3] = rng.normal(size=3)
    expected = trimesh.transform_points(points, matrix)
    assert np.array_equal(transform_points(points, matrix), expected)


def test_other_attributes_come_from_a_trimesh_made_once():
    box = trimesh.creation.box(extents=(1.0, 2.0, 3.0))
    colors = np.tile(np.array([[10, 20, 30, 255]], dtype=np.uint8), (len(box.vertices), 1))
    mesh = TriangleMesh(box.vertices, box.faces, colors)
    assert mesh.volume == pytest.approx(6.0)
    assert mesh.contains([[0.0, 0.0, 0.0]]).tolist() == [True]
    assert as_trimesh(mesh) is mesh.as_trimesh() is as_trimesh(mesh)
    assert np.array_equal(as_trimesh(mesh).visual.vertex_colors, colors)
    assert as_trimesh(box) is box
    with pytest.raises(AttributeError):
        mesh.__array_interface__  # noqa: B018 (dunder lookups are never delegated)


def test_empty_mesh_has_no_bounds():
    mesh = TriangleMesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64))
    assert mesh.is_empty and not mesh.is_watertight
    with pytest.raises(ValueError, match="empty"):
        mesh.bounds  # noqa: B018


def test_a_build_with_its_checks_and_plans_imports_no_trimesh_or_scipy_spatial(tmp_path):
    """The meshing layer, the checks, the scene JSON and the plans work on arrays: a
    whole build (checks on) loads neither trimesh nor SciPy's spatial package (the
    cost of issue 21's start-up figures)."""
    code = (
        "import sys\n"
        "from pathlib import Path\n"
        "from cga.pipeline import build\n"
        "from cga.export.scene_json import export_scene_json\n"
        "from cga.export.plan import export_plans\n"
        "scene = build('demos/house.grammar', seed=3)\n"
        "nodes = scene.nodes\n"
        f"out = Path({str(tmp_path)!r})\n"
        "export_scene_json(scene, nodes, out, 'house')\n"
        "export_plans(scene, nodes, out, 'house')\n"
        "loaded = sorted(m for m in sys.modules if m.split('.')[0] == 'trimesh'"
        " or m.startswith('scipy.spatial'))\n"
        "print(loaded)\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            cwd=_root(), check=True)
    assert result.stdout.strip().splitlines()[-1] == "[]", result.stdout


def _root() -> str:
    from pathlib import Path

    return str(Path(__file__).resolve().parents[3])
