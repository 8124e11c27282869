"""Batch engines compared: ``run_batch`` with the local process pool and with Ray.

Each repeat builds ``-n`` fresh seeds of the house (no physics, ``cga batch``'s files)
with ``--jobs`` workers, once per engine:

* **local**: :class:`cga.batch_engine.LocalEngine`, worker processes started and stopped
  by the batch (their start-up is in the figures);
* **ray**: a local Ray cluster of ``--jobs`` CPUs, started before the measured batch
  and warmed up by a batch of ``--jobs`` seeds (its workers have imported cga), so the
  figures are the per-house throughput once a cluster runs; the cluster's start-up
  (``ray.init`` to ready, and ``ray.shutdown``) is timed separately.

CPU seconds count every process involved: this one, the local pool's workers (reaped,
``RUSAGE_CHILDREN``) and, for Ray, every process of the cluster (``/proc``: the
raylet, the GCS and the workers, sampled before and after the batch). The machine's
other load stretches the wall clock, so "houses/s on idle cores" is houses / (CPU
seconds / jobs), the throughput the engine allows with its cores to itself.

    python benchmarks/bench_batch_engines.py [-n 100] [--jobs 2] [--repeats 2]

Target: Ray within 15 % of the local engine (houses/s on idle cores).
"""

from __future__ import annotations

import argparse
import logging
import os
import resource
import statistics
import tempfile
import time
from pathlib import Path

from cga.batch import BatchReport, run_batch
from cga.export import BATCH_FORMATS

ROOT = Path(__file__).resolve().parents[1]
TARGET_RATIO = 0.85
OPTIONS = {"physics": False, "formats": list(BATCH_FORMATS)}


def _own_cpu() -> float:
    """CPU seconds of this process and of its reaped children."""
    own, children = (resource.getrusage(who) for who in
                     (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def _descendants_cpu() -> float:
    """CPU seconds of the live descendants of this process (and their reaped children)."""
    parents: dict[int, int] = {}
    times: dict[int, float] = {}
    tick = os.sysconf("SC_CLK_TCK")
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        parents[int(entry.name)] = int(fields[1])
        times[int(entry.name)] = sum(int(f) for f in fields[11:15]) / tick
    mine, frontier = set(), {os.getpid()}
    while frontier:
        frontier = {pid for pid, parent in parents.items() if parent in frontier} - mine
        mine |= frontier
    return sum(times[pid] for pid in mine)


def _batch(grammar: Path, count: int, jobs: int, engine: str, seed_start: int = 0
           ) -> BatchReport:
    with tempfile.TemporaryDirectory(prefix="cga-engines-bench-") as out:
        return run_batch(grammar, count=count, out_dir=out, jobs=jobs, engine=engine,
                         seed_start=seed_start, build_options=OPTIONS)


def local_run(grammar: Path, count: int, jobs: int) -> tuple[BatchReport, float]:
    cpu = _own_cpu()
    report = _batch(grammar, count, jobs, "local")
    return report, _own_cpu() - cpu


def ray_run(grammar: Path, count: int, jobs: int) -> tuple[BatchReport, float, float]:
    """The measured batch on a running, warmed-up cluster; its CPU seconds; the wall
    seconds of starting and stopping the cluster."""
    import ray

    started = time.perf_counter()
    ray.init(num_cpus=jobs, include_dashboard=False, log_to_driver=False,
             logging_level=logging.ERROR)
    startup_wall = time.perf_counter() - started
    try:
        _batch(grammar, jobs, jobs, "ray", seed_start=10**6)  # workers import cga
        before = _own_cpu() + _descendants_cpu()
        report = _batch(grammar, count, jobs, "ray")
        cpu = _own_cpu() + _descendants_cpu() - before
    finally:
        stop = time.perf_counter()
        ray.shutdown()
        startup_wall += time.perf_counter() - stop
    return report, cpu, startup_wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", "--count", type=int, default=100)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--grammar", type=Path, default=ROOT / "demos" / "house.grammar")
    args = parser.parse_args()

    print(f"## run_batch({args.grammar.name}, -n {args.count}, jobs={args.jobs}, no physics)\n")
    print("| engine | houses | wall s | houses/s | CPU s | houses/s on idle cores | "
          "mean s / house | failed |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    rates: dict[str, list[float]] = {"local": [], "ray": []}
    walls: dict[str, list[float]] = {"local": [], "ray": []}
    startups = []
    for _ in range(args.repeats):
        runs = [("local", *local_run(args.grammar, args.count, args.jobs))]
        report, cpu, startup_wall = ray_run(args.grammar, args.count, args.jobs)
        runs.append(("ray", report, cpu))
        startups.append(startup_wall)
        for engine, report, cpu in runs:
            idle = report.built_now / (cpu / args.jobs)
            rates[engine].append(idle)
            walls[engine].append(report.houses_per_second)
            print(f"| {engine} | {report.built_now} | {report.wall_seconds:.1f} | "
                  f"{report.houses_per_second:.2f} | {cpu:.1f} | {idle:.2f} | "
                  f"{report.mean_seconds:.3f} | {len(report.failed)} |")
    print()
    print(f"Ray cluster start + stop (ray.init of {args.jobs} CPUs and ray.shutdown, the "
          f"warm-up batch excluded): median {statistics.median(startups):.1f} s wall")
    ratio = statistics.median(rates["ray"]) / statistics.median(rates["local"])
    wall_ratio = statistics.median(walls["ray"]) / statistics.median(walls["local"])
    print(f"ray / local, houses/s on idle cores (median): {ratio:.2f}; wall clock: "
          f"{wall_ratio:.2f}; target ≥ {TARGET_RATIO:g}: "
          f"{'met' if ratio >= TARGET_RATIO else 'NOT met'}")


if __name__ == "__main__":
    main()
