"""The shipped OBJ models follow docs/models.md: metres, y up, front toward −z, origin at the
centre of the footprint on the floor, realistic sizes, closed convex parts.

The files are read here with a plain OBJ reader, not with the model library, so these
checks do not depend on the code that loads models for the pipeline.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from cga.resources import shipped_dir

MODELS_DIR = shipped_dir("cga.furniture_models")

REQUIRED = (
    "bed", "doublebed", "nightstand", "wardrobe", "dresser", "desk", "officechair", "chair",
    "diningtable", "tablebig", "sofa", "armchair", "sofatable", "tvboard", "bookshelf",
    "floorlamp", "rug", "kitchencounter", "fridge", "stove", "sink", "toilet", "bathtub",
    "shower", "washbasin", "washingmachine", "shelf", "plant", "door", "window",
)

# Realistic (min, max) extents in metres: width x, height y, depth z (front toward -z).
SIZE_RANGES = {
    "bed": ((0.8, 1.1), (0.6, 1.1), (1.9, 2.2)),
    "doublebed": ((1.4, 2.0), (0.6, 1.2), (1.9, 2.2)),
    "nightstand": ((0.35, 0.6), (0.4, 0.7), (0.3, 0.5)),
    "wardrobe": ((0.8, 2.0), (1.8, 2.4), (0.5, 0.7)),
    "dresser": ((0.8, 1.6), (0.7, 1.1), (0.4, 0.6)),
    "desk": ((1.0, 1.8), (0.7, 0.8), (0.55, 0.85)),
    "officechair": ((0.5, 0.75), (0.9, 1.3), (0.5, 0.75)),
    "chair": ((0.38, 0.55), (0.8, 1.05), (0.4, 0.6)),
    "diningtable": ((1.2, 2.0), (0.72, 0.78), (0.75, 1.0)),
    "tablebig": ((1.8, 2.6), (0.72, 0.78), (0.9, 1.2)),
    "sofa": ((1.6, 2.4), (0.75, 1.0), (0.8, 1.0)),
    "armchair": ((0.7, 1.0), (0.75, 1.0), (0.7, 1.0)),
    "sofatable": ((0.8, 1.4), (0.35, 0.5), (0.5, 0.8)),
    "tvboard": ((1.2, 2.0), (0.4, 1.5), (0.35, 0.5)),
    "bookshelf": ((0.6, 1.0), (1.6, 2.2), (0.25, 0.4)),
    "floorlamp": ((0.25, 0.5), (1.5, 1.9), (0.25, 0.5)),
    "rug": ((1.2, 3.0), (0.005, 0.03), (0.8, 2.5)),
    "kitchencounter": ((0.6, 1.8), (0.85, 0.95), (0.55, 0.7)),
    "fridge": ((0.5, 0.75), (1.4, 2.0), (0.55, 0.75)),
    "stove": ((0.5, 0.9), (0.85, 0.95), (0.55, 0.7)),
    "sink": ((0.6, 1.2), (0.85, 1.3), (0.55, 0.7)),
    "toilet": ((0.35, 0.45), (0.7, 0.85), (0.55, 0.75)),
    "bathtub": ((1.5, 1.9), (0.45, 0.9), (0.7, 0.85)),
    "shower": ((0.8, 1.0), (1.9, 2.3), (0.8, 1.0)),
    "washbasin": ((0.45, 0.7), (0.8, 1.2), (0.35, 0.55)),
    "washingmachine": ((0.55, 0.65), (0.8, 0.9), (0.5, 0.7)),
    "shelf": ((0.5, 1.2), (0.6, 2.0), (0.25, 0.45)),
    "plant": ((0.3, 0.9), (0.6, 1.6), (0.3, 0.9)),
    "door": ((0.8, 1.0), (2.0, 2.2), (0.03, 0.2)),
    "window": ((1.199, 1.201), (1.199, 1.201), (0.059, 0.061)),
}

# Items whose tallest part (backrest, headboard, cistern, tap) stands at the back (+z).
TALL_AT_BACK = ("chair", "officechair", "sofa", "armchair", "bed", "doublebed", "toilet",
                "washbasin", "sink", "bathtub")
# Cabinets and appliances whose doors, drawers and handles stand out at the front (-z), so
# their body (the largest part) lies behind the centre of the footprint.
FRONTS_AT_FRONT = ("wardrobe", "dresser", "nightstand", "kitchencounter", "fridge", "stove",
                   "washingmachine", "tvboard")


def read_obj(path: Path) -> tuple[dict[str, str], list[trimesh.Trimesh], list[np.ndarray]]:
    """Header comments, one mesh per ``g`` group and the vertex colours of each group."""
    header: dict[str, str] = {}
    vertices: list[list[float]] = []
    groups: list[tuple[int, list[list[int]]]] = []
    for line in path.read_text(encoding="utf-8").splitlines():
        key, _, rest = line.partition(" ")
        if key == "#":
            name, _, value = rest.partition(" ")
            header[name] = value
        elif key == "g":
            groups.append((len(vertices), []))
        elif key == "v":
            vertices.append([float(x) for x in rest.split()])
        elif key == "f":
            groups[-1][1].append([int(i) - 1 for i in rest.split()])
    table = np.array(vertices)
    meshes, colors = [], []
    for start, faces in groups:
        f = np.array(faces)
        used = np.unique(f)
        assert used.min() >= start, "a group uses vertices of an earlier group"
        meshes.append(trimesh.Trimesh(table[used, :3], np.searchsorted(used, f), process=False))
        colors.append(table[used, 3:])
    return header, meshes, colors


@pytest.fixture(scope="module")
def models() -> dict[str, tuple[dict[str, str], list[trimesh.Trimesh], list[np.ndarray]]]:
    return {p.stem: read_obj(p) for p in sorted(MODELS_DIR.glob("*.obj"))}


def bounds(meshes: list[trimesh.Trimesh]) -> np.ndarray:
    return np.array([np.min([m.bounds[0] for m in meshes], axis=0),
                     np.max([m.bounds[1] for m in meshes], axis=0)])


def test_every_required_model_is_shipped_with_a_lowercase_name(models):
    assert set(REQUIRED) <= set(models)
    assert all(name == name.lower() and name.isalnum() for name in models)


@pytest.mark.parametrize("name", REQUIRED)
def test_model_is_on_the_floor_and_centred(models, name):
    _, meshes, _ = models[name]
    lo, hi = bounds(meshes)
    assert lo[1] == 0.0
    assert abs(lo[0] + hi[0]) / 2 < 1e-3
    assert abs(lo[2] + hi[2]) / 2 < 1e-3


@pytest.mark.parametrize("name", REQUIRED)
def test_model_has_a_realistic_size_in_metres(models, name):
    _, meshes, _ = models[name]
    lo, hi = bounds(meshes)
    for axis, (extent, (low, high)) in enumerate(zip(hi - lo, SIZE_RANGES[name])):
        assert low <= extent <= high, f"{name}: extent along axis {axis} is {extent:.3f} m"


@pytest.mark.parametrize("name", REQUIRED)
def test_every_part_is_a_closed_convex_solid(models, name):
    _, meshes, _ = models[name]
    assert len(meshes) >= 1
    for index, part in enumerate(meshes):
        assert part.is_watertight, f"{name} part_{index} is open"
        assert part.volume > 0, f"{name} part_{index} is inside out"
        hull = part.convex_hull.volume
        assert part.volume == pytest.approx(hull, rel=1e-3), f"{name} part_{index} is concave"


@pytest.mark.parametrize("name", REQUIRED)
def test_model_declares_density_and_colours(models, name):
    header, meshes, colors = models[name]
    density = float(header["density"])
    mass = density * sum(m.volume for m in meshes)
    assert 1.0 <= mass <= 150.0, f"{name} weighs {mass:.1f} kg"
    main = [float(c) for c in header["color"].split()]
    assert len(main) == 3 and all(0 <= c <= 1 for c in main)
    for rgb in colors:
        assert rgb.shape[1] == 3 and np.all((rgb >= 0) & (rgb <= 1))
        assert np.all(rgb == rgb[0]), "each part has one colour"


@pytest.mark.parametrize("name", TALL_AT_BACK)
def test_tallest_part_stands_at_the_back(models, name):
    _, meshes, _ = models[name]
    tallest = max(meshes, key=lambda m: m.bounds[1][1])
    assert tallest.bounds.mean(axis=0)[2] > 0.02


@pytest.mark.parametrize("name", FRONTS_AT_FRONT)
def test_fronts_and_handles_face_minus_z(models, name):
    _, meshes, _ = models[name]
    body = max(meshes, key=lambda m: m.volume)
    assert body.bounds.mean(axis=0)[2] > 0.005
    lo, _ = bounds(meshes)
    assert body.bounds[0][2] > lo[2] + 0.01, "something stands out in front of the body"


@pytest.mark.parametrize("name, seat_range", [("chair", (0.4, 0.5)),
                                              ("officechair", (0.4, 0.55))])
def test_seat_height(models, name, seat_range):
    _, meshes, _ = models[name]
    seat = max(meshes, key=lambda m: np.prod(m.extents[[0, 2]]))
    assert seat_range[0] <= seat.bounds[1][1] <= seat_range[1]


@pytest.mark.parametrize("name", ["chair", "diningtable", "tablebig", "desk", "sofatable"])
def test_stands_on_four_legs(models, name):
    _, meshes, _ = models[name]
    feet = [m for m in meshes if m.bounds[0][1] == 0.0]
    assert len(feet) == 4
    assert all(m.extents[1] > 0.3 for m in feet)


def test_door_leaf_with_handles_on_both_faces(models):
    _, meshes, _ = models["door"]
    leaf = max(meshes, key=lambda m: m.volume)
    assert leaf.extents == pytest.approx((0.9, 2.1, 0.04), abs=1e-6)
    others = [m for m in meshes if m is not leaf]
    assert any(m.bounds[0][2] >= leaf.bounds[1][2] - 1e-9 for m in others)
    assert any(m.bounds[1][2] <= leaf.bounds[0][2] + 1e-9 for m in others)
    assert all(0.9 <= m.bounds.mean(axis=0)[1] <= 1.2 for m in others), "handles at ~1 m"


def test_window_is_a_frame_around_panes(models):
    _, meshes, colors = models["window"]
    lo, hi = bounds(meshes)
    assert lo == pytest.approx((-0.6, 0.0, -0.03))
    assert hi == pytest.approx((0.6, 1.2, 0.03))
    assert len({tuple(c[0]) for c in colors}) == 2, "frame and glass differ in colour"


def test_bed_headboard_and_mattress(models):
    _, meshes, _ = models["bed"]
    headboard = max(meshes, key=lambda m: m.bounds[1][1])
    lo, hi = bounds(meshes)
    assert headboard.bounds[1][2] == pytest.approx(hi[2])
    assert headboard.extents[0] == pytest.approx(hi[0] - lo[0])
