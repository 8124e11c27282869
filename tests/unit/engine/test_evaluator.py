"""The evaluator: start symbol, variables, binding, units, choices, depth, locality, errors."""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import box

from cga.errors import DerivationError
from cga.evaluator import Evaluator, derive
from cga.registry import OperationRegistry
from cga.operation import Child, Operation, Param
from cga.shape import Mass

LOT = box(0, 0, 10, 6)


def leaf_paths(derivation):
    return [t.path_name for t in derivation.terminals]


def error_of(grammar, **kwargs):
    with pytest.raises(DerivationError) as info:
        derive(grammar, LOT, **kwargs)
    return info.value


class Draw(Operation):
    """Test operation: draws a number from the shape's stream and records it in attrs."""

    name = "draw"
    params = (Param("scale", "number", default=1.0),)

    def apply(self, shape, args, ctx):
        value = float(ctx.rng.random()) * args["scale"]
        return [Child(successor=0, geometry=shape.geometry, scope=shape.scope,
                      attrs={"drawn": value})]


class Fails(Operation):
    """Test operation raising a span-less DerivationError, or a bug (ValueError)."""

    name = "fails"
    params = (Param("bug", "bool", default=False),)

    def apply(self, shape, args, ctx):
        if args["bug"]:
            raise ValueError("internal bug")
        raise DerivationError("cannot do that here")


def registry(*extra):
    table = OperationRegistry()
    for operation in extra:
        table.register(operation)
    return table


# -- start symbol, terminals, paths -----------------------------------------------------

def test_start_symbol_is_lot_when_it_has_a_rule(g):
    grammar = g.grammar(g.rule("Other", g.step(g.op("extrude", 1), "X")),
                        g.rule("Lot", g.step(g.op("extrude", 2), "Body")))
    d = derive(grammar, LOT)
    assert leaf_paths(d) == ["Lot/Body"]
    assert d.terminals[0].geometry.height == 2


def test_start_symbol_is_first_rule_otherwise(g):
    grammar = g.grammar(g.rule("let", g.step(g.op("extrude", 3), "Body")))
    assert leaf_paths(derive(grammar, LOT)) == ["let/Body"]


def test_paths_index_children_of_multi_child_applications(g):
    grammar = g.grammar(
        g.rule("Lot", g.step(g.op("extrude", 9), "Body")),
        g.rule("Body", g.step(g.op("repeated_split", "y", 3), "Ground", "Upper")))
    d = derive(grammar, LOT)
    assert leaf_paths(d) == ["Lot/Body/Ground[0]", "Lot/Body/Upper[1]", "Lot/Body/Upper[2]"]
    assert [t.attrs["floor"] for t in d.terminals] == [0, 1, 2]
    assert [child.shape.symbol for child in d.root.children[0].children] == ["Ground", "Upper", "Upper"]


def test_rename_step_without_operation_keeps_geometry(g):
    grammar = g.grammar(g.rule("Lot", g.step(g.op("extrude", 4), "A")),
                        g.rule("A", g.step(None, "B")))
    d = derive(grammar, LOT)
    assert leaf_paths(d) == ["Lot/A/B"]
    assert d.terminals[0].geometry.height == 4


def test_sequence_applies_every_step_to_the_predecessor(g):
    grammar = g.grammar(
        g.rule("Lot", g.step(g.op("extrude", 4), "Body")),
        g.rule("Body", g.seq(g.step(g.op("component_split", "side_faces"), "Facade"),
                             g.step(g.op("component_split", "top"), "Roof"))))
    d = derive(grammar, LOT)
    assert leaf_paths(d)[-1] == "Lot/Body/Roof[4]"
    assert [t.symbol for t in d.terminals] == ["Facade"] * 4 + ["Roof"]


def test_default_lot_and_grammar_lot_in_units(g):
    grammar = g.grammar(g.rule("Lot", g.step(g.op("extrude", 1), "B")))
    assert derive(grammar).lot.area == pytest.approx(14 * 10)
    lot_call = g.call("rectangle", g.name("w"), 3)
    grammar = g.grammar(g.rule("Lot", g.step(g.op("extrude", 1), "B")),
                        variables=[g.var("w", 4)], units=10, lot=lot_call)
    d = derive(grammar)
    assert d.lot.bounds == (0, 0, 40, 30)
    assert d.terminals[0].geometry.height == 10


# -- variables ----------------------------------------------------------------------------

def test_variables_in_order_and_ranges_drawn_once_per_build(g):
    grammar = g.grammar(
        g.rule("Lot", g.step(g.op("extrude", g.name("h")), "B")),
        variables=[g.var("base", 2), g.var("h", g.binop("*", g.name("base"), 3)),
                   g.var("r", g.rnd(1, 2))])
    d1, d2 = derive(grammar, LOT, seed=5), derive(grammar, LOT, seed=5)
    assert d1.variables["h"] == 6.0
    assert 1 <= d1.variables["r"] <= 2
    assert d1.variables == d2.variables
    draws = {derive(grammar, LOT, seed=s).variables["r"] for s in range(8)}
    assert len(draws) == 8


def test_range_draw_does_not_depend_on_other_variables(g):
    one = g.grammar(g.rule("Lot", g.step(None, "B")), variables=[g.var("r", g.rnd(0, 1))])
    two = g.grammar(g.rule("Lot", g.step(None, "B")),
                    variables=[g.var("q", g.rnd(0, 1)), g.var("r", g.rnd(0, 1))])
    assert derive(one, LOT, seed=3).variables["r"] == derive(two, LOT, seed=3).variables["r"]


def test_variable_used_before_definition(g):
    grammar = g.grammar(g.rule("Lot", g.step(None, "B")),
                        variables=[g.var("a", g.name("b", at=(3, 7))), g.var("b", 1, at=(4, 3))])
    error = error_of(grammar)
    assert str(error).startswith("test.grammar:3:7: error: variable 'b' is used before it "
                                 "is defined (at line 4)")


def test_undefined_variable_did_you_mean(g):
    grammar = g.grammar(
        g.rule("Lot", g.step(g.op("extrude", g.name("floorHieght", at=(9, 20))), "B")),
        variables=[g.var("floorHeight", 3)])
    text = str(error_of(grammar))
    assert "test.grammar:9:20: error: undefined variable 'floorHieght'" in text
    assert "did you mean 'floorHeight'?" in text


def test_shape_attribute_in_variables_is_an_error(g):
    grammar = g.grammar(g.rule("Lot", g.step(None, "B")),
                        variables=[g.var("a", g.name("scope.sx", at=(2, 5)))])
    assert "test.grammar:2:5: error: shape attribute 'scope.sx' is only available inside rules" \
        in str(error_of(grammar))


# -- binding -------------------------------------------------------------------------------

def test_unknown_operation_did_you_mean(g):
    grammar = g.grammar(g.rule("Lot", g.step(g.op("extrud", 3, at=(5, 8)), "B")))
    text = str(error_of(grammar))
    assert "test.grammar:5:8: error: unknown operation 'extrud'" in text
    assert "did you mean 'extrude'?" in text


def test_too_many_arguments_points_at_the_extra_one(g):
    grammar = g.grammar(g.rule("Lot", g.step(g.op("extrude", 3, g.arg(4, at=(2, 19))), "B")))
    text = str(error_of(grammar))
    assert "test.grammar:2:19: error: extrude takes 1 positional argument, got 2" in text
    assert "signature: extrude(height)" in text


def test_missing_argument_points_at_the_call(g):
    grammar = g.grammar(g.rule("Lot", g.step(g.op("repeated_split", "y", at=(6, 9)), "A")))
    text = str(error_of(grammar))
    assert "test.grammar:6:9: error: repeated_split: missing argument 'size'" in text
    assert "signature: repeated_split(axis, size)" in text


def test_unknown_keyword_did_you_mean(g):
    grammar = g.grammar(g.rule("Lot", g.step(
        g.op("extrude", g.arg(3, kw="hieght", at=(1, 30))), "B")))
    text = str(error_of(grammar))
    assert "test.grammar:1:30: error: extrude has no parameter 'hieght'" in text
    assert "did you mean 'height'?" in text


def test_keyword_argument_binds_and_duplicate_is_an_error(g):
    ok = g.grammar(g.rule("Lot", g.step(g.op("extrude", g.arg(7, kw="height")), "B")))
    assert derive(ok, LOT).terminals[0].geometry.height == 7
    twice = g.grammar(g.rule("Lot", g.step(
        g.op("extrude", 3, g.arg(4, kw="height", at=(3, 3))), "B")))
    assert "test.grammar:3:3: error: extrude: argument 'height' given twice" in str(error_of(twice))


def test_wrong_kind_names_the_parameter_and_value(g):
    grammar = g.grammar(g.rule("Lot", g.step(g.op("extrude", g.arg("tall", at=(4, 17))), "B")))
    text = str(error_of(grammar))
    assert ("test.grammar:4:17: error: extrude: argument 'height' (length) expected a number, "
            "got the string \"tall\"") in text


def test_axis_kind_lists_the_choices(g):
    grammar = g.grammar(
        g.rule("Lot", g.step(g.op("extrude", 3), "B")),
        g.rule("B", g.step(g.op("repeated_split", g.arg("T", at=(8, 24)), 1), "F")))
    assert "test.grammar:8:24: error: repeated_split: argument 'axis' (axis) must be one of " \
           "'x', 'y', 'z'" in str(error_of(grammar))


def test_successor_count_checked_at_the_rule(g):
    grammar = g.grammar(
        g.rule("Lot", g.step(g.op("extrude", 3), "B")),
        g.rule("B", g.step(g.op("repeated_split", "y", 1), "A", "C", "D", at=(7, 1))))
    text = str(error_of(grammar))
    assert "test.grammar:7:1: error: repeated_split takes 1 to 2 successors, got 3 in rule B" in text


def test_split_needs_sized_parts(g):
    grammar = g.grammar(g.rule("Lot", g.step(g.op("extrude", 3), "B")),
                        g.rule("B", g.step(g.op("split", "y"), "A", "C", at=(3, 1))))
    assert "test.grammar:3:1: error: split needs sized parts" in str(error_of(grammar))


# -- units ----------------------------------------------------------------------------------

def test_length_arguments_and_split_sizes_in_units_attributes_reported_back(g):
    # units = 10: extrude(1.2) is 12 m; split sizes 0.3 → 3 m; the guard reads scope.sy in
    # grammar units (0.3), not metres.
    grammar = g.grammar(
        g.rule("Lot", g.step(g.op("extrude", 1.2), "Body")),
        g.rule("Body", g.split_step(g.op("split", "y"), [("floating", 0.3, "Floor")], repeat=True)),
        g.rule("Floor", g.case((g.binop("==", g.name("scope.sy"), 0.3), g.seq(g.step(None, "Ok"))),
                               (None, g.seq(g.step(None, "Wrong"))))),
        units=10)
    d = derive(grammar, LOT)
    assert [t.symbol for t in d.terminals] == ["Ok"] * 4
    assert [t.geometry.height for t in d.terminals] == pytest.approx([3.0] * 4)
    assert d.units == 10


def test_units_override(g):
    grammar = g.grammar(g.rule("Lot", g.step(g.op("extrude", 2), "B")), units=10)
    assert derive(grammar, LOT, units=1).terminals[0].geometry.height == 2


def test_area_attribute_in_grammar_units(g):
    grammar = g.grammar(g.rule("Lot", g.case(
        (g.binop(">", g.name("area"), 0.59), g.seq(g.step(None, "Big"))),
        (None, g.seq(g.step(None, "Small"))))), units=10)
    # 10 m × 6 m = 60 m² = 0.6 grammar units²
    assert derive(grammar, LOT).terminals[0].symbol == "Big"


# -- choices --------------------------------------------------------------------------------

def test_stochastic_choice_reproducible_and_distributed(g):
    grammar = g.grammar(g.rule("Lot", g.stochastic(
        (30, g.seq(g.step(None, "A"))), (None, g.seq(g.step(None, "B"))))))
    picks = [derive(grammar, LOT, seed=s).terminals[0].symbol for s in range(400)]
    assert picks == [derive(grammar, LOT, seed=s).terminals[0].symbol for s in range(400)]
    assert 0.22 < picks.count("A") / 400 < 0.38


def test_percentages_must_add_up(g):
    over = g.grammar(g.rule("Lot", g.stochastic((70, g.seq(g.step(None, "A"))),
                                                (40, g.seq(g.step(None, "B"))), at=(2, 8))))
    assert "test.grammar:2:8: error: the percentages add up to 110%" in str(error_of(over))
    short = g.grammar(g.rule("Lot", g.stochastic((70, g.seq(g.step(None, "A"))), at=(3, 8))))
    assert "test.grammar:3:8: error: the percentages add up to 70%, not 100%" in str(error_of(short))


def test_case_guards_take_first_true_and_need_else(g):
    grammar = g.grammar(
        g.rule("Lot", g.step(g.op("extrude", 9), "Body")),
        g.rule("Body", g.step(g.op("repeated_split", "y", 3), "F")),
        g.rule("F", g.case((g.binop("==", g.name("floor"), 0), g.seq(g.step(None, "Shop"))),
                           (g.binop("<", g.name("index"), 2), g.seq(g.step(None, "Office"))),
                           (None, g.seq(g.step(None, "Flat"))))))
    assert [t.symbol for t in derive(grammar, LOT).terminals] == ["Shop", "Office", "Flat"]
    no_else = g.grammar(g.rule("Lot", g.case(
        (g.binop(">", g.name("area"), 1000), g.seq(g.step(None, "A"))), at=(4, 8))))
    text = str(error_of(no_else))
    assert "test.grammar:4:8: error: no case of rule Lot is true for this shape" in text
    assert "area = 60" in text


# -- depth limit ----------------------------------------------------------------------------

def test_recursion_limit_names_the_cycle(g):
    grammar = g.grammar(g.rule("A", g.step(g.op("extrude", 1), "B"), at=(2, 1)),
                        g.rule("B", g.step(None, "A"), at=(3, 1)))
    text = str(error_of(grammar))
    assert "test.grammar:" in text
    assert "recursion deeper than 64 at rule" in text
    assert ("A → B → A …" in text) or ("B → A → B …" in text)


def test_recursion_limit_is_configurable_and_guards_stop_recursion(g):
    # Floor --> case scope.sy > 1 : split y { 1 : Slab | ~1 : Floor } | else : Top
    grammar = g.grammar(
        g.rule("Lot", g.step(g.op("extrude", 10), "Floor")),
        g.rule("Floor", g.case(
            (g.binop(">", g.name("scope.sy"), 1.5),
             g.seq(g.split_step(g.op("split", "y"), [("absolute", 1, "Slab"), ("floating", 1, "Floor")]))),
            (None, g.seq(g.step(None, "Top"))))))
    d = derive(grammar, LOT)
    assert [t.symbol for t in d.terminals] == ["Slab"] * 9 + ["Top"]
    with pytest.raises(DerivationError, match="recursion deeper than 5 at rule Floor"):
        derive(grammar, LOT, max_depth=5)


# -- operations' errors -----------------------------------------------------------------------

def test_spanless_error_from_operation_gets_the_call_span(g):
    grammar = g.grammar(g.rule("Lot", g.step(g.op("fails", at=(6, 10)), "B")))
    with pytest.raises(DerivationError) as info:
        derive(grammar, LOT, operations=registry(Fails()))
    assert str(info.value).startswith("test.grammar:6:10: error: cannot do that here")


def test_non_cga_exception_from_operation_propagates(g):
    grammar = g.grammar(g.rule("Lot", g.step(g.op("fails", g.arg(True, kw="bug")), "B")))
    with pytest.raises(ValueError, match="internal bug"):
        derive(grammar, LOT, operations=registry(Fails()))


def test_resolve_in_context_finds_files_next_to_grammar(g, tmp_path):
    (tmp_path / "types.csv").write_text("x")
    seen = {}

    class Resolve(Operation):
        name = "resolve"
        params = (Param("table", "path"),)

        def apply(self, shape, args, ctx):
            seen["path"] = ctx.resolve(args["table"], "rules")
            return []

    grammar = g.grammar(g.rule("Lot", g.step(g.op("resolve", "D:\\x\\types"), "B")),
                        file=str(tmp_path / "house.grammar"))
    derive(grammar, LOT, operations=registry(Resolve()))
    assert seen["path"] == tmp_path / "types.csv"
    missing = g.grammar(g.rule("Lot", g.step(g.op("resolve", g.arg("nope.csv", at=(4, 17))),
                                             "B")), file=str(tmp_path / "house.grammar"))
    with pytest.raises(DerivationError) as info:
        derive(missing, LOT, operations=registry(Resolve()))
    assert str(info.value).startswith("test.grammar:4:17: error: rule table not found: nope.csv")
    assert str(tmp_path / "nope.csv") in str(info.value)


def test_registry_is_copied(g):
    table = OperationRegistry()
    evaluator = Evaluator(g.grammar(g.rule("Lot", g.step(g.op("draw"), "B"))), operations=table)
    table.register(Draw())
    with pytest.raises(DerivationError, match="unknown operation 'draw'"):
        evaluator.derive(LOT)


def test_timings_per_operation(g):
    grammar = g.grammar(g.rule("Lot", g.step(g.op("extrude", 9), "Body")),
                        g.rule("Body", g.step(g.op("repeated_split", "y", 3), "F")))
    timings = derive(grammar, LOT).timings
    assert set(timings) == {"extrude", "repeated_split"}
    assert all(t >= 0 for t in timings.values())


def test_duplicate_rule_is_an_error(g):
    grammar = g.grammar(g.rule("Lot", g.step(None, "A"), at=(2, 1)),
                        g.rule("Lot", g.step(None, "B"), at=(5, 1)))
    assert "test.grammar:5:1: error: a second rule for Lot (the first is at line 2)" \
        in str(error_of(grammar))


# -- locality ------------------------------------------------------------------------------

def _locality_grammar(g, right_height):
    """Lot → split x into Left and Right; each subtree extrudes by a random height and
    draws from its own stream, below a repeated split."""
    return g.grammar(
        g.rule("Lot", g.split_step(g.op("split", "x"), [("floating", 1, "Left"),
                                                        ("floating", 1, "Right")])),
        g.rule("Left", g.step(g.op("extrude", g.rnd(3, 9)), "LeftBody")),
        g.rule("LeftBody", g.step(g.op("repeated_split", "z", 1), "LeftPart")),
        g.rule("LeftPart", g.step(g.op("draw"), "LeftLeaf")),
        g.rule("Right", g.step(g.op("extrude", right_height), "RightBody")),
        g.rule("RightBody", g.step(g.op("draw", 2), "RightLeaf")))


def _signature(terminal):
    geometry = terminal.geometry
    return (terminal.path_name, geometry.footprint.wkt, geometry.base, geometry.height,
            terminal.attrs.get("drawn"))


def test_editing_one_rule_changes_only_its_subtree(g):
    before = derive(_locality_grammar(g, 4), LOT, seed=11, operations=registry(Draw()))
    after = derive(_locality_grammar(g, g.rnd(2, 8)), LOT, seed=11, operations=registry(Draw()))
    left_before = [_signature(t) for t in before.terminals if t.symbol == "LeftLeaf"]
    left_after = [_signature(t) for t in after.terminals if t.symbol == "LeftLeaf"]
    assert len(left_before) == 6 and left_before == left_after
    right_before = [_signature(t) for t in before.terminals if t.symbol == "RightLeaf"]
    right_after = [_signature(t) for t in after.terminals if t.symbol == "RightLeaf"]
    assert right_before != right_after
    drawn = [s[-1] for s in left_before]
    assert len(set(drawn)) == len(drawn)  # each shape has its own stream


def test_same_seed_same_derivation_other_seed_differs(g):
    a = derive(_locality_grammar(g, 4), LOT, seed=1, operations=registry(Draw()))
    b = derive(_locality_grammar(g, 4), LOT, seed=1, operations=registry(Draw()))
    c = derive(_locality_grammar(g, 4), LOT, seed=2, operations=registry(Draw()))
    sig = lambda d: [_signature(t) for t in d.terminals]  # noqa: E731
    assert sig(a) == sig(b)
    assert sig(a) != sig(c)


def test_lot_is_a_flat_mass(g):
    d = derive(g.grammar(g.rule("Lot", g.step(None, "Ground"))), LOT)
    mass = d.terminals[0].geometry
    assert isinstance(mass, Mass) and mass.height == 0
    assert np.allclose(d.terminals[0].scope.size, (10, 0, 6))
