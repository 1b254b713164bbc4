"""ECLiPSe's term_string/2, atom_string/2 and split_string/4, as SEED's rules get them:
the examples of ECLiPSe's reference manual, successes, failures and errors (docs/seed.md).
The engine's own term_string/2, atom_string/2, split_string/4 stay SWI-Prolog's."""

import pytest

from conftest import ask


@pytest.mark.parametrize("query, answer", [
    ('eclipse_term_string(T, "look")', 'eclipse_term_string(look,"look")'),
    ('eclipse_term_string(T, "26.0")', 'eclipse_term_string(26.0,"26.0")'),
    ('eclipse_term_string(T, "f(1,2).")', 'eclipse_term_string(f(1,2),"f(1,2).")'),
    ('eclipse_term_string(T, "f(1,2)")', 'eclipse_term_string(f(1,2),"f(1,2)")'),
    # written as ECLiPSe's writeq writes: a space after each comma, around infix operators
    ('eclipse_term_string(f(1,2), L)', 'eclipse_term_string(f(1,2),"f(1, 2)")'),
    ('eclipse_term_string(f(1,2), "f(1, 2)")', 'eclipse_term_string(f(1,2),"f(1, 2)")'),
    ('eclipse_term_string(atom, S)', 'eclipse_term_string(atom,"atom")'),
    ("eclipse_term_string('[|]'(a, '[|]'(1, [])), S)", 'eclipse_term_string([a,1],"[a, 1]")'),
    ('eclipse_term_string(2.60, "2.6")', 'eclipse_term_string(2.6,"2.6")'),
    ('eclipse_term_string(2.6, "2.60")', 'eclipse_term_string(2.6,"2.60")'),
    ('eclipse_term_string((head :- body), S)', 'eclipse_term_string((head:-body),"head :- body")'),
    ('eclipse_term_string(*(^(1,2),+(3,4)), S)', 'eclipse_term_string(1^2*(3+4),"1 ^ 2 * (3 + 4)")'),
    ('eclipse_term_string(f(X, Y, X), S)', 'eclipse_term_string(f(X,Y,X),"f(_g1, _g2, _g1)")'),
    ("eclipse_atom_string('Tom', \"Tom\")", "eclipse_atom_string('Tom',\"Tom\")"),
    ('eclipse_atom_string(tom, X)', 'eclipse_atom_string(tom,"tom")'),
    ('eclipse_atom_string(X, "4")', "eclipse_atom_string('4',\"4\")"),
    ('eclipse_atom_string([], X)', 'eclipse_atom_string([],"[]")'),
    ('eclipse_split_string("/usr/local/eclipse", "/", "", L)',
     'eclipse_split_string("/usr/local/eclipse","/","",["","usr","local","eclipse"])'),
    ('eclipse_split_string("/usr/local//eclipse/", "/", "/", L)',
     'eclipse_split_string("/usr/local//eclipse/","/","/",["usr","local","eclipse"])'),
    ('eclipse_split_string(" comma, separated , data items ", ",", " \\t", L)',
     'eclipse_split_string(" comma, separated , data items ",","," \\t",["comma","separated","data items"])'),
    ('eclipse_split_string("   Hello world...", "", " .", L)',
     'eclipse_split_string("   Hello world...",""," .",["Hello world"])'),
])
def test_manual_examples_succeed(query, answer):
    assert ask("", query) == [answer]


@pytest.mark.parametrize("query", [
    'eclipse_term_string(2.6, "2.5")', "eclipse_atom_string(jo, \"joe\")",
    'eclipse_split_string("a b", " ", "", [_])',
])
def test_manual_examples_fail(query):
    assert ask("", query) == []


@pytest.mark.parametrize("query, error", [
    ("eclipse_term_string(T, atom)", "type_error(string,atom)"),
    ('eclipse_term_string(T, "F(1,2)")', "syntax_error("),
    ("eclipse_atom_string(X, Y)", "instantiation_error"),
    ('eclipse_atom_string(4, "4")', "type_error(atom,4)"),
    ("eclipse_atom_string(tom, 'tom')", "type_error(string,tom)"),
    ('eclipse_atom_string(f(x), S)', "type_error(atom,f(x))"),
    ('eclipse_split_string(S, "", "", L)', "instantiation_error"),
    ('eclipse_split_string(abc, "", "", L)', "type_error(string,abc)"),
    ('eclipse_split_string("a b", 32, "", L)', "type_error(string,32)"),
    ('eclipse_split_string("a b", " ", \' \', L)', "type_error(string,' ')"),
    ('eclipse_split_string("a b", " ", "", x)', "type_error(list,x)"),
])
def test_manual_errors(query, error):
    (answer,) = ask("", f"catch({query}, error(E, _), true)")
    assert f",error({error}" in answer, answer


def test_the_swi_prolog_built_ins_keep_swi_prologs_meaning():
    # what the conformance suite records of SWI-Prolog 9
    assert ask("", "atom_string(42, S)") == ['atom_string(42,"42")']
    assert ask("", "term_string(f(1,2), S)") == ['term_string(f(1,2),"f(1,2)")']
    assert ask("", "split_string(abc, \"\", \"\", L)") == ['split_string(abc,"","",["abc"])']
