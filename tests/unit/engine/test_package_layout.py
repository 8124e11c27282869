"""Package layout: in a checkout only cga's intended subpackages import as ``cga.*``; a
setuptools ``build/`` folder beside the package does not shadow :func:`cga.build`."""

from __future__ import annotations

import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

REPO = Path(__file__).resolve().parents[3]

PROBE = textwrap.dedent("""
    import importlib.util, json
    import cga
    out = {"cga": cga.__file__}
    try:
        import cga.build
        out["build_module"] = cga.build.__file__ if hasattr(cga.build, "__file__") else "?"
    except ModuleNotFoundError:
        out["build_module"] = None
    import cga.pipeline
    out["build_is_function"] = callable(cga.build) and cga.build.__module__ == "cga.pipeline"
    for name in ("cga.tests", "cga.docs", "cga.build"):
        out[name] = importlib.util.find_spec(name) is not None
    import cga.operations, cga.rules, cga.furniture_models
    from cga.resources import shipped_dir
    out["operations"] = cga.operations.__file__
    out["rules"] = str(shipped_dir("cga.rules"))
    out["models"] = str(shipped_dir("cga.furniture_models"))
    print(json.dumps(out))
""")


def _checkout(tmp_path: Path) -> Path:
    """A minimal checkout: the package, the library's folders and the usual clutter."""
    root = tmp_path / "checkout"
    shutil.copytree(REPO / "cga", root / "cga", ignore=shutil.ignore_patterns("__pycache__"))
    (root / "operations").mkdir(parents=True)
    (root / "operations" / "__init__.py").write_text('"""operations"""\n')
    (root / "rules").mkdir()
    (root / "rules" / "table.csv").write_text("Type;Min\n")
    (root / "models").mkdir()
    (root / "models" / "__init__.py").write_text("")
    for clutter in ("build", "tests", "docs"):
        (root / clutter).mkdir()
        (root / clutter / "x.py").write_text("")
    (root / "build" / "lib").mkdir()
    return root


def test_only_intended_subpackages_import_from_a_checkout(tmp_path):
    import json

    root = _checkout(tmp_path)
    result = subprocess.run([sys.executable, "-c", PROBE], cwd=tmp_path, capture_output=True,
                            text=True, env={"PYTHONPATH": str(root), "PATH": "/usr/bin:/bin"},
                            check=True)
    out = json.loads(result.stdout)
    assert out["cga"] == str(root / "cga" / "__init__.py")
    assert out["build_module"] is None and out["build_is_function"]
    assert not out["cga.tests"] and not out["cga.docs"] and not out["cga.build"]
    assert out["operations"] == str(root / "operations" / "__init__.py")
    assert out["rules"] == str(root / "rules")
    assert out["models"] == str(root / "models")


def test_every_package_folder_is_installed():
    """pyproject.toml lists the packages a (non-editable) install copies; a folder with an
    ``__init__.py`` missing from the list works in a checkout and is absent once installed."""
    import tomllib

    project = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))
    setuptools = project["tool"]["setuptools"]
    listed = set(setuptools["packages"])
    folders = {name: REPO / path for name, path in setuptools["package-dir"].items()}
    found = set()
    for name, folder in folders.items():
        for init in folder.rglob("__init__.py"):
            if "__pycache__" in init.parts:
                continue
            parts = init.parent.relative_to(folder).parts
            found.add(".".join((name, *parts)))
    assert sorted(found - listed) == []
