"""`cga --help` and `cga check` do not load the geometry, physics or plotting libraries,
and `cga build --no-physics` does not load the physics engine."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
HEAVY = ("trimesh", "scipy", "pybullet", "manifold3d", "PIL", "networkx", "rich", "email")
"""Libraries a check or `--help` never needs (`email` comes with `importlib.metadata`)."""
LAYOUT = ("cga.operations.furniture.solver", "cga.operations.floorplan.bsp",
          "cga.operations.floorplan.circulation", "cga.operations.roomtyping.assign",
          "cga.operations.roomtyping.room_graph")
"""Layout code that only a build runs: a check loads the operations for their checks."""

_PROBE = """
import json, sys
from cga.cli import main
try:
    main({args!r})
except SystemExit:
    pass
print(json.dumps(sorted(m for m in sys.modules
                        if m.split('.')[0] in {heavy!r} or m in {layout!r})), file=sys.stderr)
"""


def _imported(args: list[str], cache: Path) -> set[str]:
    """Top-level heavy modules, and the :data:`LAYOUT` modules, a fresh process imported
    while running ``cga args``."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), CGA_CACHE_DIR=str(cache))
    done = subprocess.run([sys.executable, "-c", _PROBE.format(args=args, heavy=HEAVY, layout=LAYOUT)],
                          cwd=ROOT, env=env, capture_output=True, text=True, timeout=120)
    last = done.stderr.strip().splitlines()[-1]
    return {name if name in LAYOUT else name.split(".")[0] for name in json.loads(last)}


def test_help_imports_no_heavy_library(tmp_path):
    assert _imported(["--help"], tmp_path) == set()


@pytest.mark.parametrize("grammar", ["house", "office", "usar_maze"])
def test_check_imports_no_heavy_library_once_the_cache_is_warm(tmp_path, grammar):
    path = str(ROOT / "demos" / f"{grammar}.grammar")
    cold = _imported(["check", path], tmp_path)
    assert "pybullet" not in cold  # parsing a model (trimesh) is all a cold cache adds
    assert _imported(["check", path], tmp_path) == set()


def test_build_without_checks_does_not_import_physics(tmp_path):
    out = tmp_path / "out"
    imported = _imported(["build", str(ROOT / "demos" / "house.grammar"), "--quiet",
                          "--no-physics", "--export", "json", "--out", str(out)], tmp_path)
    assert (out / "house.scene.json").is_file()
    assert "pybullet" not in imported


def test_build_without_checks_loads_neither_trimesh_nor_scipy(tmp_path):
    """The default files (glb, scene JSON, plans) are written from arrays: trimesh (and
    the SciPy and networkx modules it loads) cost more CPU than meshing the house. Only
    parsing a model file the cache does not hold yet reads it with trimesh."""
    args = ["build", str(ROOT / "demos" / "house.grammar"), "--quiet", "--no-physics",
            "--out", str(tmp_path / "out")]
    _imported(args, tmp_path)  # fills the model cache
    imported = _imported(args, tmp_path)
    assert (tmp_path / "out" / "house.glb").is_file()
    assert (tmp_path / "out" / "house.floor0.png").is_file()
    assert not imported & {"trimesh", "scipy", "pybullet"}
