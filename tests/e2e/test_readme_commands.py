"""The README's commands run as written (issue 20: its `--lot footprint.geojson` example
failed, no such file was shipped).

Every ``cga ...`` command of the README (its ``sh`` blocks, and inline commands such as
`cga build demos/house.grammar --seed 7`) runs with ``python -m cga`` in a scratch
folder holding a copy of ``demos/``, in the order the README gives them (``cga render``
reads the build before it), and must exit with status 0. The install steps before a
``&&`` (a fresh venv, ``pip install``) and ``pytest`` are left out: CI runs them, and
so are commands for a Ray cluster (``--engine ray``), which need one. Two changes are
made to a command: a batch of more than :data:`MAX_SEEDS` seeds (``-n 1000``,
``-n 1e6``) builds :data:`MAX_SEEDS`, so the test stays within the suite's time budget
(its options are still parsed and used as written), and a cluster's shared folder
(``/shared/...``) is a folder of the scratch folder. ``cga batch merge`` joins the
manifests of all 100 shards of the cluster example, of which the README runs one here,
so it must refuse naming the 99 missing shards (a cluster runs the others). The
README's Python API example runs as a script in the same folder.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
MAX_SEEDS = 2

pytestmark = pytest.mark.slow


def readme_commands(text: str) -> list[list[str]]:
    """The ``cga`` commands of ``text`` in order, each as its argument list."""
    commands: list[list[str]] = []
    fence: str | None = None
    for line in text.splitlines():
        if line.startswith("```"):
            fence = line[3:].strip() if fence is None else None
            continue
        if fence == "sh":
            tokens = shlex.split(line, comments=True)
            segments: list[list[str]] = [[]]
            for token in tokens:
                if token == "&&":
                    segments.append([])
                else:
                    segments[-1].append(token)
            commands += [s for s in segments if s and s[0] == "cga"]
        elif fence is None:
            for span in re.findall(r"`(cga [^`]+)`", line):
                tokens = shlex.split(span)
                if len(tokens) >= 3:  # a command, not a mention such as `cga build`
                    commands.append(tokens)
    return commands


def python_examples(text: str) -> list[str]:
    """The ``python`` blocks under the README's "Python API" heading."""
    section = text.split("## Python API", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```python\n(.*?)```", section, re.DOTALL)


def needs_a_cluster(command: list[str]) -> bool:
    return "--engine" in command and command[command.index("--engine") + 1] == "ray"


def bounded(command: list[str]) -> list[str]:
    """``command`` with a seed count above :data:`MAX_SEEDS` lowered to it and a
    cluster's shared folder made relative to the working folder."""
    out = [token.replace("/shared/", "shared/", 1) if token.startswith("/shared/") else token
           for token in command]
    for k, token in enumerate(out[:-1]):
        if token == "-n" and float(out[k + 1]) > MAX_SEEDS:
            out[k + 1] = str(MAX_SEEDS)
    return out


@pytest.fixture(scope="module")
def workdir(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("readme")
    shutil.copytree(ROOT / "demos", folder / "demos")
    return folder


def run(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])}
    return subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True, timeout=900)


def test_the_readme_lists_the_commands_checked_here():
    commands = [" ".join(c) for c in readme_commands(README.read_text(encoding="utf-8"))]
    assert "cga build demos/house.grammar --seed 7" in commands
    assert ("cga build demos/apartment.grammar --lot demos/footprint.geojson "
            "--robot-radius 0.3 --strict") in commands
    assert any(c.startswith("cga render out/house/house.scene.json") for c in commands)
    assert (ROOT / "demos" / "footprint.geojson").is_file()


def test_every_readme_command_runs(workdir):
    text = README.read_text(encoding="utf-8")
    failures = []
    for command in readme_commands(text):
        if needs_a_cluster(command):
            continue
        result = run([sys.executable, "-m", "cga", *bounded(command)[1:]], workdir)
        if command[1:3] == ["batch", "merge"]:
            if not (result.returncode == 2 and "99/100 missing" in result.stderr):
                failures.append(f"{shlex.join(command)} → exit {result.returncode}, "
                                f"expected the 99 other shards named as missing\n"
                                f"{result.stderr[-2000:]}")
            continue
        if result.returncode != 0:
            failures.append(f"{shlex.join(command)} → exit {result.returncode}\n"
                            f"{result.stderr[-2000:]}")
    assert not failures, "\n\n".join(failures)
    assert (workdir / "out" / "apartment" / "apartment.scene.json").is_file()
    assert (workdir / "out" / "house" / "house.render").is_dir()


def test_the_python_api_example_runs(workdir):
    for code in python_examples(README.read_text(encoding="utf-8")):
        result = run([sys.executable, "-c", code], workdir)
        assert result.returncode == 0, result.stderr[-2000:]
        assert "True" in result.stdout  # the example prints the checks' verdicts
