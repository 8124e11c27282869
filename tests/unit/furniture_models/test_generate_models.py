"""scripts/generate_models.py is the only source of models/*.obj, and it is deterministic."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

from cga.resources import shipped_dir

SCRIPT = Path(__file__).resolve().parents[3] / "scripts" / "generate_models.py"


@pytest.fixture(scope="module")
def generator():
    spec = importlib.util.spec_from_file_location("generate_models", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up while building
    try:
        spec.loader.exec_module(module)
        yield module
    finally:
        del sys.modules[spec.name]


def test_generating_twice_gives_identical_bytes(generator, tmp_path):
    first, second = tmp_path / "a", tmp_path / "b"
    assert generator.main(["--out", str(first)]) == 0
    assert generator.main(["--out", str(second)]) == 0
    names = sorted(p.name for p in first.iterdir())
    assert len(names) >= 30
    assert names == sorted(p.name for p in second.iterdir())
    for name in names:
        assert (first / name).read_bytes() == (second / name).read_bytes(), name


def test_shipped_models_are_exactly_what_the_script_generates(generator, tmp_path):
    generator.main(["--out", str(tmp_path)])
    shipped = shipped_dir("cga.furniture_models")
    generated = {p.name: p.read_bytes() for p in tmp_path.glob("*.obj")}
    on_disk = {p.name: p.read_bytes() for p in shipped.glob("*.obj")}
    assert sorted(on_disk) == sorted(generated)
    stale = [name for name in generated if generated[name] != on_disk[name]]
    assert not stale, f"regenerate with: python {SCRIPT.relative_to(SCRIPT.parents[1])}"


def test_check_mode_spots_edited_and_extra_files(generator, tmp_path, capsys):
    generator.main(["--out", str(tmp_path)])
    assert generator.main(["--out", str(tmp_path), "--check"]) == 0
    chair = tmp_path / "chair.obj"
    chair.write_text(chair.read_text().replace("# density", "# density 1\n# was"))
    (tmp_path / "spare.obj").write_text("")
    assert generator.main(["--out", str(tmp_path), "--check"]) == 1
    err = capsys.readouterr().err
    assert "chair.obj" in err and "spare.obj" in err and "bed.obj" not in err
