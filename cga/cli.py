"""The ``cga`` command line: ``cga build``, ``cga check``, ``cga batch`` (and ``cga batch
merge``) and ``cga render``.

Every user error is a :class:`~cga.errors.CGAError`: its message (file:line:column, the
line and a caret for grammar errors) goes to stderr and the exit status is 2, with no
traceback. Exit status 0 means success. Startup stays fast: trimesh, shapely-heavy
modules and pybullet are imported by the commands that need them, not here.

Each subcommand is a pair (``add_arguments``, ``run``) in :data:`COMMANDS`; adding a
command is one more entry.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from . import __version__
from .batch_engine import ENGINES
from .errors import CGAError

if TYPE_CHECKING:  # pragma: no cover
    from pathlib import Path

__all__ = ["COMMANDS", "main"]


def _formats(text: str) -> list[str]:
    return [part.strip().lower() for part in text.split(",") if part.strip()]


def _add_allow_path(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--allow-path", action="append", default=[], metavar="DIR",
                        dest="allow_paths",
                        help="a folder besides the grammar's own folder tree and the shipped "
                             "data that rule tables, models and lots may be read from "
                             "(repeatable; anything else is refused)")


def _add_output(parser: argparse.ArgumentParser, json_help: str) -> None:
    """``--quiet`` or ``--json`` (one of them)."""
    output = parser.add_mutually_exclusive_group()
    output.add_argument("--quiet", action="store_true", help="print nothing but errors")
    output.add_argument("--json", action="store_true", help=json_help)


def _add_set(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        dest="overrides",
                        help="replace a variable of the grammar's Variables: section, e.g. "
                             "--set difficulty=7 (repeatable; the value must be of the "
                             "variable's kind)")


def _overrides(args: argparse.Namespace) -> dict[str, str]:
    from .overrides import parse_assignments

    return parse_assignments(args.overrides)


def _add_build_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("grammar", metavar="FILE", help="the .grammar file")
    _add_allow_path(parser)
    _add_set(parser)
    parser.add_argument("--seed", type=int, default=0, metavar="N",
                        help="random seed; the same seed gives byte-identical files (default 0)")
    parser.add_argument("--lot", metavar="LOT",
                        help="footprint: 14x10 (metres, also written 14x10m), 1.4x1u (grammar "
                             'units), "polygon((0,0),(14,0),...)" (metres) or a .geojson file '
                             "(WGS84 longitude/latitude, a projected CRS or local metres; "
                             "docs/lots.md). Default: the grammar's Lot:, else 14x10 m")
    parser.add_argument("--out", metavar="DIR",
                        help="output folder (default out/<grammar name>)")
    parser.add_argument("--units", type=float, metavar="U",
                        help="metres per grammar unit (overrides the grammar's units)")
    parser.add_argument("--no-physics", action="store_true",
                        help="skip the physics and navigability checks")
    parser.add_argument("--strict", action="store_true",
                        help="fail instead of repairing (e.g. extra doors) and when a check fails")
    parser.add_argument("--robot-radius", type=float, default=0.25, metavar="R",
                        help="robot radius in metres for the navigability check (default 0.25)")
    parser.add_argument("--export", type=_formats, default=[], metavar="FORMATS",
                        help="extra outputs, comma separated: obj,urdf,sdf,mjcf,usd,map,view,render")
    parser.add_argument("--max-depth", type=int, default=64, metavar="N",
                        help="derivation depth limit (default 64)")
    _add_materials(parser)
    _add_output(parser, "print a machine-readable summary (JSON) on stdout")


def _add_materials(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--materials", choices=("neutral", "random"), default=None,
                        help="materials and lights: neutral, or drawn with the seed per "
                             "build and room (default: the grammar variable 'materials', "
                             "else neutral; docs/appearance.md)")


def _run_build(args: argparse.Namespace) -> int:
    from pathlib import Path

    from .pipeline import build, default_out_dir
    from .export import DEFAULT_FORMATS

    out_dir = Path(args.out) if args.out else default_out_dir(Path(args.grammar).stem)
    formats = list(dict.fromkeys([*DEFAULT_FORMATS, *args.export]))
    scene = build(args.grammar, seed=args.seed, lot=args.lot, units=args.units,
                  out_dir=out_dir, formats=formats, physics=not args.no_physics,
                  robot_radius=args.robot_radius, strict=args.strict,
                  quiet=args.quiet or args.json, max_depth=args.max_depth,
                  allow_paths=args.allow_paths, overrides=_overrides(args),
                  materials=args.materials)
    if args.json:
        import json

        from .summary import summary_dict

        print(json.dumps(summary_dict(scene, out_dir=out_dir), indent=2, ensure_ascii=False))
    elif not args.quiet:
        from .summary import print_summary

        print_summary(scene, out_dir=out_dir)
    return 0


def _add_check_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("grammar", metavar="FILE", help="the .grammar file")
    parser.add_argument("--lot", metavar="LOT",
                        help="a --lot value to check as cga build would read it")
    _add_allow_path(parser)
    parser.add_argument("--quiet", action="store_true", help="print nothing but errors")


def _run_check(args: argparse.Namespace) -> int:
    from .validate import check_file

    problems = check_file(args.grammar, allow_paths=args.allow_paths, lot=args.lot)
    for problem in problems:
        print(problem, file=sys.stderr)
    if problems:
        count = len(problems)
        print(f"{args.grammar}: {count} problem{'s' * (count != 1)}", file=sys.stderr)
        return 2
    if not args.quiet:
        print(f"{args.grammar}: ok")
    return 0


def _whole_number(text: str) -> int:
    """An integer option that may be written as ``1000`` or ``1e6`` (but not ``1.5``)."""
    try:
        return int(text)
    except ValueError:
        pass
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not value.is_integer():
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}")
    return int(value)


def _add_batch_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("grammar", metavar="FILE", help="the .grammar file")
    parser.add_argument("-n", "--count", type=_whole_number, required=True, metavar="N",
                        help="number of seeds to build (1000 or 1e6)")
    _add_allow_path(parser)
    _add_set(parser)
    parser.add_argument("--sweep", metavar="NAME=LO:HI[:STEP]",
                        help="build the seeds once per value of a grammar variable, e.g. "
                             "--sweep difficulty=0:10, into <out>/NAME=VALUE/; the report "
                             "gives each value's mean difficulty metrics (sweep.json)")
    parser.add_argument("--seed-start", type=_whole_number, default=0, metavar="S",
                        help="first seed (default 0)")
    parser.add_argument("--jobs", type=int, metavar="J",
                        help="worker processes (default 1, at most 4 per core); with --engine "
                             "ray the CPUs of the local cluster (default: all), or with "
                             "--address the most builds in flight (default: the cluster's CPUs)")
    parser.add_argument("--time-limit", type=float, metavar="SECONDS",
                        help="stop a build that takes longer and record its seed as failed")
    parser.add_argument("--engine", choices=ENGINES, default="local",
                        help="where builds run: worker processes on this machine (local, the "
                             'default) or a Ray cluster (ray; pip install "cga[ray]")')
    parser.add_argument("--address", metavar="ADDRESS",
                        help="with --engine ray: the running cluster to use (host:6379, "
                             "ray://host:10001, auto); default: start a local one")
    parser.add_argument("--retries", type=int, metavar="N",
                        help="with --engine ray: times a build whose worker died is retried "
                             "before its seed is recorded as failed (default 2)")
    parser.add_argument("--shard", metavar="I/N",
                        help="build only the seeds s with s %% N == I, into "
                             "manifest.shard-I-of-N.jsonl (SLURM: --shard "
                             "$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT); join shards with "
                             "cga batch merge")
    parser.add_argument("--force", action="store_true",
                        help="when the houses in --out were built from other inputs (grammar, "
                             "tables, models, options, version), move them and their manifest "
                             "to --out/superseded-<time>/ and start anew instead of refusing")
    parser.add_argument("--out", metavar="DIR",
                        help="output folder (default out/<grammar name>-batch)")
    parser.add_argument("--no-physics", action="store_true",
                        help="skip the physics and navigability checks")
    parser.add_argument("--export", type=_formats, default=[], metavar="FORMATS",
                        help="extra outputs per seed besides glb and scene JSON, comma "
                             "separated: plan,obj,urdf,sdf,mjcf,usd,map,view,render")
    _add_materials(parser)
    _add_output(parser, "print the batch report (JSON) on stdout")


def _run_batch(args: argparse.Namespace) -> int:
    import json
    from pathlib import Path

    from .batch import run_batch
    from .batch_shard import manifest_name, parse_shard
    from .export import BATCH_FORMATS

    out_dir = Path(args.out) if args.out else Path("out") / f"{Path(args.grammar).stem}-batch"
    options = {"physics": not args.no_physics, "allow_paths": args.allow_paths,
               "formats": list(dict.fromkeys([*BATCH_FORMATS, *args.export])),
               "overrides": _overrides(args)}
    shard = parse_shard(args.shard) if args.shard else None
    if args.materials is not None:
        options["materials"] = args.materials
    kwargs = dict(count=args.count, out_dir=out_dir, jobs=args.jobs, seed_start=args.seed_start,
                  time_limit=args.time_limit, build_options=options, engine=args.engine,
                  address=args.address, retries=args.retries, shard=shard, force=args.force)
    if args.sweep:
        return _run_sweep(args, out_dir, kwargs)
    if args.quiet or args.json:
        report = run_batch(args.grammar, **kwargs)
    else:
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeRemainingColumn

        columns = (*Progress.get_default_columns()[:1], BarColumn(), MofNCompleteColumn(),
                   TimeRemainingColumn())
        with Progress(*columns) as progress:
            task = progress.add_task("building", total=args.count)
            report = run_batch(args.grammar, **kwargs,
                               on_progress=lambda done, total: progress.update(
                                   task, completed=done, total=total))
    data = report.to_dict()
    if args.json:
        print(json.dumps({**data, "out_dir": str(out_dir)}, indent=2))
    elif not args.quiet:
        print(f"{data['seeds']} seeds{f' (shard {shard})' if shard else ''} in {out_dir}: "
              f"{data['houses']} built "
              f"({data['built_now']} now, {data['skipped']} skipped: built before), "
              f"{data['failed']} failed; {data['validity_rate']:.1%} valid, "
              f"{data['placement_rate']:.1%} of items placed, {data['mean_seconds']:.2f} s mean "
              f"(p95 {data['p95_seconds']:.2f} s)")
    if not report.failed:
        return 0
    for failure in data["failed_seeds"]:
        print(f"seed {failure['seed']} failed: {failure['error']}", file=sys.stderr)
    more = len(report.failed) - len(data["failed_seeds"])
    print(f"{len(report.failed)} seed{'s' * (len(report.failed) != 1)} failed"
          f"{f' ({more} not listed)' if more else ''}: see {out_dir / manifest_name(shard)} and "
          f"seed_*/error.txt; a rerun builds them again", file=sys.stderr)
    return 2


def _add_merge_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("folders", nargs="+", metavar="DIR",
                        help="folders holding the shards' manifest.shard-I-of-N.jsonl")
    parser.add_argument("--out", metavar="DIR",
                        help="folder for the merged manifest.jsonl (default: the first DIR); "
                             "house folders stay where they are")
    _add_output(parser, "print what was merged (JSON) on stdout")


def _run_merge(args: argparse.Namespace) -> int:
    import json

    from .batch_merge import merge_manifests

    report = merge_manifests(args.folders, args.out)
    data = report.to_dict()
    if args.json:
        print(json.dumps(data, indent=2))
    elif not args.quiet:
        print(f"{data['seeds']} seeds from {len(data['sources'])} manifests in "
              f"{data['manifest']}: {data['houses']} built, {data['failed']} failed")
    if report.failed:
        print(f"seed{'s' * (len(report.failed) > 1)} "
              f"{', '.join(map(str, report.failed[:20]))}{' …' * (len(report.failed) > 20)} "
              f"failed: a rerun of their shards builds them again", file=sys.stderr)
        return 2
    return 0


def _add_render_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("scene", metavar="FILE",
                        help="a build's <name>.scene.json (its <name>.glb must be beside it)")
    parser.add_argument("--out", metavar="DIR",
                        help="folder to write <name>.render/ into (default: the scene's folder)")
    parser.add_argument("--width", type=int, default=640, metavar="W",
                        help="image width in pixels (default 640)")
    parser.add_argument("--height", type=int, default=480, metavar="H",
                        help="image height in pixels (default 480)")
    parser.add_argument("--fov", type=float, default=90.0, metavar="DEGREES",
                        help="horizontal field of view (default 90)")
    parser.add_argument("--eye-height", type=float, default=1.0, metavar="M",
                        help="camera height above the walking surface in metres (default 1.0)")
    parser.add_argument("--views-per-room", type=int, default=1, metavar="N",
                        help="camera views per room (default 1)")
    parser.add_argument("--robot-radius", type=float, default=0.25, metavar="R",
                        help="cameras stand at least this far from obstacles, in metres, "
                             "where a robot of this radius can drive (default 0.25)")
    _add_output(parser, "print what was written (JSON) on stdout")


def _run_render(args: argparse.Namespace) -> int:
    import json
    import time
    from pathlib import Path

    from .errors import UsageError
    from .export import check_formats
    from .fsutil import atomic_output_dir

    check_formats(["render"])
    from .render.files import render_folder, write_render
    from .render.inputs import inputs_from_files
    from .render.placement import RenderOptions

    try:
        options = RenderOptions(width=args.width, height=args.height, fov=args.fov,
                                eye_height=args.eye_height, views_per_room=args.views_per_room,
                                robot_radius=args.robot_radius)
    except ValueError as error:
        raise UsageError(f"cga render: {error}") from None
    scene = Path(args.scene)
    inputs = inputs_from_files(scene)
    out_dir = Path(args.out) if args.out else scene.parent
    started = time.perf_counter()
    with atomic_output_dir(out_dir, protect=[scene]) as staging:
        written = write_render(inputs, options, staging, inputs.name)
    seconds = time.perf_counter() - started
    folder = out_dir / render_folder(inputs.name)
    views = sum(1 for p in written if p.name.endswith(".camera.json"))
    if args.json:
        print(json.dumps({"folder": str(folder), "views": views, "files": len(written),
                          "seconds": round(seconds, 3)}, indent=2))
    elif not args.quiet:
        print(f"{views} views ({len(written)} files) in {folder}, {seconds:.2f} s")
    return 0


def _run_sweep(args: argparse.Namespace, out_dir: Path, kwargs: dict) -> int:
    """``cga batch --sweep``: one batch per value, then a table of metric means."""
    import json

    from .overrides import parse_sweep
    from .sweep import SWEEP_REPORT, run_sweep, value_text

    name, values = parse_sweep(args.sweep)
    if args.quiet or args.json:
        report = run_sweep(args.grammar, name=name, values=values, **kwargs)
    else:
        from rich.console import Console

        console = Console(stderr=True)
        report = run_sweep(args.grammar, name=name, values=values, **kwargs,
                           on_value=lambda v: console.print(
                               f"{name} = {value_text(v)}: building {args.count} seeds…",
                               highlight=False))
    data = report.to_dict()
    if args.json:
        print(json.dumps({**data, "out_dir": str(out_dir)}, indent=2))
    elif not args.quiet:
        _print_sweep(data, out_dir / SWEEP_REPORT)
    failed = sum(row["failed"] for row in data["values"])
    if failed:
        print(f"{failed} seed{'s' * (failed != 1)} failed: see the manifests under {out_dir}",
              file=sys.stderr)
    return 2 if failed else 0


def _print_sweep(data: dict, path: Path) -> None:
    """One row per metric, one column per value (eleven values fit a terminal; eleven
    metrics as columns would not)."""
    from rich.console import Console
    from rich.table import Table

    rows = data["values"]
    table = Table(title=f"mean difficulty metrics per {data['variable']}")
    table.add_column(data["variable"], justify="left", no_wrap=True)
    for row in rows:
        table.add_column(f"{row['value']:g}", justify="right", no_wrap=True)
    table.add_row("built", *(str(row["houses"]) for row in rows))
    for metric in data["metrics"]:
        table.add_row(metric.replace("_", " "),
                      *("—" if row[metric] is None else f"{row[metric]:.3g}" for row in rows))
    console = Console()
    if not console.is_terminal:  # a file or a pipe: no terminal width to squeeze into
        console = Console(width=160)
    console.print(table)
    console.print(f"written to {path}", highlight=False)


COMMANDS: dict[str, tuple[str, Callable[[argparse.ArgumentParser], None],
                          Callable[[argparse.Namespace], int]]] = {
    "build": ("derive, check and export a building", _add_build_arguments, _run_build),
    "check": ("check a grammar without building it", _add_check_arguments, _run_check),
    "batch": ("build many seeds into one folder each, with a manifest (resumable); "
              "cga batch merge DIR... joins the manifests of shards",
              _add_batch_arguments, _run_batch),
    "render": ("render camera views, depth, semantic and instance masks of a build",
               _add_render_arguments, _run_render),
}
"""Subcommand name → (help, add_arguments, run)."""


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="cga", description="Shape-grammar building generator.",
        epilog="Exit status: 0 success, 2 an error in the input (grammar, rule table, "
               "option, missing file) or, for batch, any seed that failed; 128 + N when "
               "stopped by signal N (130 for Ctrl-C).")
    parser.add_argument("--version", action="version", version=f"cga {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, (help_text, add_arguments, run) in COMMANDS.items():
        sub = commands.add_parser(name, help=help_text, description=help_text)
        add_arguments(sub)
        sub.set_defaults(run=run)
    return parser


def _merge_parser() -> argparse.ArgumentParser:
    description = ("join the manifests of a sharded batch (cga batch --shard I/N) into one "
                   "manifest.jsonl, checking for missing shards, duplicate seeds and gaps")
    parser = argparse.ArgumentParser(prog="cga batch merge", description=description)
    _add_merge_arguments(parser)
    parser.set_defaults(run=_run_merge)
    return parser


_MAX_LINE = 1_000
"""Longest line of an error message printed; messages quote short excerpts of inputs
(:func:`cga.errors.excerpt`) and this is the last guard for any that does not."""


def _bounded(message: str) -> str:
    """``message`` with control characters (but line ends) escaped and lines cut at
    :data:`_MAX_LINE` characters, so no input can flood or drive the terminal."""
    lines = []
    for line in message.split("\n"):
        line = "".join(ch if ch.isprintable() else repr(ch)[1:-1] for ch in line)
        lines.append(line if len(line) <= _MAX_LINE else line[:_MAX_LINE] + "…")
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status.

    Parameters
    ----------
    argv:
        Arguments without the program name (default: ``sys.argv[1:]``).
    """
    from .collector import tune_for_building
    from .interrupts import Terminated, handle_termination
    from .threads import one_blas_thread

    one_blas_thread()  # before anything imports numpy
    tune_for_building()
    arguments = list(sys.argv[1:] if argv is None else argv)
    if arguments[:2] == ["batch", "merge"]:  # a command of batch, not a grammar named merge
        args = _merge_parser().parse_args(arguments[2:])
    else:
        args = _parser().parse_args(arguments)
    try:
        with handle_termination():
            return args.run(args)
    except CGAError as error:
        print(_bounded(error.report()), file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except Terminated as signal:
        print(f"terminated ({signal.name})", file=sys.stderr)
        return signal.exit_status

