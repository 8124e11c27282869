"""Exporters: one pure builder and one writer per output format (docs/outputs.md).

:data:`EXPORTERS` maps a format name to a writer
``export_x(scene, nodes, out_dir: Path, name: str) -> list[Path]`` that writes its files
into ``out_dir`` atomically (:func:`cga.fsutil.atomic_write`) and returns their paths.
``cga build`` writes :data:`DEFAULT_FORMATS` and whatever ``--export`` adds. A new
format is one module with its builder and writer, plus one entry here.

A writer's module is imported the first time its format is used: the formats pull in
heavy libraries (the plan pictures Pillow, the ROS map the occupancy grid and SciPy, the
views manifold3d), and a build pays only for the formats it writes.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterator, MutableMapping, Sequence
from pathlib import Path

from cga.errors import UsageError
from cga.scene import Scene, SceneNode

__all__ = ["Exporter", "EXPORTERS", "ExporterTable", "DEFAULT_FORMATS", "BATCH_FORMATS", "OPTIONAL_MODULES",
           "check_formats", "missing_packages"]

Exporter = Callable[[Scene, Sequence[SceneNode], Path, str], list[Path]]
"""``export_x(scene, nodes, out_dir, name) -> written paths``."""



class ExporterTable(MutableMapping[str, Exporter]):
    """Format name → writer, where a writer may be given as ``"module:function"`` and is
    imported on its first lookup (the operation registry's pattern, :mod:`cga.registry`).
    Iteration order is the order formats were added; assigning a callable registers a
    writer of one's own."""

    def __init__(self, entries: dict[str, str | Exporter]):
        self._entries = dict(entries)

    def __getitem__(self, name: str) -> Exporter:
        entry = self._entries[name]
        if isinstance(entry, str):
            module_name, function = entry.split(":")
            entry = getattr(importlib.import_module(module_name), function)
            self._entries[name] = entry
        return entry

    def module(self, name: str) -> str | None:
        """The module of the writer of ``name`` if it is not imported yet, else None."""
        entry = self._entries[name]
        return entry.split(":")[0] if isinstance(entry, str) else None

    def __setitem__(self, name: str, writer: Exporter) -> None:
        self._entries[name] = writer

    def __delitem__(self, name: str) -> None:
        del self._entries[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)

    def __contains__(self, name: object) -> bool:
        return name in self._entries


EXPORTERS = ExporterTable({
    "glb": "cga.export.glb:export_glb",
    "json": "cga.export.scene_json:export_scene_json",
    "plan": "cga.export.plan:export_plans",
    "obj": "cga.export.obj:export_obj",
    "urdf": "cga.export.urdf:export_urdf",
    "sdf": "cga.export.sdf:export_sdf",
    "mjcf": "cga.export.mjcf:export_mjcf",
    "usd": "cga.export.usd:export_usd",
    "map": "cga.export.rosmap:export_rosmap",
    "view": "cga.export.view:export_view",
    "render": "cga.export.render:export_render",
})
"""Format name → writer (imported on first use)."""

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
