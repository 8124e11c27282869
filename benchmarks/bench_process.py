"""Whole-process CPU time of the ``cga`` commands, as a user pays it.

Each case runs ``python -m cga ...`` as a child process and takes its CPU time (user +
system, from ``resource.getrusage(RUSAGE_CHILDREN)``): imports, the on-disk caches'
reads, the build and the writing of every file. Cases are interleaved (one run of
each, then the next round) so the machine's load falls on all of them alike; one
untimed round first fills the on-disk caches (the parser and the model library), as
any second build on a machine finds them, and Python's bytecode caches (``__pycache__``,
written even when ``PYTHONDONTWRITEBYTECODE`` is set, as an installed package has them:
without them every run compiles the modules it imports, about 0.1 s). The table gives the minimum and median CPU
seconds and the median as a multiple of the reference loop (``benchmarks/reference.py``)
timed in the same run.

    python benchmarks/bench_process.py [--repeats 5] [--cases help,check,build,...]
                                       [--src DIR]

``--src`` times another checkout (e.g. an export of an older commit) with the same
harness, for before/after figures.

Targets (CPU, medians): ``build`` ≤ 1.2 s, ``build-no-physics`` ≤ 0.8 s, ``check`` ≤ 0.3 s,
``storeys-20`` ≤ 12 × ``storeys-1``.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from reference import ReferenceClock  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
HOUSE = "demos/house.grammar"
CASES: dict[str, tuple[list[str], float | None]] = {
    "help": (["--help"], None),
    "check": (["check", HOUSE], 0.3),
    "build": (["build", HOUSE, "--quiet"], 1.2),
    "build-no-physics": (["build", HOUSE, "--quiet", "--no-physics"], 0.8),
    "storeys-1": (["build", HOUSE, "--quiet", "--set", "buildingHeight=3"], None),
    "storeys-20": (["build", HOUSE, "--quiet", "--set", "buildingHeight=60"], None),
}
"""Case name → (arguments of ``python -m cga``, CPU target in seconds or None).
``build`` writes ``cga build``'s default files (glb, scene JSON, plans) with the checks."""
DEFAULT_CASES = "help,check,build,build-no-physics,storeys-1,storeys-20"


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_case(args: list[str], src: Path, out: Path) -> float:
    """CPU seconds of one ``python -m cga`` process (fails loudly on a non-zero exit)."""
    command = [sys.executable, "-m", "cga", *args]
    if args[0] == "build":
        command += ["--out", str(out)]
    env = dict(os.environ, PYTHONPATH=str(src))
    env.pop("PYTHONDONTWRITEBYTECODE", None)  # an installed cga has its bytecode compiled
    before = _children_cpu()
    subprocess.run(command, cwd=src, env=env, check=True, stdout=subprocess.DEVNULL)
    return _children_cpu() - before


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--cases", default=DEFAULT_CASES,
                        help=f"comma-separated, of {', '.join(CASES)}")
    parser.add_argument("--src", type=Path, default=ROOT,
                        help="the checkout to time (default: this one)")
    options = parser.parse_args()
    names = [n.strip() for n in options.cases.split(",") if n.strip()]
    unknown = [n for n in names if n not in CASES]
    if unknown:
        parser.error(f"unknown case(s) {', '.join(unknown)}; known: {', '.join(CASES)}")
    src = options.src.resolve()
    times: dict[str, list[float]] = {n: [] for n in names}
    clock = ReferenceClock()
    for _ in range(10):
        clock.sample()
    with tempfile.TemporaryDirectory(prefix="cga-process-bench-") as tmp:
        out = Path(tmp)
        for name in names:  # warm-up round: fills the on-disk caches
            run_case(CASES[name][0], src, out / name)
        for _ in range(options.repeats):
            for name in names:
                times[name].append(run_case(CASES[name][0], src, out / name))
            for _ in range(10):  # the reference sees the same load as the cases
                clock.sample()
    reference = clock.seconds
    print(f"Whole-process CPU, {options.repeats} interleaved runs per case ({src}); "
          f"{clock.describe()}\n")
    print("| case | min s | median s | median / ref | target | verdict |")
    print("|---|---:|---:|---:|---:|---|")
    for name in names:
        median, target = statistics.median(times[name]), CASES[name][1]
        verdict = "" if target is None else ("met" if median <= target else "not met")
        print(f"| {name} | {min(times[name]):.3f} | {median:.3f} | {median / reference:,.0f} "
              f"| {'' if target is None else f'≤ {target} s'} | {verdict} |")
    if "storeys-1" in times and "storeys-20" in times:
        growth = statistics.median(times["storeys-20"]) / statistics.median(times["storeys-1"])
        print(f"\n20 storeys / 1 storey: {growth:.1f}× (target ≤ 12×: "
              f"{'met' if growth <= 12 else 'not met'})")


if __name__ == "__main__":
    main()
