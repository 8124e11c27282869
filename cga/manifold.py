"""manifold3d as cga uses it: import it from here (``from cga.manifold import manifold3d``).

Importing this module makes manifold3d's first operation on one CPU
(:func:`cga.threads.first_use_on_one_cpu`), so its oneTBB task arena is one thread wide
and it computes on the calling thread only: a building's solids are too small for a
second thread to help, and its spinning cost as much CPU as the work (``cga/threads.py``).
Every build's meshes are the same either way: the threads only share out the work.

This holds for the whole process, and only if no other code ran a manifold3d operation
first: a program that imports cga as a library and meshes large solids with manifold3d
itself gets them computed on one thread too.
"""

from __future__ import annotations

import manifold3d

from .threads import first_use_on_one_cpu

__all__ = ["manifold3d"]

first_use_on_one_cpu(lambda: manifold3d.Manifold.cube((1.0, 1.0, 1.0)).num_vert())
