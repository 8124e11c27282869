"""Batch throughput: ``run_batch`` on the house demo, without and with the checks.

Each run builds ``-n`` fresh seeds into a new temporary folder (nothing to resume) with
the options ``cga batch`` uses (the default files: glb and scene JSON; ``--formats``
changes them), in ``--jobs`` worker processes. The table gives, per run, the wall time, houses per second and the
batch report (validity and furniture placement rates, mean and p95 seconds per house);
with ``--repeats`` > 1 the minimum and median houses/s follow. The machine's other load
slows the wall clock, so the CPU seconds of the run (this process and its workers) are
given too, with the throughput they allow: houses / (CPU seconds / jobs), the rate of
``--jobs`` otherwise idle cores.

    python benchmarks/bench_batch.py [-n 100] [--physics-n 20] [--jobs 2] [--repeats 1]
                                     [--modes no-physics,physics] [--grammar FILE]
                                     [--formats glb,json,plan]

Target (2 cores): ``-n 100 --jobs 2 --no-physics`` at ≥ 5 houses/s. The dataset figure
in RESULTS.md is ``--modes physics --physics-n 200``.
"""

from __future__ import annotations

import argparse
import resource
import statistics
import sys
import tempfile
from pathlib import Path

from cga.batch import BatchReport, run_batch
from cga.export import BATCH_FORMATS

sys.path.insert(0, str(Path(__file__).resolve().parent))
from reference import ReferenceClock  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
TARGET_HOUSES_PER_SECOND = 5.0
TARGET_CPU_PER_HOUSE = {"no-physics": 0.15, "physics": 0.4}
"""CPU seconds per house (workers and this process; issue 21)."""
MODES = {"no-physics": False, "physics": True}
"""Mode name → whether the physics and navigability checks run."""


def _cpu_seconds() -> float:
    """CPU time (user + system) of this process and of its finished worker processes."""
    own, workers = (resource.getrusage(who) for who in
                    (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
    return own.ru_utime + own.ru_stime + workers.ru_utime + workers.ru_stime


def _compile_bytecode() -> None:
    """Write the bytecode of cga's modules, as an installed cga has it: the workers are
    fresh interpreters, and without it each compiles every module it imports (about
    0.1 s a worker, every run when ``PYTHONDONTWRITEBYTECODE`` is set)."""
    import compileall

    import cga
    import cga.operations

    for package in (cga, cga.operations):
        compileall.compile_dir(Path(package.__file__).parent, quiet=1)


def one_run(grammar: Path, count: int, jobs: int, physics: bool, formats: list[str]
            ) -> tuple[BatchReport, float]:
    """A fresh batch of ``count`` seeds (0 .. count-1) in a temporary folder, and the CPU
    seconds it took (the worker pool is shut down, so its children are counted, when
    ``run_batch`` returns)."""
    with tempfile.TemporaryDirectory(prefix="cga-batch-bench-") as out:
        cpu = _cpu_seconds()
        report = run_batch(grammar, count=count, out_dir=out, jobs=jobs,
                           build_options={"physics": physics, "formats": formats})
        return report, _cpu_seconds() - cpu


def _failures(report: BatchReport) -> str:
    """Invalid houses counted by failed check, with their seeds (first ten)."""
    failed: dict[str, list[int]] = {}
    for record in report.records:
        if record.error is not None:
            failed.setdefault("error", []).append(record.seed)
        for check, passed in sorted(record.checks.items()):
            if not passed:
                failed.setdefault(check, []).append(record.seed)
    if not failed:
        return "none"
    return "; ".join(f"{check} {len(seeds)} (seeds {', '.join(map(str, seeds[:10]))}"
                     f"{', ...' if len(seeds) > 10 else ''})" for check, seeds in failed.items())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", "--count", type=int, default=100,
                        help="houses per run without physics")
    parser.add_argument("--physics-n", type=int, default=20, help="houses per run with physics")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--modes", default=",".join(MODES),
                        help=f"comma-separated: {', '.join(MODES)}")
    parser.add_argument("--grammar", type=Path, default=ROOT / "demos" / "house.grammar")
    parser.add_argument("--formats", default=",".join(BATCH_FORMATS),
                        help="files per house, comma-separated (default: as cga batch)")
    args = parser.parse_args()
    modes = [m.strip() for m in args.modes.split(",") if m.strip()]
    formats = [f.strip() for f in args.formats.split(",") if f.strip()]
    if any(m not in MODES for m in modes) or args.repeats < 1:
        parser.error(f"--modes takes {', '.join(MODES)}; --repeats must be ≥ 1")

    print(f"## run_batch({args.grammar.name}, jobs={args.jobs}, files: {', '.join(formats)})\n")
    _compile_bytecode()
    clock = ReferenceClock()
    print("| mode | houses | wall s | houses/s | CPU s | CPU s / house | / ref | "
          "houses/s on idle cores | valid | placed | mean s | p95 s | errors |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    per_house: dict[str, list[float]] = {}
    rates: dict[str, list[float]] = {}
    failures: list[str] = []
    for mode in modes:
        count = args.count if mode == "no-physics" else args.physics_n
        for _ in range(args.repeats):
            for _ in range(10):
                clock.sample()
            report, cpu = one_run(args.grammar, count, args.jobs, MODES[mode], formats)
            for _ in range(10):
                clock.sample()
            data = report.to_dict()
            rates.setdefault(mode, []).append(report.houses_per_second)
            house_cpu = cpu / max(report.built_now, 1)
            per_house.setdefault(mode, []).append(house_cpu)
            print(f"| {mode} | {report.count} | {report.wall_seconds:.1f} | "
                  f"{report.houses_per_second:.2f} | {cpu:.1f} | {house_cpu:.3f} | "
                  f"{clock.ratio(house_cpu):,.0f} | "
                  f"{report.built_now / (cpu / args.jobs):.2f} | {data['validity_rate']:.1%} | "
                  f"{data['placement_rate']:.1%} | {report.mean_seconds:.3f} | "
                  f"{report.p95_seconds:.3f} | {data['errors']} |")
            failures.append(f"{mode}, {report.count} houses: {_failures(report)}")
    print()
    print(clock.describe())
    for mode, values in per_house.items():
        median = statistics.median(values)
        print(f"{mode}: CPU per house median {median:.3f} s ({clock.ratio(median):,.0f} × ref); "
              f"target ≤ {TARGET_CPU_PER_HOUSE[mode]} s: "
              f"{'met' if median <= TARGET_CPU_PER_HOUSE[mode] else 'not met'}")
    print()
    print("Invalid houses by failed check:")
    for line in failures:
        print(f"- {line}")
    print()
    for mode, values in rates.items():
        line = (f"{mode}: houses/s min {min(values):.2f}, median {statistics.median(values):.2f} "
                f"over {len(values)} run{'s' * (len(values) != 1)}")
        if mode == "no-physics":
            best = statistics.median(values)
            line += (f"; target ≥ {TARGET_HOUSES_PER_SECOND:g}/s: "
                     f"{'met' if best >= TARGET_HOUSES_PER_SECOND else 'NOT met'}")
        print(line)


if __name__ == "__main__":
    main()
