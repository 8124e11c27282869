"""--set NAME=VALUE and --sweep NAME=LO:HI (cga.overrides): values of the variable's kind,
clear errors for unknown names and bad values, exit status 2 from the CLI."""

from __future__ import annotations

import pytest

from cga.cli import main
from cga.errors import UsageError
from cga.overrides import parse_assignments, parse_sweep
from cga.pipeline import build

GRAMMAR = """\
Lot: rectangle(12, 8)
Variables:
  h = 6;
  top = h + 1;
  flat = false;
  label = "a";
Rules:
Lot --> extrude(top) Body
"""


@pytest.fixture
def grammar_file(tmp_path):
    path = tmp_path / "block.grammar"
    path.write_text(GRAMMAR)
    return path


def _height(scene) -> float:
    return scene.terminals[0].geometry.height


def test_override_replaces_the_value_and_later_variables_see_it(grammar_file):
    assert _height(build(grammar_file, formats=(), quiet=True)) == 7
    assert _height(build(grammar_file, formats=(), quiet=True, overrides={"h": "9"})) == 10
    build(grammar_file, formats=(), quiet=True, overrides={"flat": "TRUE", "label": "b c"})


@pytest.mark.parametrize("overrides, message", [
    ({"hh": "3"}, "has no variable 'hh'; did you mean 'h'"),
    ({"zzz": "3"}, "it declares h, top, flat, label"),
    ({"h": "tall"}, "h is a number"),
    ({"h": "inf"}, "h is a number"),
    ({"flat": "maybe"}, "flat is a truth value"),
])
def test_bad_overrides_are_usage_errors(grammar_file, overrides, message):
    with pytest.raises(UsageError, match=message):
        build(grammar_file, formats=(), quiet=True, overrides=overrides)


def test_cli_set_errors_exit_2_without_traceback(grammar_file, tmp_path, capsys):
    status = main(["build", str(grammar_file), "--out", str(tmp_path / "o"), "--quiet",
                   "--set", "hh=3"])
    err = capsys.readouterr().err
    assert status == 2 and "did you mean 'h'" in err and "Traceback" not in err
    assert main(["build", str(grammar_file), "--quiet", "--set", "h"]) == 2
    assert "expects NAME=VALUE" in capsys.readouterr().err


def test_parse_assignments():
    assert parse_assignments(["a=1", " b = x y "]) == {"a": "1", "b": "x y"}
    with pytest.raises(UsageError, match="twice"):
        parse_assignments(["a=1", "a=2"])
    with pytest.raises(UsageError, match="NAME=VALUE"):
        parse_assignments(["=1"])


@pytest.mark.parametrize("text, values", [
    ("difficulty=0:10", [float(v) for v in range(11)]),
    ("d=0:1:0.25", [0, 0.25, 0.5, 0.75, 1.0]),
    ("d=1,3,5", [1, 3, 5]),
    ("d=2:2", [2]),
])
def test_parse_sweep(text, values):
    name, got = parse_sweep(text)
    assert name == text.split("=")[0] and got == pytest.approx(values)


@pytest.mark.parametrize("text", ["d", "d=1:", "d=3:1", "d=0:10:0", "d=0:1e9", "d=a,b"])
def test_bad_sweeps(text):
    with pytest.raises(UsageError):
        parse_sweep(text)
