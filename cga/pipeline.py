"""The build pipeline: grammar file → Scene → checks → files (docs/architecture.md,
"Stages and the data between them").

``parse → derive → Scene → scene nodes (meshes) → checks → exporters``. Every stage is
timed into ``scene.timings`` (``parse``, ``derive`` and, inside it, each operation by
name, ``meshing``, ``physics``, ``navigability``, ``difficulty``, ``export``). Checks run only for
scenes with floors and are imported only then, as are the exporters, so a massing build
never loads pybullet. All files of a build are staged and moved into the output folder
only when every exporter has succeeded (:func:`cga.fsutil.atomic_output_dir`).
"""

from __future__ import annotations

import contextlib
import math
import time
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from shapely.geometry import Polygon

from .errors import DerivationError, ExportError, NoSolutionError, SourceError, UsageError
from .evaluator import DEFAULT_MAX_DEPTH, Evaluator, check_max_depth, evaluate_units
from .model import Diagnostic
from .registry import OperationRegistry
from .scene import Scene

if TYPE_CHECKING:  # pragma: no cover
    from .lot import LotInput

__all__ = ["MAX_ROBOT_RADIUS", "STAGES", "build", "check_grammar", "default_out_dir", "run_checks",
           "export_scene"]

STAGES = ("parse", "derive", "meshing", "physics", "navigability", "difficulty", "export")
"""Pipeline stages as they appear in ``Scene.timings`` (operation timings are the other keys)."""


MAX_ROBOT_RADIUS = 5.0
"""Largest ``--robot-radius`` (m): a robot 10 m across fits through no door, and the
navigability raster grows with the radius (1e6 asked for petabytes)."""


def default_out_dir(name: str) -> Path:
    """``out/<name>`` in the working directory (docs/outputs.md)."""
    return Path("out") / name


class _Progress:
    """Times stages into a dict and shows the running stage on a terminal (stderr)."""

    def __init__(self, timings: dict[str, float], quiet: bool):
        self.timings = timings
        self.status = None
        if not quiet:
            from rich.console import Console

            console = Console(stderr=True)
            if console.is_terminal:
                self.status = console.status("building…")

    def __enter__(self) -> "_Progress":
        if self.status is not None:
            self.status.start()
        return self

    def __exit__(self, *exc: Any) -> None:
        if self.status is not None:
            self.status.stop()

    @contextlib.contextmanager
    def stage(self, name: str, message: str) -> Iterator[None]:
        if self.status is not None:
            self.status.update(message)
        started = time.perf_counter()
        try:
            yield
        finally:
            self.timings[name] = self.timings.get(name, 0.0) + time.perf_counter() - started


def _check_options(seed: int, units: float | None, robot_radius: float, formats: Sequence[str],
                   max_depth: int) -> None:
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise UsageError(f"--seed must be a whole number ≥ 0, got {seed!r}")
    if units is not None and not 0 < units < math.inf:
        raise UsageError(f"--units must be positive (metres per grammar unit), got {units!r}")
    if not 0 < robot_radius <= MAX_ROBOT_RADIUS:
        raise UsageError(f"--robot-radius must be positive and at most {MAX_ROBOT_RADIUS:g} m, "
                         f"got {robot_radius!r}")
    check_max_depth(max_depth)
    if formats:
        from .export import check_formats

        check_formats(formats)


def check_grammar(grammar_path: str | Path, *, seed: int = 0, units: float | None = None,
                  robot_radius: float = 0.25, formats: Sequence[str] = ("glb",),
                  max_depth: int = DEFAULT_MAX_DEPTH, overrides: Mapping[str, str] | None = None,
                  **_other_build_options: Any) -> None:
    """Raise what :func:`build` would raise for every seed before deriving anything: a
    missing or unreadable grammar, a syntax error, a bad option (``cga batch`` checks
    this once instead of failing each seed the same way).

    Takes :func:`build`'s keywords; those that need a derivation to check are ignored.
    """
    from .parser import parse, read_grammar

    path = Path(grammar_path)
    text = read_grammar(path)
    _check_options(seed, units, robot_radius, formats, max_depth)
    grammar = parse(text, str(path))
    if overrides:
        from .evaluator import evaluate_variables
        from .overrides import check_override_names

        check_override_names(grammar, overrides)
        evaluate_variables(grammar, seed, overrides)  # the values' kinds


def run_checks(scene: Scene, *, robot_radius: float = 0.25) -> None:
    """Run the physics and navigability checks on ``scene.nodes`` into ``scene.checks``
    (floors only), then measure ``scene.difficulty`` from their grids.

    Each entry is the check's report (a :class:`~cga.report.CheckReport`); their times
    go to ``scene.timings``.
    """
    from .difficulty import measure_scene

    progress = _Progress(scene.timings, quiet=True)
    _run_checks(scene, robot_radius, progress)
    with progress.stage("difficulty", "measuring difficulty…"):
        scene.difficulty = measure_scene(scene)


def _run_checks(scene: Scene, robot_radius: float, progress: _Progress) -> None:
    if not scene.floors:
        return
    from .checks.navigability import check_navigability
    from .checks.physics import check_physics

    with progress.stage("physics", "physics check (settling furniture)…"):
        report = check_physics(scene)
    scene.checks["physics"] = report
    with progress.stage("navigability", "navigability check…"):
        reach = check_navigability(scene, radius=robot_radius)
    scene.checks["navigability"] = reach


def export_scene(scene: Scene, out_dir: str | Path, formats: Sequence[str], *,
                 protect: Sequence[str | Path] = ()) -> list[Path]:
    """Write ``formats`` of ``scene.nodes`` into ``out_dir`` all-or-nothing; returns the
    written files.

    Files an earlier build of the same name wrote in one of ``formats`` and this one
    does not write again are removed (a stale plan of a floor this build lacks); files
    of other formats are kept, and no other file is replaced or removed
    (:mod:`cga.output_record`). ``protect`` lists inputs that must survive whatever
    happens (the grammar itself is always protected).

    Raises
    ------
    ExportError
        The folder cannot be created or written (a file of that name, no permission),
        or it holds a file of an output's name that no build of this name wrote.
    """
    from .export import EXPORTERS
    from .fsutil import atomic_output_dir
    from .output_record import OutputFormats

    target = Path(out_dir)
    written: list[Path] = []
    try:
        inputs = [*protect, *([scene.source] if scene.source else [])]
        kinds = OutputFormats(frozenset(formats))
        with atomic_output_dir(target, owner=scene.name, protect=inputs,
                               formats=kinds) as staging:
            for fmt in dict.fromkeys(formats):
                files = EXPORTERS[fmt](scene, scene.nodes, staging, scene.name)
                kinds.files.update({path.relative_to(staging).as_posix(): fmt
                                    for path in files})
                written.extend(files)
    except OSError as error:
        raise ExportError(f"cannot write the output folder {target}: {error.strerror or error}"
                          f"{f' ({error.filename})' if error.filename else ''}") from None
    return [target / path.relative_to(staging) for path in written]


def _input_files(*names: str | None) -> list[Path]:
    """The options that name existing files (a ``--lot`` may be a GeoJSON file or a size)."""
    files = []
    for name in names:
        try:
            if name and Path(name).is_file():
                files.append(Path(name))
        except (OSError, ValueError):  # e.g. a polygon text longer than a file name may be
            continue
    return files


def _lot_notes(lot: "LotInput | None", units: float) -> list[Diagnostic]:
    """What reading ``--lot`` decided, and the unit of a plain size when the grammar's
    units are not metres (so the default is visible)."""
    if lot is None:
        return []
    notes = list(lot.diagnostics)
    if not lot.unit_stated and units != 1:
        minx, minz, maxx, maxz = lot.polygon.bounds
        notes.append(Diagnostic("info", "lot", (
            f"--lot {lot.text} has no unit, so it is metres ({maxx - minx:g} m × "
            f"{maxz - minz:g} m) although the grammar's units = {units:g}; write "
            f"{lot.text.strip()}m to say so or {lot.text.strip()}u for grammar units")))
    return notes


def build(grammar_path: str | Path, *, seed: int = 0, lot: str | Polygon | None = None,
          units: float | None = None, out_dir: str | Path | None = None,
          formats: Sequence[str] = ("glb",), physics: bool = True, robot_radius: float = 0.25,
          strict: bool = False, quiet: bool = False, max_depth: int = DEFAULT_MAX_DEPTH,
          operations: OperationRegistry | None = None,
          allow_paths: Sequence[str | Path] = (),
          overrides: Mapping[str, str] | None = None,
          materials: str | None = None) -> Scene:
    """Build a grammar: derive it, mesh it, check it and write the requested files.

    Parameters
    ----------
    grammar_path:
        The ``.grammar`` file.
    seed:
        Build seed (≥ 0); the same seed gives byte-identical files.
    lot:
        ``--lot`` text (``"14x10"``, ``"polygon(...)"``, a ``.geojson`` path) or a shapely
        polygon in metres; default: the grammar's ``Lot:``, else a 14 m × 10 m rectangle.
    units:
        Metres per grammar unit; overrides the grammar's ``units``.
    out_dir:
        The folder that receives the files; default ``out/<grammar name>``.
    formats:
        Export formats (keys of :data:`cga.export.EXPORTERS`); empty writes nothing.
    physics:
        Run the physics and navigability checks (scenes with floors only).
    robot_radius:
        Robot radius (m) for the navigability check.
    strict:
        Operations fail instead of repairing (``OperationContext.strict``), and a
        failed check fails the build (nothing is written).
    quiet:
        Show no progress on the terminal.
    max_depth:
        Derivation depth limit (runaway recursion guard).
    operations:
        An :class:`~cga.registry.OperationRegistry` with extra operations (copied).
    allow_paths:
        Folders besides the grammar's folder tree and the shipped data that rule
        tables, models and the lot file may be read from (``--allow-path``; see
        :mod:`cga.sandbox`). Anything else is refused.
    overrides:
        Grammar variables to replace, name → value text (``--set NAME=VALUE``,
        :mod:`cga.overrides`); each must be declared by the grammar and of its kind.
    materials:
        ``"neutral"`` or ``"random"`` (``--materials``): whether materials and lights are
        drawn with the seed (docs/appearance.md); default: the grammar variable
        ``materials``, else neutral.

    Returns
    -------
    Scene
        With ``timings`` per stage and operation and ``checks`` when they ran.

    Raises
    ------
    CGAError
        Any user error (syntax, derivation, rule table, missing file, a file outside
        the allowed folders, bad option, strict failure); source errors carry the
        grammar text for their excerpt.
    """
    from .difficulty import measure_scene
    from .operations.furniture.library import grammar_library
    from .parser import parse, read_grammar
    from .sandbox import Sandbox

    path = Path(grammar_path)
    text = read_grammar(path)
    _check_options(seed, units, robot_radius, formats, max_depth)
    if materials is not None:
        from .appearance import check_mode

        check_mode(materials)
    sandbox = Sandbox.for_grammar(path.parent, allow_paths)
    timings: dict[str, float] = {}
    try:
        with _Progress(timings, quiet) as progress:
            with progress.stage("parse", f"parsing {path.name}…"):
                grammar = parse(text, str(path))
            lot_text = lot if isinstance(lot, str) else None
            lot_input = None
            build_units = units if units is not None else evaluate_units(grammar)
            if lot is not None:
                from .lot import LotInput, read_lot, validate_lot

                lot_input = (read_lot(lot, units=build_units,
                                      sandbox=sandbox.with_working_directory())
                             if isinstance(lot, str)
                             else LotInput(validate_lot(lot, "lot"), text="lot"))
            # one model library per build: add_furniture sizes items with it, the
            # meshing layer poses the same loaded models; both read only in the sandbox
            library = grammar_library(path.parent, sandbox)
            with progress.stage("derive", "deriving the shape tree…"):
                try:
                    derivation = Evaluator(
                        grammar, seed=seed, units=units, operations=operations,
                        max_depth=max_depth, base_dir=path.parent, strict=strict,
                        library=library, sandbox=sandbox, overrides=overrides,
                    ).derive(None if lot_input is None else lot_input.polygon)
                except (DerivationError, NoSolutionError) as error:  # what a lot's size can cause
                    hint = None if lot_input is None else lot_input.unit_hint(build_units)
                    if hint is not None:
                        error.add_hint(hint)
                    raise
            timings.update(derivation.timings)
            from .appearance import appearance_from
            from .building import stack_storeys

            appearance = appearance_from(derivation.variables, mode=materials,
                                         base_dir=path.parent, sandbox=sandbox)

            scene = Scene(name=path.stem, seed=seed, units=derivation.units,
                          terminals=stack_storeys(derivation.terminals), source=path,
                          diagnostics=[*_lot_notes(lot_input, build_units),
                                       *derivation.diagnostics],
                          timings=timings, library=library, appearance=appearance,
                          georeference=None if lot_input is None else lot_input.georeference)
            with progress.stage("meshing", "meshing…"):
                scene.nodes  # noqa: B018 - made once here, timed; checks and exporters reuse them
            if physics:
                _run_checks(scene, robot_radius, progress)
            with progress.stage("difficulty", "measuring difficulty…"):
                scene.difficulty = measure_scene(scene)
            failed = [c for c in scene.checks.values() if not c.passed]
            if strict and failed:
                raise NoSolutionError("strict mode: the build does not pass its checks",
                                      [c.summary() for c in failed])
            if formats:
                with progress.stage("export", "writing files…"):
                    export_scene(scene, out_dir or default_out_dir(scene.name), formats,
                                 protect=_input_files(lot_text))
    except SourceError as error:
        if error.span is not None and error.span.file == str(path):
            error.with_source(text)
        raise
    return scene
