"""BLAS threads for a process that builds: one.

numpy's and SciPy's wheels link OpenBLAS, which starts a thread per core when it loads
and lets idle threads spin before they sleep. A build multiplies only 3 × 3 and 4 × 4
matrices and short vectors, where those threads never help, but their start and spin
cost CPU: 0.08 s of the 0.17 s that importing numpy costs on a 2-core machine, about
0.1 s of a whole ``cga build`` and a quarter of ``cga check`` (issue 21's measurements).
A batch's workers, one per core, would each also start a pool, so threads outnumber
cores.

The limit must be in the environment before numpy loads, so the command line sets it
first thing (:func:`one_blas_thread`), and batch workers inherit it. A variable the user
set is kept; a program that imports cga as a library keeps its own settings.

manifold3d (walls with openings, the grid checks' shadows, views) runs its algorithms in
a oneTBB task arena as wide as the CPUs the process may use. A building's solids are a few
dozen triangles, so the second thread only waits, spinning, while the first works: it
doubled manifold3d's CPU time (11.5 ms of CPU for 5.6 ms of wall time per batch house)
and, in a batch with a worker per core, spun on the core of the other worker.
:func:`first_use_on_one_cpu` makes its first use with the thread pinned to one CPU, and
oneTBB sizes its arena once, from that mask; :mod:`cga.manifold` does it on import.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import TypeVar

__all__ = ["BLAS_THREAD_VARIABLES", "first_use_on_one_cpu", "one_blas_thread"]

_T = TypeVar("_T")

BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
"""The variables that size the thread pools of the BLAS libraries numpy and SciPy use
(OpenBLAS in their wheels, MKL in some distributions)."""


def one_blas_thread() -> None:
    """Ask the BLAS libraries for one thread each, unless the environment already says
    otherwise; effective only before numpy is first imported."""
    for name in BLAS_THREAD_VARIABLES:
        os.environ.setdefault(name, "1")


def first_use_on_one_cpu(first_use: Callable[[], _T]) -> _T:
    """Run ``first_use`` with the calling thread allowed one CPU, then allow it the CPUs
    it had: a thread pool that is sized from the CPUs the thread may use when it first
    runs (oneTBB's) then has no worker threads. Where a thread's CPUs cannot be set (not
    Linux, or refused), ``first_use`` just runs."""
    try:
        allowed = os.sched_getaffinity(0)
        if len(allowed) > 1:
            os.sched_setaffinity(0, {min(allowed)})
    except (AttributeError, OSError):
        return first_use()
    try:
        return first_use()
    finally:
        if len(allowed) > 1:
            os.sched_setaffinity(0, allowed)
