"""Every demo's glTF passes the Khronos glTF validator with no errors and no warnings,
and every primitive has a material.

Runs when the validator is installed: ``CGA_GLTF_VALIDATOR_DIR`` names an npm-installed
``gltf-validator`` package (``.ci/run`` sets it up) and ``node`` is on the PATH.
"""

from __future__ import annotations

import json
import os
import shutil
import struct
import subprocess
from pathlib import Path

import pytest

from cga.pipeline import build

DEMOS = sorted((Path(__file__).resolve().parents[2] / "demos").glob("*.grammar"))
VALIDATOR = os.environ.get("CGA_GLTF_VALIDATOR_DIR")

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(not VALIDATOR or shutil.which("node") is None,
                       reason="Khronos glTF validator not installed (set CGA_GLTF_VALIDATOR_DIR)"),
]

# validateBytes resolves to the validator's report (see the package's README)
SCRIPT = """
const validator = require(process.argv[2]);
const data = new Uint8Array(require('fs').readFileSync(process.argv[3]));
validator.validateBytes(data, {maxIssues: 1000}).then(
  (report) => process.stdout.write(JSON.stringify(report)),
  (error) => { process.stderr.write(String(error)); process.exit(2); });
"""


@pytest.mark.parametrize("grammar", DEMOS, ids=lambda p: p.stem)
def test_demo_glb_has_no_validation_errors(grammar, tmp_path):
    build(grammar, seed=5, out_dir=tmp_path, formats=["glb"], quiet=True)
    script = tmp_path / "validate.js"
    script.write_text(SCRIPT)
    glb = tmp_path / f"{grammar.stem}.glb"
    result = subprocess.run(["node", str(script), str(Path(VALIDATOR).resolve()), str(glb)],
                            capture_output=True, text=True, timeout=120, check=False)
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    errors = [m for m in report["issues"]["messages"] if m["severity"] in (0, 1)]
    assert report["issues"]["numErrors"] == 0, errors[:20]
    assert report["issues"]["numWarnings"] == 0, errors[:20]
    # every primitive has a PBR material (read from the file's JSON chunk directly)
    data = glb.read_bytes()
    length = struct.unpack_from("<I", data, 12)[0]
    document = json.loads(data[20:20 + length])
    primitives = [p for m in document["meshes"] for p in m["primitives"]]
    assert primitives and all("material" in p for p in primitives)
    assert all("pbrMetallicRoughness" in m for m in document["materials"])
