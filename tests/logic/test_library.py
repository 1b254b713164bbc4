"""Library built-ins with the semantics SEED's rules rely on: ECLiPSe's string built-ins,
checked against the examples of ECLiPSe's reference manual (docs/seed.md)."""

import pytest

from conftest import ask


@pytest.mark.parametrize("query, answer", [
    # split_string/4: separators, padding, and separators that are also padding
    ('split_string("/usr/local/eclipse", "/", "", L)', 'split_string("/usr/local/eclipse","/","",["","usr","local","eclipse"])'),
    ('split_string("/usr/local//eclipse/", "/", "/", L)', 'split_string("/usr/local//eclipse/","/","/",["usr","local","eclipse"])'),
    ('split_string(" comma, separated , data items ", ",", " ", L)',
     'split_string(" comma, separated , data items ",","," ",["comma","separated","data items"])'),
    ('split_string("   Hello world...", "", " .", L)', 'split_string("   Hello world...",""," .",["Hello world"])'),
    ('split_string("please shut down", " ", "", [P, A, B])',
     'split_string("please shut down"," ","",["please","shut","down"])'),
    # concat_string/2: atoms, strings and numbers, always a string
    ('concat_string([the, man, " is aged ", 20], X)', 'concat_string([the,man," is aged ",20],"theman is aged 20")'),
    ('concat_string([1, 2, 3], X)', 'concat_string([1,2,3],"123")'),
    ('concat_string(["tea", "cup"], X)', 'concat_string(["tea","cup"],"teacup")'),
    # number_string/2: no white space, a leading + allowed
    ('number_string(X, "+12")', 'number_string(12,"+12")'),
    ('number_string(N, "123.4")', 'number_string(123.4,"123.4")'),
    ('number_string(1989, X)', 'number_string(1989,"1989")'),
    # term_string/2 and atom_string/2 read a string; string/1 tests for one
    ('term_string(T, "look")', 'term_string(look,"look")'),
    ('term_string(T, "f(1,2).")', 'term_string(f(1,2),"f(1,2).")'),
    ('atom_string(X, "4")', "atom_string('4',\"4\")"),
    ('string("astring")', 'string("astring")'),
])
def test_eclipse_examples_succeed(query, answer):
    assert ask("", query) == [answer]


@pytest.mark.parametrize("query", [
    'concat_string([ab, bc], "abc")', 'number_string(N, "- 15")', 'number_string(N, " +15")',
    'number_string(N, "2 ")', 'number_string(N, ".5")', 'number_string(N, "Abcd")',
    'number_string(222, "123")', "string('astring')", 'string(X)', 'term_string(2.6, "2.5")',
    "atom_string(jo, \"joe\")",
])
def test_eclipse_examples_fail(query):
    assert ask("", query) == []


@pytest.mark.parametrize("query, error", [
    ("concat_string(A, X)", "instantiation_error"),
    ("concat_string([abc, D], X)", "instantiation_error"),
    ("concat_string(art, X)", "type_error(list,art)"),
    ("concat_string([f(x)], X)", "type_error(atomic,f(x))"),
    ("concat_string([a], b)", "type_error(string,b)"),
])
def test_concat_string_errors_as_eclipse_raises_them(query, error):
    (answer,) = ask("", f"catch({query}, error(E, _), true)")
    assert f",error({error}," in answer
