"""Exporters: one pure builder and one writer per output format (docs/outputs.md).

:data:`EXPORTERS` maps a format name to a writer
``export_x(scene, nodes, out_dir: Path, name: str) -> list[Path]`` that writes its files
into ``out_dir`` atomically (:func:`cga.fsutil.atomic_write`) and returns their paths.
``cga build`` writes :data:`DEFAULT_FORMATS` and whatever ``--export`` adds. A new
format is one module with its builder and writer, plus one entry here.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

from cga.errors import UsageError
from cga.scene import Scene, SceneNode

from .glb import export_glb
from .mjcf import export_mjcf
from .obj import export_obj
from .plan import export_plans
from .render import export_render
from .rosmap import export_rosmap
from .scene_json import export_scene_json
from .sdf import export_sdf
from .urdf import export_urdf
from .usd import export_usd
from .view import export_view

__all__ = ["Exporter", "EXPORTERS", "DEFAULT_FORMATS", "BATCH_FORMATS", "OPTIONAL_MODULES",
           "check_formats", "missing_packages"]

Exporter = Callable[[Scene, Sequence[SceneNode], Path, str], list[Path]]
"""``export_x(scene, nodes, out_dir, name) -> written paths``."""

EXPORTERS: dict[str, Exporter] = {
    "glb": export_glb,
    "json": export_scene_json,
    "plan": export_plans,
    "obj": export_obj,
    "urdf": export_urdf,
    "sdf": export_sdf,
    "mjcf": export_mjcf,
    "usd": export_usd,
    "map": export_rosmap,
    "view": export_view,
    "render": export_render,
}
"""Format name → writer."""

DEFAULT_FORMATS: tuple[str, ...] = ("glb", "json", "plan")
"""What ``cga build`` writes without ``--export``."""

BATCH_FORMATS: tuple[str, ...] = ("glb", "json")
"""What ``cga batch`` writes per seed without ``--export``: a dataset needs the model and
its labels; plan pictures (the slowest default output) are one ``--export plan`` away."""

OPTIONAL_MODULES: dict[str, tuple[str, str, str]] = {"usd": ("pxr", "usd-core", "robot"),
                                                     "render": ("embreex", "embreex", "render")}
"""Format → (module it imports, package that provides it, the extra that installs it) for
formats whose library is not a dependency of cga: ``pip install 'cga[robot]'`` installs
the robot formats' libraries, ``pip install 'cga[render]'`` Embree for ``render``."""


def missing_packages(formats: Sequence[str]) -> list[str]:
    """The packages ``formats`` need that are not installed (in format order)."""
    import importlib.util

    return list(dict.fromkeys(
        package for fmt in formats if fmt in OPTIONAL_MODULES
        for module, package, _ in [OPTIONAL_MODULES[fmt]]
        if importlib.util.find_spec(module) is None))


def check_formats(formats: Sequence[str]) -> None:
    """Refuse unknown formats and formats whose optional package is not installed.

    Raises
    ------
    UsageError
        Naming the unknown formats and the ones available, or the missing packages and
        the extra that installs them.
    """
    unknown = [f for f in formats if f not in EXPORTERS]
    if unknown:
        raise UsageError(f"unknown export format{'s' * (len(unknown) > 1)} "
                         f"{', '.join(unknown)}; available: {', '.join(EXPORTERS)}")
    missing = missing_packages(formats)
    if missing:
        extras = ",".join(dict.fromkeys(OPTIONAL_MODULES[f][2] for f in formats
                                        if f in OPTIONAL_MODULES
                                        and OPTIONAL_MODULES[f][1] in missing))
        raise UsageError(f"--export {','.join(formats)} needs {' and '.join(missing)}, "
                         f"which {'is' if len(missing) == 1 else 'are'} not installed: "
                         f"pip install 'cga[{extras}]'")
