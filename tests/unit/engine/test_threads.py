"""The command line asks BLAS for one thread before numpy loads, and keeps a setting the
user made; manifold3d computes on the calling thread."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from cga.threads import BLAS_THREAD_VARIABLES, first_use_on_one_cpu, one_blas_thread

ROOT = Path(__file__).resolve().parents[3]

_PROBE = """
import os, sys
from cga.cli import main
main(['check', {grammar!r}])
print(os.environ.get('OPENBLAS_NUM_THREADS'), 'numpy' in sys.modules)
"""


def _blas_threads_seen(env: dict[str, str]) -> str:
    done = subprocess.run(
        [sys.executable, "-c", _PROBE.format(grammar=str(ROOT / "demos" / "house.grammar"))],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=120, check=True)
    return done.stdout.strip().splitlines()[-1]


def test_the_command_line_sets_one_thread_before_numpy_loads():
    env = {k: v for k, v in os.environ.items() if k not in BLAS_THREAD_VARIABLES}
    env["PYTHONPATH"] = str(ROOT)
    assert _blas_threads_seen(env) == "1 True"


def test_a_users_setting_is_kept():
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="3")
    assert _blas_threads_seen(env) == "3 True"


def test_one_blas_thread_sets_only_missing_variables(monkeypatch):
    monkeypatch.delenv("OPENBLAS_NUM_THREADS", raising=False)
    monkeypatch.setenv("MKL_NUM_THREADS", "4")
    one_blas_thread()
    assert os.environ["OPENBLAS_NUM_THREADS"] == "1"
    assert os.environ["MKL_NUM_THREADS"] == "4"



_MANIFOLD_PROBE = """
import os
from cga.manifold import manifold3d
box = manifold3d.Manifold.cube((1.0, 1.0, 1.0))
cutters = [manifold3d.Manifold.cube((0.2, 2.0, 0.2)).translate((0.1 * k, -0.5, 0.3))
           for k in range(5)]
for _ in range(20):
    manifold3d.Manifold.batch_boolean([box, *cutters], manifold3d.OpType.Subtract).num_vert()
print(len(os.listdir('/proc/self/task')), len(os.sched_getaffinity(0)))
"""


@pytest.mark.skipif(not sys.platform.startswith("linux")
                    or len(getattr(os, "sched_getaffinity", lambda _: ())(0)) < 2,
                    reason="needs Linux's thread list and two CPUs to run on")
def test_manifold_computes_on_the_calling_thread_only():
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1")
    done = subprocess.run([sys.executable, "-c", _MANIFOLD_PROBE], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=120, check=True)
    threads, cpus = map(int, done.stdout.split())
    assert threads == 1  # no task-arena worker beside the main thread
    assert cpus == len(os.sched_getaffinity(0))  # the thread got its CPUs back


def test_first_use_runs_on_one_cpu_then_the_cpus_come_back():
    if not hasattr(os, "sched_getaffinity"):
        pytest.skip("no CPU affinity on this platform")
    before = os.sched_getaffinity(0)
    seen = first_use_on_one_cpu(lambda: os.sched_getaffinity(0))
    assert len(seen) == 1 and seen <= before
    assert os.sched_getaffinity(0) == before


def test_first_use_runs_where_cpus_cannot_be_set(monkeypatch):
    def refuse(*_):
        raise OSError("not permitted")

    monkeypatch.setattr(os, "sched_setaffinity", refuse)
    assert first_use_on_one_cpu(lambda: "ran") == "ran"
