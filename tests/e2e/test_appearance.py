"""Appearance end to end: materials on every primitive, per seed and the same for the
same seed, restrictions kept, lights in every room, three office lights at sixths.

The checks read the written files (the glb's JSON chunk, the scene JSON, the material
table with the csv module) rather than the code that made them.
"""

from __future__ import annotations

import colorsys
import csv
import json
import struct
from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

from cga.appearance import shipped_appearance
from cga.appearance.dress import dress_nodes
from cga.pipeline import build

ROOT = Path(__file__).resolve().parents[2]
DEMOS = ROOT / "demos"


def _gltf(path: Path) -> dict:
    data = path.read_bytes()
    length = struct.unpack_from("<I", data, 12)[0]
    assert data[16:20] == b"JSON"
    return json.loads(data[20:20 + length])


def _table() -> dict[str, dict[str, str]]:
    with (ROOT / "rules" / "materials.csv").open(encoding="utf-8") as handle:
        rows = [r for r in csv.reader(handle, delimiter=";") if r and not r[0].startswith("#")]
    return {r[0]: dict(zip(rows[0], r)) for r in rows[1:]}


def _names(cell: str) -> set[str]:
    return {n.strip().lower() for n in cell.split(";") if n.strip()}


@pytest.fixture(scope="module")
def house(tmp_path_factory):
    out = tmp_path_factory.mktemp("house")
    scene = build(DEMOS / "house.grammar", seed=3, out_dir=out, formats=["glb", "json"],
                  physics=False, quiet=True, materials="random")
    return scene, out


def test_every_primitive_has_a_pbr_material(house):
    _, out = house
    document = _gltf(out / "house.glb")
    primitives = [p for m in document["meshes"] for p in m["primitives"]]
    assert all("material" in p for p in primitives)
    materials = document["materials"]
    for material in materials:
        pbr = material["pbrMetallicRoughness"]
        assert len(pbr["baseColorFactor"]) == 4
        assert 0 <= pbr.get("roughnessFactor", 1) <= 1
    glass = [m for m in materials if m["name"].startswith("glass_")]
    assert glass and all(m["alphaMode"] == "BLEND" for m in glass)
    # furniture is coloured by materials, not by vertex colours a renderer may ignore
    assert not any("COLOR_0" in p["attributes"] for p in primitives)


def test_the_same_seed_gives_the_same_bytes(house, tmp_path):
    _, out = house
    build(DEMOS / "house.grammar", seed=3, out_dir=tmp_path, formats=["glb"], physics=False,
          quiet=True, materials="random")
    assert (tmp_path / "house.glb").read_bytes() == (out / "house.glb").read_bytes()


def test_every_room_has_a_light_node_and_a_punctual_light(house):
    _, out = house
    document = _gltf(out / "house.glb")
    scene_doc = json.loads((out / "house.scene.json").read_text())
    lights = document["extensions"]["KHR_lights_punctual"]["lights"]
    assert "KHR_lights_punctual" in document["extensionsUsed"]
    nodes = {n["name"]: n for n in document["nodes"]}
    lit = set()
    for node in document["nodes"]:
        reference = node.get("extensions", {}).get("KHR_lights_punctual")
        if reference is not None:
            light = lights[reference["light"]]
            assert light["type"] == "point" and light["intensity"] > 0
            lit.add((node["extras"]["floor"], node["extras"]["room"]))
    rooms = {(r["floor"], r["id"]) for r in scene_doc["rooms"]}
    assert rooms and rooms <= lit
    assert len(scene_doc["lights"]) == len(lights)
    assert all(entry["name"] in nodes for entry in scene_doc["lights"])


def test_an_office_gets_its_three_lights_at_sixths(tmp_path):
    build(DEMOS / "office.grammar", seed=1, out_dir=tmp_path, formats=["json"], physics=False,
          quiet=True)
    document = json.loads((tmp_path / "office.scene.json").read_text())
    offices = [r for r in document["rooms"] if r["type"] == "Office"]
    assert offices
    checked = 0
    for room in offices:
        interior = Polygon(room["interior"]["exterior"])
        rect = interior.minimum_rotated_rectangle
        if abs(rect.area - interior.area) > 1e-6:
            continue  # not a rectangle
        corners = np.asarray(rect.exterior.coords)[:4]
        edges = [corners[1] - corners[0], corners[2] - corners[1]]
        long_edge = max(edges, key=np.linalg.norm)
        length = float(np.linalg.norm(long_edge))
        axis = long_edge / length
        ours = [light for light in document["lights"]
                if (light["floor"], light["room"]) == (room["floor"], room["id"])]
        assert len(ours) == 3
        along = sorted(float(np.dot([l["position"][0], l["position"][2]], axis)) for l in ours)
        start = float(np.min(np.asarray(interior.exterior.coords) @ axis))
        assert np.allclose(np.array(along) - start, [length / 6, length / 2, 5 * length / 6],
                           atol=1e-6)
        checked += 1
    assert checked > 0


def test_over_100_seeds_materials_vary_repeat_and_keep_their_targets(house):
    scene, _ = house
    table = _table()
    looks = shipped_appearance("random")
    library = scene.library
    nodes = scene.nodes
    floors = {plan.index: plan for plan in scene.floors}
    wood_hues = [colorsys.rgb_to_hsv(*(int(r["Color"][i:i + 2], 16) / 255 for i in (1, 3, 5)))[0]
                 for r in table.values() if r["Surface"] == "wood"]
    signatures = set()
    for seed in range(100):
        dressed = dress_nodes(nodes, scene.floors, looks.palette(seed), library)
        signature = tuple(m.name for n in dressed for m in n.materials)
        signatures.add(signature)
        if seed < 3:  # the same seed again: the same materials
            again = dress_nodes(nodes, scene.floors, looks.palette(seed), library)
            assert tuple(m.name for n in again for m in n.materials) == signature
        for node in dressed:
            index = np.asarray(node.face_materials)
            assert len(index) == len(node.mesh.faces) and index.max() < len(node.materials)
            if node.kind == "furniture":
                model = library.get(node.item.model)
                parts = np.repeat(model.part_names, [len(p.faces) for p in model.parts])
                for k, material in enumerate(node.materials):
                    row = table[material.row]
                    for part in set(parts[index == k]):
                        assert row["Surface"] == part.split("_")[-1], (node.path, part)
                        assert not _names(row["Models"]) or node.item.model in _names(row["Models"])
                        assert not _names(row["Parts"]) or part in _names(row["Parts"])
                    if row["Surface"] == "wood":
                        hue = colorsys.rgb_to_hsv(*material.color)[0]
                        assert min(wood_hues) - 2e-3 <= hue <= max(wood_hues) + 2e-3
            if node.kind == "slab":
                plan = floors[int(node.path.split("/")[0][5:])]
                centres = node.mesh.triangles_center
                for k, material in enumerate(node.materials):
                    rooms = _names(table[material.row]["Rooms"])
                    if not rooms:
                        continue
                    for c in centres[index == k]:
                        [room] = [r for r in plan.rooms
                                  if shapely.contains_xy(r.interior, c[0], c[2])]
                        assert (room.type or "").lower() in rooms
    assert len(signatures) == 100


def _with_variable(tmp_path: Path, line: str) -> Path:
    text = (DEMOS / "massing.grammar").read_text()
    grammar = tmp_path / "look.grammar"
    grammar.write_text(text.replace("Variables:\n", f"Variables:\n  {line}\n", 1))
    return grammar


def test_the_grammar_variable_switches_materials_and_the_option_wins(tmp_path):
    grammar = _with_variable(tmp_path, 'materials = "random";')
    scene = build(grammar, seed=2, formats=[], physics=False, quiet=True)
    assert scene.looks().mode == "random"
    assert build(grammar, seed=2, formats=[], physics=False, quiet=True,
                 materials="neutral").looks().mode == "neutral"


def test_a_bad_material_mode_is_a_usage_error(tmp_path):
    from cga.errors import UsageError

    grammar = _with_variable(tmp_path, 'materials = "loud";')
    with pytest.raises(UsageError, match="'materials' must be one of neutral, random"):
        build(grammar, seed=2, formats=[], physics=False, quiet=True)
    with pytest.raises(UsageError, match="--materials"):
        build(DEMOS / "massing.grammar", formats=[], physics=False, quiet=True, materials="x")
