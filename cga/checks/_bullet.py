"""pybullet sessions for the checks: a quiet import and a DIRECT client that always closes.

pybullet prints its build time when imported and V-HACD writes progress straight to the
process's standard output from C++; neither belongs in a build summary or a CLI pipe.
:func:`quiet_output` silences both file descriptors 1 and 2 for the duration of a call.
:func:`direct_client` opens a headless physics server of its own (never the GUI), so two
checks, or a check and a user's own simulation, never share state.

Convex parts reach pybullet as Wavefront OBJ text with one object per part: loaded as a
``GEOM_MESH``, each object becomes one convex hull of a compound shape (the format V-HACD
writes too). :func:`obj_text` and :func:`obj_objects` write and read that format.
"""

from __future__ import annotations

import contextlib
import importlib
import os
import sys
from collections.abc import Iterator
from collections.abc import Sequence
from types import ModuleType
from typing import Any

import numpy as np

from cga.mesh import MeshLike

__all__ = ["quiet_output", "pybullet", "direct_client", "obj_text", "obj_objects"]


@contextlib.contextmanager
def quiet_output() -> Iterator[None]:
    """Send everything written to file descriptors 1 and 2 to ``os.devnull`` meanwhile."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(AttributeError, ValueError):
            stream.flush()
    saved = [os.dup(fd) for fd in (1, 2)]
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        for fd in (1, 2):
            os.dup2(devnull, fd)
        yield
    finally:
        for fd, copy in zip((1, 2), saved):
            os.dup2(copy, fd)
            os.close(copy)
        os.close(devnull)


def pybullet() -> ModuleType:
    """The ``pybullet`` module, imported without its build-time banner."""
    module = sys.modules.get("pybullet")
    if module is None:
        with quiet_output():  # imported on first use, quietly
            module = importlib.import_module("pybullet")
    return module


@contextlib.contextmanager
def direct_client() -> Iterator[tuple[ModuleType, int]]:
    """A fresh pybullet DIRECT server: yields ``(pybullet, client_id)``, disconnects after."""
    pb = pybullet()
    client = pb.connect(pb.DIRECT)
    if client < 0:
        raise RuntimeError("pybullet could not start a DIRECT physics server")
    try:
        yield pb, client
    finally:
        pb.disconnect(physicsClientId=client)




def obj_text(meshes: Sequence[MeshLike], *, offset: Sequence[float] = (0.0, 0.0, 0.0)) -> str:
    """OBJ text with one object (``o partN``) per mesh, vertices moved by ``-offset``
    (written to the nanometre)."""
    chunks: list[str] = []
    base = 1
    shift = np.asarray(offset, dtype=float)
    for number, mesh in enumerate(meshes):
        vertices = np.asarray(mesh.vertices, dtype=float) - shift
        faces = np.asarray(mesh.faces, dtype=np.int64) + base
        chunks.append(f"o part{number}\n")
        chunks.append(("v %.9f %.9f %.9f\n" * len(vertices)) % tuple(vertices.ravel()))
        chunks.append(("f %d %d %d\n" * len(faces)) % tuple(faces.ravel().tolist()))
        base += len(vertices)
    return "".join(chunks)


def obj_objects(text: str) -> list[np.ndarray]:
    """The vertex positions of each object (``o``) of OBJ text, in file order.

    Only ``o`` and ``v`` lines matter: the callers rebuild each object as a convex hull.
    Vertices before the first ``o`` line form an object of their own.
    """
    objects: list[list[list[float]]] = [[]]
    for line in text.splitlines():
        if line.startswith("o "):
            objects.append([])
        elif line.startswith("v "):
            objects[-1].append([float(t) for t in line.split()[1:4]])
    return [np.asarray(o, dtype=float) for o in objects if o]
