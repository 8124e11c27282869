"""End to end: every grammar in ``demos/`` builds out of the box, and its files make sense.

The demos are found by globbing ``demos/*.grammar``, so a new demo is covered without
touching this file. Each is built in-process without physics (the physics and
navigability checks run once, on the house), and one is built through the command line
in a subprocess. The assertions read the written files (scene JSON, glb, plans), not the
in-memory objects, and check them with shapely, networkx and trimesh rather than with
the code that made them.
"""

from __future__ import annotations

import io
import json
import subprocess
import sys
from pathlib import Path

import networkx as nx
import numpy as np
import pytest
import trimesh
from shapely import union_all
from shapely.geometry import Polygon, box

from glb_nodes import mesh_node_names

from cga.pipeline import build
from cga.export import DEFAULT_FORMATS

ROOT = Path(__file__).resolve().parents[2]
DEMOS = sorted((ROOT / "demos").glob("*.grammar"))
OUTSIDE = -1
TOLERANCE = 1e-6  # m; JSON coordinates are rounded to the micrometre


def test_the_demos_are_there():
    names = {path.stem for path in DEMOS}
    assert {"house", "apartment", "office", "seed_compat", "massing"} <= names


def _polygon(data: dict) -> Polygon:
    return Polygon(data["exterior"], data["holes"])


def _footprint(item: dict) -> Polygon:
    """An item's plan rectangle from its axis-aligned bbox (items turn in quarter turns)."""
    (x0, _, z0), (x1, _, z1) = item["bbox"]["min"], item["bbox"]["max"]
    return box(x0, z0, x1, z1)


def _by_floor(rows: list[dict], floor: int) -> list[dict]:
    return [row for row in rows if row["floor"] == floor]


@pytest.fixture(scope="module", params=DEMOS, ids=lambda path: path.stem)
def built(request, tmp_path_factory):
    """(scene JSON, output folder, grammar name) of a build at seed 0 without physics."""
    demo: Path = request.param
    out = tmp_path_factory.mktemp(demo.stem)
    build(demo, seed=0, out_dir=out, formats=DEFAULT_FORMATS, physics=False, quiet=True)
    data = json.loads((out / f"{demo.stem}.scene.json").read_text(encoding="utf-8"))
    return data, out, demo.stem


def test_files_are_written(built):
    data, out, name = built
    assert data["name"] == name and data["seed"] == 0
    for floor in data["floors"]:
        assert (out / f"{name}.floor{floor['index']}.svg").stat().st_size > 0
        assert (out / f"{name}.floor{floor['index']}.png").stat().st_size > 0
    assert not [d for d in data["diagnostics"] if d["level"] == "error"]


def test_glb_loads_and_holds_every_node(built):
    data, out, name = built
    scene = trimesh.load(io.BytesIO((out / f"{name}.glb").read_bytes()), file_type="glb")
    names = mesh_node_names(out / f"{name}.glb")
    assert len(names) == len(data["nodes"]) > 0
    assert {item["node"] for item in data["furniture"]} <= names
    low, high = scene.bounds
    assert np.all(np.isfinite([low, high])) and np.all(high > low)
    if data["floors"]:
        # everything stands on the lot, between the ground and the top of the last storey
        # or of the massing above it (a parapet)
        x0, z0 = np.min([_polygon(f["footprint"]).bounds[:2] for f in data["floors"]], axis=0)
        x1, z1 = np.max([_polygon(f["footprint"]).bounds[2:] for f in data["floors"]], axis=0)
        top = max([f["elevation"] + f["height"] for f in data["floors"]]
                  + [n["bbox"]["max"][1] for n in data["nodes"] if n["kind"] in ("mass", "face")])
        assert low[0] >= x0 - TOLERANCE and low[2] >= z0 - TOLERANCE
        assert high[0] <= x1 + TOLERANCE and high[2] <= z1 + TOLERANCE
        assert low[1] >= -TOLERANCE and high[1] <= top + TOLERANCE


def _floor_grammar(data: dict) -> None:
    if not data["floors"]:
        pytest.skip("a massing grammar: no floor plans")


def test_every_floor_is_partitioned_and_typed(built):
    data, _, _ = built
    _floor_grammar(data)
    for floor in data["floors"]:
        rooms = _by_floor(data["rooms"], floor["index"])
        assert len(rooms) > 1
        assert all(isinstance(r["type"], str) and r["type"] for r in rooms)
        # the rooms tile the floor: their polygons cover the footprint without overlap
        footprint = _polygon(floor["footprint"])
        polygons = [_polygon(r["polygon"]) for r in rooms]
        assert sum(p.area for p in polygons) == pytest.approx(footprint.area, rel=1e-6)
        assert footprint.symmetric_difference(union_all(polygons)).area < 1e-4


def test_doors_connect_every_room(built):
    data, _, _ = built
    _floor_grammar(data)
    for floor in data["floors"]:
        index = floor["index"]
        doors = _by_floor(data["doors"], index)
        graph = nx.Graph(tuple(d["rooms"]) for d in doors)
        graph.add_nodes_from(r["id"] for r in _by_floor(data["rooms"], index))
        fronts = [d for d in doors if d["front"]]
        if index == 0:
            assert len(fronts) == 1 and OUTSIDE in fronts[0]["rooms"]
        else:
            assert not fronts and OUTSIDE not in graph
        assert nx.is_connected(graph), f"floor {index}: rooms cut off from the others"


def test_furniture_is_placed_inside_rooms_without_overlaps(built):
    data, _, _ = built
    _floor_grammar(data)
    for floor in data["floors"]:
        index = floor["index"]
        interiors = {r["id"]: _polygon(r["interior"]) for r in _by_floor(data["rooms"], index)}
        solid = [i for i in _by_floor(data["furniture"], index) if not i["is_detail"]]
        assert solid, f"floor {index} has no furniture"
        for item in solid:
            assert interiors[item["room"]].buffer(TOLERANCE).contains(_footprint(item)), item["node"]
        blocking = [i for i in solid if not i["non_collision"]]
        for k, a in enumerate(blocking):
            for b in blocking[k + 1:]:
                overlap = _footprint(a).intersection(_footprint(b)).area
                # the JSON rounds positions and sizes to 1e-6 m: items that touch may
                # overlap on paper by that much times their side (a few 1e-6 m²)
                assert overlap < 1e-5, f"{a['node']} overlaps {b['node']} by {overlap:.4f} m²"


@pytest.mark.physics
def test_house_passes_its_checks(tmp_path):
    scene = build(ROOT / "demos" / "house.grammar", seed=0, out_dir=tmp_path, formats=("json",),
                  quiet=True)
    data = json.loads((tmp_path / "house.scene.json").read_text(encoding="utf-8"))
    physics, reach = data["checks"]["physics"], data["checks"]["navigability"]
    solid = [i for i in data["furniture"] if not i["is_detail"] and not i["non_collision"]]
    assert physics["item_count"] == len(solid) > 0
    assert physics["max_penetration_m"] <= 0.005 and physics["passed"]
    assert reach["passed"] and all(f["passed"] for f in reach["floors"])
    assert scene.timings["physics"] > 0


def test_cli_builds_a_demo_and_prints_its_summary(tmp_path):
    demo = ROOT / "demos" / "apartment.grammar"
    result = subprocess.run(
        [sys.executable, "-m", "cga", "build", str(demo), "--seed", "1", "--no-physics",
         "--out", str(tmp_path / "out")], cwd=tmp_path, capture_output=True, text=True,
        timeout=300)
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr
    summary = result.stdout
    assert "apartment" in summary and "floor 0" in summary
    assert "Livingroom" in summary and "derive" in summary and "add_furniture" in summary
    assert (tmp_path / "out" / "apartment.glb").stat().st_size > 0
