"""The on-disk cache of parsed models: a hit gives the same model without parsing, a
changed file is parsed again, a damaged or deleted entry costs only a parse."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cga.operations.furniture import library
from cga.operations.furniture.library import load_model
from cga.resources import shipped_dir

SHIPPED = shipped_dir("cga.furniture_models")


@pytest.fixture
def cache(tmp_path, monkeypatch) -> Path:
    folder = tmp_path / "cache"
    monkeypatch.setenv("CGA_CACHE_DIR", str(folder))
    return folder / "models"


def _no_parsing(monkeypatch):
    def refuse(path, text):
        raise AssertionError(f"{path} was parsed although it is in the cache")
    monkeypatch.setattr(library, "_parse_geometry", refuse)


def _same(a, b) -> None:
    assert (a.name, a.size, a.density, a.color, a.convex_parts) == \
        (b.name, b.size, b.density, b.color, b.convex_parts)
    assert a.volume == b.volume
    assert len(a.parts) == len(b.parts)
    for p, q in zip(a.parts, b.parts):
        assert np.array_equal(p.vertices, q.vertices) and np.array_equal(p.faces, q.faces)
        assert np.array_equal(p.visual.vertex_colors, q.visual.vertex_colors)
    assert np.array_equal(a.mesh.vertices, b.mesh.vertices)


@pytest.mark.parametrize("name", ["chair", "sofa", "doublebed", "door"])
def test_a_cached_model_equals_the_parsed_one(cache, monkeypatch, name):
    parsed = load_model(SHIPPED / f"{name}.obj")
    assert len(list(cache.glob("*.npz"))) == 1
    _no_parsing(monkeypatch)
    _same(load_model(SHIPPED / f"{name}.obj"), parsed)


def test_a_changed_file_is_parsed_again(cache, monkeypatch, tmp_path):
    path = tmp_path / "crate.obj"
    path.write_text((SHIPPED / "chair.obj").read_text().replace("density 465", "density 700"))
    assert load_model(path).density == 700
    path.write_text((SHIPPED / "chair.obj").read_text())
    assert load_model(path).density == 465
    assert len(list(cache.glob("*.npz"))) == 2


def test_a_damaged_entry_is_parsed_again_and_rewritten(cache):
    parsed = load_model(SHIPPED / "chair.obj")
    (entry,) = cache.glob("*.npz")
    entry.write_bytes(entry.read_bytes()[:100])
    _same(load_model(SHIPPED / "chair.obj"), parsed)
    assert library._from_cache(entry.read_bytes()) is not None


def test_a_file_without_vertex_colours_round_trips(cache, monkeypatch, tmp_path):
    path = tmp_path / "crate.obj"
    corners = [(x, y, z) for x in (-0.5, 0.5) for y in (0, 1) for z in (-0.5, 0.5)]
    faces = [(1, 2, 4), (1, 4, 3), (5, 7, 8), (5, 8, 6), (1, 5, 6), (1, 6, 2),
             (3, 4, 8), (3, 8, 7), (1, 3, 7), (1, 7, 5), (2, 6, 8), (2, 8, 4)]
    path.write_text("\n".join(["g body", *(f"v {a} {b} {c}" for a, b, c in corners),
                               *(f"f {a} {b} {c}" for a, b, c in faces)]) + "\n")
    parsed = load_model(path)
    assert parsed.geometry.colors == (None,)
    _no_parsing(monkeypatch)
    cached = load_model(path)
    assert cached.geometry.colors == (None,)
    assert cached.size == parsed.size == (1.0, 1.0, 1.0)


def test_an_unwritable_cache_only_costs_a_parse(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("CGA_CACHE_DIR", str(blocker))
    assert load_model(SHIPPED / "chair.obj").name == "chair"


def test_check_reads_no_arrays_for_a_cached_file(cache, monkeypatch):
    library.ModelLibrary([SHIPPED]).get("chair")  # fills the on-disk cache
    monkeypatch.setattr(library, "_from_cache", lambda data: pytest.fail("arrays read"))
    _no_parsing(monkeypatch)
    assert library.ModelLibrary([SHIPPED]).check("chair") == SHIPPED / "chair.obj"


def test_check_parses_a_file_the_cache_does_not_hold(cache, tmp_path):
    good = tmp_path / "crate.obj"
    good.write_text((SHIPPED / "chair.obj").read_text().replace("density 465", "density 701"))
    bad = tmp_path / "broken.obj"
    bad.write_text("v 0 0 0\nf 1 2 3\n")
    models = library.ModelLibrary([tmp_path])
    assert models.check("crate") == good
    assert len(list(cache.glob("*.npz"))) == 1  # parsed now, so the next check reads none
    with pytest.raises(library.ModelFileError):
        models.check("broken")


def test_another_trimesh_install_parses_again(cache, monkeypatch):
    load_model(SHIPPED / "chair.obj")
    monkeypatch.setattr(library, "_trimesh_install", lambda: "/elsewhere/trimesh/__init__.py:1:2")
    parsed = []
    real = library._parse_geometry
    monkeypatch.setattr(library, "_parse_geometry",
                        lambda path, text: parsed.append(path) or real(path, text))
    assert load_model(SHIPPED / "chair.obj").name == "chair"
    assert parsed == [SHIPPED / "chair.obj"]
    assert len(list(cache.glob("*.npz"))) == 2


def test_the_trimesh_install_is_read_without_importing_it():
    import importlib.util

    origin = importlib.util.find_spec("trimesh").origin
    assert library._trimesh_install().startswith(f"{origin}:")
