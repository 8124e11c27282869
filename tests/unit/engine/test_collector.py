"""The command line sets the garbage collector for building, and never lowers a
threshold a program set higher."""

from __future__ import annotations

import gc

import pytest

from cga.cli import main
from cga.collector import BUILD_THRESHOLDS, tune_for_building


@pytest.fixture
def thresholds():
    saved = gc.get_threshold()
    yield
    gc.set_threshold(*saved)


def test_the_command_line_raises_the_thresholds(thresholds, capsys):
    gc.set_threshold(700, 10, 10)
    with pytest.raises(SystemExit):
        main(["--help"])
    assert gc.get_threshold() == BUILD_THRESHOLDS


def test_higher_thresholds_are_kept(thresholds):
    gc.set_threshold(10 * BUILD_THRESHOLDS[0], 5, 500)
    tune_for_building()
    assert gc.get_threshold() == (10 * BUILD_THRESHOLDS[0], BUILD_THRESHOLDS[1], 500)

