"""End to end: `cga build demos/massing.grammar` in a subprocess, twice, and the glb in trimesh."""

from __future__ import annotations

import io
import subprocess
import sys
from pathlib import Path

import numpy as np
import trimesh

ROOT = Path(__file__).resolve().parents[2]
DEMO = ROOT / "demos" / "massing.grammar"

# Shapes of demos/massing.grammar, counted by hand from the rules (the same for every seed):
#   ground-floor facades (L-shaped lot, 6 edges: 24, 10, 12, 8, 12, 18 m), bays of
#   ~2.6 + 0.45 m → round(L / 3.05) bays of 2 shapes: 16 + 8 + 6 + 8 + 12 = 50, and the
#   10 m entrance side: 3.5 m of shop front (1 bay = 2) + entrance + 3.5 m (2) = 5;
#   storeys: 12.4 m above the ground floor minus the 3.1 m top floor → 3 storeys;
#   top floor: penthouse (still L-shaped: 6 walls + 1 roof) and the terrace deck (1).
EXPECTED_NODES = 50 + 5 + 3 + 7 + 1


def run_cga(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "cga", *args], cwd=cwd, capture_output=True,
                          text=True, timeout=120)


def test_same_seed_gives_byte_identical_glb(tmp_path):
    outputs = []
    for run in ("a", "b"):
        result = run_cga("build", str(DEMO), "--seed", "7", "--out", str(tmp_path / run),
                         "--quiet", cwd=tmp_path)
        assert result.returncode == 0, result.stderr
        assert result.stdout == ""
        outputs.append((tmp_path / run / "massing.glb").read_bytes())
    assert outputs[0] == outputs[1]
    other = run_cga("build", str(DEMO), "--seed", "8", "--out", str(tmp_path / "c"), "--quiet",
                    cwd=tmp_path)
    assert other.returncode == 0, other.stderr
    assert (tmp_path / "c" / "massing.glb").read_bytes() != outputs[0]


def test_default_output_folder_and_glb_contents(tmp_path):
    result = run_cga("build", str(DEMO), "--seed", "3", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "massing" in result.stdout and "derive" in result.stdout
    out = tmp_path / "out" / "massing"
    assert {"massing.glb", "massing.scene.json"} <= {p.name for p in out.iterdir()}
    scene = trimesh.load(io.BytesIO((out / "massing.glb").read_bytes()), file_type="glb")
    names = scene.graph.nodes_geometry
    assert len(names) == EXPECTED_NODES
    assert all(name.startswith("Lot/Building/") for name in names)
    assert sum("/Glazing[" in n for n in names) == sum("/Pier[" in n for n in names) == 27
    # y up: the lot spans x 0..24, z 0..18 and the building rises 16.6 m (a roof garden
    # adds 0.6 m on some seeds)
    low, high = scene.bounds
    assert np.allclose(low, 0) and np.allclose(high[[0, 2]], [24, 18])
    assert np.isclose(high[1], 16.6) or np.isclose(high[1], 17.2)


def test_check_command_and_error_exit(tmp_path):
    ok = run_cga("check", str(DEMO), cwd=tmp_path)
    assert ok.returncode == 0 and ok.stdout.strip().endswith(": ok")
    bad = tmp_path / "bad.grammar"
    bad.write_text("Rules:\nLot --> extrude(2) Body\nBody --> split(\"y\"){ ~1 : A\n")
    result = run_cga("build", str(bad), cwd=tmp_path)
    assert result.returncode == 2
    assert f"{bad}:3:" in result.stderr and "Traceback" not in result.stderr
    assert not (tmp_path / "out").exists()
