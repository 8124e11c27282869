"""Run a function in a forked child with a time limit and a memory limit.

A hang inside GEOS, numpy or pybullet cannot be interrupted by a Python signal, and a
runaway allocation can take the whole machine down with the test run; a forked child
can simply be killed. The child inherits everything the parent has imported and
loaded (warm caches), so a call costs a fork, not a fresh interpreter.

``run_forked(function, *args)`` returns ``("ok", value)`` with the function's (picklable)
result, ``("bug", traceback)`` when it raised, or ``("timeout", None)`` when it did not
finish in time. Memory is limited with ``resource.setrlimit(RLIMIT_AS)`` in the child:
the address space it already shares with the parent plus ``memory_limit`` bytes, so an
allocation past the limit fails as ``MemoryError`` in the child (reported as a bug)
instead of swapping.
"""

from __future__ import annotations

import multiprocessing
import resource
import traceback
from collections.abc import Callable
from typing import Any

__all__ = ["GIB", "run_forked"]

GIB = 1 << 30


def _address_space() -> int:
    """Bytes of virtual memory this process uses now (Linux ``/proc/self/statm``)."""
    try:
        with open("/proc/self/statm", encoding="ascii") as statm:
            pages = int(statm.read().split()[0])
        return pages * resource.getpagesize()
    except (OSError, ValueError, IndexError):
        return 0


def _child(connection: Any, memory_limit: int | None, function: Callable[..., Any],
           args: tuple[Any, ...]) -> None:
    if memory_limit is not None:
        limit = _address_space() + memory_limit
        _, hard = resource.getrlimit(resource.RLIMIT_AS)
        if hard != resource.RLIM_INFINITY:
            limit = min(limit, hard)
        resource.setrlimit(resource.RLIMIT_AS, (limit, hard))
    try:
        outcome: tuple[str, Any] = ("ok", function(*args))
    except BaseException:  # the property under test: report anything, never crash
        outcome = ("bug", traceback.format_exc())
    try:
        connection.send(outcome)
    finally:
        connection.close()


def run_forked(function: Callable[..., Any], *args: Any, time_limit: float = 30.0,
               memory_limit: int | None = 2 * GIB) -> tuple[str, Any]:
    """``function(*args)`` in a forked child; see the module docstring for the outcome."""
    context = multiprocessing.get_context("fork")
    receive, send = context.Pipe(duplex=False)
    process = context.Process(target=_child, args=(send, memory_limit, function, args))
    process.start()
    send.close()
    try:
        if not receive.poll(time_limit):
            return ("timeout", None)
        try:
            return receive.recv()
        except EOFError:  # the child died without reporting (killed by the OS)
            return ("bug", f"the child exited with status {process.exitcode} without a result")
    finally:
        process.kill()
        process.join()
        receive.close()
