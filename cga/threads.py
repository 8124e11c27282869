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
"""

from __future__ import annotations

import os

__all__ = ["BLAS_THREAD_VARIABLES", "one_blas_thread"]

BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
"""The variables that size the thread pools of the BLAS libraries numpy and SciPy use
(OpenBLAS in their wheels, MKL in some distributions)."""


def one_blas_thread() -> None:
    """Ask the BLAS libraries for one thread each, unless the environment already says
    otherwise; effective only before numpy is first imported."""
    for name in BLAS_THREAD_VARIABLES:
        os.environ.setdefault(name, "1")
