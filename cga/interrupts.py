"""Catchable termination signals become exceptions, so every ``finally`` cleans up.

By default SIGTERM and SIGHUP end a Python process at once: ``finally`` blocks do not
run, and a build or batch killed that way left its staging folder behind (issue 19,
defect 6). :func:`handle_termination` (installed by the command line, never by the
library on import) turns them into :class:`Terminated`, which unwinds like Ctrl-C's
:class:`KeyboardInterrupt`.

A few steps must not be cut in half by a signal: moving a build's staged files into
the output folder and updating its record of written files. They run inside
:func:`deferred`; a signal arriving then is remembered and raised when the block ends.
SIGKILL cannot be caught; what it leaves behind is found by the next run
(:func:`cga.fsutil.remove_stale_staging`).
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from types import FrameType
from typing import Any

__all__ = ["Terminated", "TERMINATION_SIGNALS", "handle_termination", "deferred"]

TERMINATION_SIGNALS = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP")
                            if hasattr(signal, name))
"""The signals a terminal, a scheduler or ``kill`` sends to stop a process politely."""


class Terminated(BaseException):
    """The process received SIGTERM or SIGHUP (a ``BaseException``, like KeyboardInterrupt,
    so ``except Exception`` handlers do not swallow it)."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum

    @property
    def name(self) -> str:
        return signal.Signals(self.signum).name

    @property
    def exit_status(self) -> int:
        """The shell convention for death by a signal: 128 + its number."""
        return 128 + self.signum


_state = threading.local()


def _pending() -> list[int]:
    if not hasattr(_state, "pending"):
        _state.depth = 0
        _state.pending = []
    pending: list[int] = _state.pending
    return pending


def _raise_for(signum: int) -> None:
    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise Terminated(signum)


def _handler(signum: int, frame: FrameType | None) -> None:
    pending = _pending()
    if _state.depth > 0:
        pending.append(signum)
        return
    _raise_for(signum)


@contextlib.contextmanager
def handle_termination() -> Iterator[None]:
    """Install the handlers for the duration of a command (main thread only), then
    restore the previous ones."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous: dict[int, Any] = {}
    for signum in TERMINATION_SIGNALS:
        previous[signum] = signal.signal(signum, _handler)
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


@contextlib.contextmanager
def deferred() -> Iterator[None]:
    """Hold back termination signals while the block runs; raise the first one after it.

    Only signals that reach the handlers of :func:`handle_termination` can be held
    back; without them installed (the library used from Python) this does nothing.
    """
    pending = _pending()
    _state.depth += 1
    try:
        yield
    finally:
        _state.depth -= 1
        if _state.depth == 0 and pending:
            signum = pending[0]
            pending.clear()
            _raise_for(signum)
