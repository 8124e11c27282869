"""A fixed reference workload, timed in the same run as a benchmark, to normalise its figures.

The machine the benchmarks run on is shared: the CPU time of the same code moves with
the load (cache and frequency contention from the other core). A figure divided by the
CPU time of a fixed pure-Python loop measured in the same process, interleaved with the
benchmark, moves much less, so ratios compare across runs made on different days or
loads where raw milliseconds do not.

    from reference import ReferenceClock
    clock = ReferenceClock()
    ...  # call clock.sample() now and then while the benchmark runs
    print(clock.describe(), clock.ratio(seconds))

The loop is interpreter work (integer and float arithmetic, list indexing, a dict, calls):
the mix a layout or typing step spends its time in. Do not change it, or ratios measured
before the change no longer compare.
"""

from __future__ import annotations

import statistics
import time

__all__ = ["REFERENCE_ITERATIONS", "ReferenceClock", "reference_loop"]

REFERENCE_ITERATIONS = 20_000
"""Iterations of :func:`reference_loop`: about 4 ms of CPU on the benchmark machine."""


def _step(value: float, index: int) -> float:
    return value * 0.999 + index % 7


def reference_loop(iterations: int = REFERENCE_ITERATIONS) -> float:
    """The fixed workload; returns a value so the work cannot be skipped."""
    table: dict[int, float] = {}
    values = [float(i) for i in range(64)]
    total = 0.0
    for i in range(iterations):
        j = i & 63
        values[j] = _step(values[j], i)
        table[j] = table.get(j, 0.0) + values[j]
        total += values[(j * 7) & 63] - table[j] * 1e-9
    return total


def _cpu_seconds(iterations: int) -> float:
    start = time.process_time()
    reference_loop(iterations)
    return time.process_time() - start


class ReferenceClock:
    """CPU times of the reference loop, sampled during a benchmark.

    ``sample`` runs the loop once; call it between the timed items (every few seeds) so the
    reference sees the same load as the figures. ``seconds`` is the median of the samples.
    """

    def __init__(self, iterations: int = REFERENCE_ITERATIONS, warmup: int = 3) -> None:
        self.iterations = iterations
        self.samples: list[float] = []
        for _ in range(warmup):
            _cpu_seconds(iterations)

    def sample(self) -> float:
        """Time the loop once (CPU seconds) and keep the sample."""
        seconds = _cpu_seconds(self.iterations)
        self.samples.append(seconds)
        return seconds

    @property
    def seconds(self) -> float:
        """Median CPU seconds of one reference loop (one sample is taken if none was)."""
        if not self.samples:
            self.sample()
        return statistics.median(self.samples)

    def ratio(self, seconds: float) -> float:
        """``seconds`` in reference loops."""
        return seconds / self.seconds

    def describe(self) -> str:
        """One line for a report: the loop's median CPU time and the spread of samples."""
        ordered = sorted(self.samples) or [self.seconds]
        return (f"reference loop ({self.iterations:,} iterations): median "
                f"{self.seconds * 1e3:.2f} ms CPU over {len(ordered)} samples "
                f"(min {ordered[0] * 1e3:.2f}, max {ordered[-1] * 1e3:.2f})")
