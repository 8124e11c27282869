"""The command line asks BLAS for one thread before numpy loads, and keeps a setting the
user made."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from cga.threads import BLAS_THREAD_VARIABLES, one_blas_thread

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

