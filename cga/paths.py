"""Real paths and which folder a file lies in, compared by their text.

The sandbox asks whether each file a build reads lies in an allowed folder, and the
provenance of a batch house names each file below its folder: some thirty files a
house. On real paths (absolute, normalised, links resolved) those questions are text
comparisons, which is what ``pathlib`` compares part by part at several times the cost.
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["is_below", "real_path", "relative_text"]


def real_path(path: str | Path) -> Path:
    """``path`` absolute with every symbolic link and ``..`` resolved (never raises on loops)."""
    return Path(os.path.realpath(os.path.abspath(path)))


def is_below(path: str | Path, root: str | Path) -> bool:
    """Whether ``path`` is ``root`` or lies below it; both are real paths (absolute and
    normalised, :func:`real_path`), so this compares their text, which is what
    ``root in path.parents`` compares part by part, at a fraction of the cost (a build
    asks for every model file it loads, and names each in its provenance)."""
    text, top = str(path), str(root)
    return text == top or text.startswith(top if top.endswith(os.sep) else top + os.sep)


def relative_text(real: str, folder: str) -> str:
    """The path of ``real`` below ``folder`` (real paths, :func:`is_below`), as
    ``Path(real).relative_to(folder).as_posix()`` gives it."""
    rest = real[len(folder):].lstrip(os.sep)
    return rest.replace(os.sep, "/") if rest else "."
