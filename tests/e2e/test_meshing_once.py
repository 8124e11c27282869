"""One build meshes its scene once and loads each model once: the checks and every
exporter read ``scene.nodes`` (docs/architecture.md, "Meshing")."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import pytest

import cga.meshing
import cga.meshing.items
import cga.meshing.shapes
import cga.meshing.solids
from cga.export import EXPORTERS, missing_packages
from cga.operations.furniture import library as library_module
from cga.pipeline import build

DEMOS = Path(__file__).resolve().parents[2] / "demos"
FORMATS = tuple(f for f in EXPORTERS if not missing_packages([f]))
"""Every format this environment can write (USD needs usd-core)."""


@pytest.fixture
def counted(monkeypatch):
    """Counts of every meshing entry point, model-library creation and model-file parse
    during the test (the process-wide parse cache emptied first)."""
    calls: Counter[str] = Counter()
    parsed: Counter[Path] = Counter()

    def counting(module, name):
        original = getattr(module, name)

        def wrapper(*args, **kwargs):
            calls[name] += 1
            return original(*args, **kwargs)

        monkeypatch.setattr(module, name, wrapper)

    counting(cga.meshing, "scene_nodes")
    counting(cga.meshing, "shape_node")
    counting(cga.meshing.solids, "floor_nodes")
    counting(cga.meshing.items, "item_node")
    original_load = library_module.load_model

    def load(path):
        parsed[Path(path).resolve()] += 1
        return original_load(path)

    monkeypatch.setattr(library_module, "load_model", load)
    monkeypatch.setattr(library_module, "_PARSED", {})
    original_init = library_module.ModelLibrary.__init__

    def init(self, *args, **kwargs):
        calls["ModelLibrary"] += 1
        original_init(self, *args, **kwargs)

    monkeypatch.setattr(library_module.ModelLibrary, "__init__", init)
    return calls, parsed


def test_a_furnished_build_meshes_once_and_loads_each_model_once(counted, tmp_path):
    calls, parsed = counted
    scene = build(DEMOS / "house.grammar", seed=1, out_dir=tmp_path, formats=FORMATS,
                  quiet=True)
    items = sum(len(plan.furniture) for plan in scene.floors)
    models = {item.model for plan in scene.floors for item in plan.furniture}
    assert scene.checks["physics"] and scene.checks["navigability"]
    assert calls["scene_nodes"] == 1
    assert calls["floor_nodes"] == len(scene.floors) == 2
    assert calls["item_node"] == items > 20
    assert calls["ModelLibrary"] == 1
    assert parsed and max(parsed.values()) == 1
    assert {scene.library.get(m).path.resolve() for m in models} <= set(parsed)
    assert scene.nodes is scene.nodes and calls["scene_nodes"] == 1


def test_a_massing_build_meshes_each_shape_once_and_loads_no_model(counted, tmp_path):
    calls, parsed = counted
    scene = build(DEMOS / "massing.grammar", seed=0, out_dir=tmp_path,
                  formats=FORMATS, quiet=True)
    assert calls["scene_nodes"] == 1
    assert calls["shape_node"] == len(scene.terminals) > 1
    assert calls["floor_nodes"] == calls["item_node"] == 0
    assert not parsed
