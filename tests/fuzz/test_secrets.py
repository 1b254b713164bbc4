"""Nothing of a file the command line does not name reaches the screen (issue 46).

A BT.CPP document may `<include>` any path, and a knowledge file may `:- consult` one: someone
who runs schemalog on a tree they were sent (a CI job on a pull request) must not print
/etc/passwd or /proc/self/environ to whoever sent it. The property: a secret marker in any file
such a reference reaches, while that file is not yet the format it is read as (a BT.CPP <root>
document, Prolog text), never appears on standard output or error, nor in what is written, in
any command or output format.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import pytest
from hypothesis import given, strategies as st

from harness import Case, invoke, violations
from test_fuzz_cli import GUARD, profile

pytestmark = pytest.mark.fuzz

# An absolute place outside the case's directory, as /etc/passwd is outside a sent tree's
OUTSIDE = Path(tempfile.mkdtemp(prefix="schemalog-secret-"))

MARKERS = st.text("ABCDEFGHJKLMNPQRSTUVWXYZ0123456789", min_size=12, max_size=12).map(lambda s: "S3CR" + s)


@st.composite
def secret_files(draw, marker: str) -> bytes:
    """A file's bytes with `marker` in it, of a kind that is not a BT.CPP document nor Prolog text."""
    kind = draw(st.sampled_from(["passwd", "environ", "dotenv", "xml-not-root", "root-malformed", "key",
                                 "entity", "control", "binary", "prolog-broken"]))
    before = draw(st.text("abc xyz:=/.\n", max_size=30))
    text = {
        "passwd": f"root:x:0:0:{marker}:/root:/bin/bash\n",
        "environ": f"HOME=/root\0TOKEN={marker}\0PATH=/bin\0",
        "dotenv": f"{before}API_KEY={marker}\nOTHER=1\n",
        "xml-not-root": f'<config password="{marker}"><{marker}>{marker}</{marker}></config>',
        "root-malformed": f'<root BTCPP_format="4"><BehaviorTree ID="{marker}"><Action ID="{marker}"/>',
        "key": f"-----BEGIN OPENSSH PRIVATE KEY-----\n{marker}\n-----END OPENSSH PRIVATE KEY-----\n",
        "entity": f'<config>&{marker};</config>',
        "control": f"\x1b]0;{marker}\x07{before}{marker}\r\n",
        "binary": f"\x00\x01{marker}\xff",
        "prolog-broken": f"{before}secret('{marker}') :- \n{marker} {marker}(",
    }[kind]
    return text.encode("utf-8", "surrogateescape")


TREE = ('<root BTCPP_format="4" main_tree_to_execute="main"><include path="{path}"/>\n'
        '  <BehaviorTree ID="main"><Sequence><Action ID="a"/><Action ID="b"/></Sequence></BehaviorTree></root>\n')
KNOWLEDGE = ":- {how}('{path}').\ntask(t).\nschema(t, [(a, true)], a.done).\n"

BT_COMMANDS = [["compress", "t.xml"], ["compress", "t.xml", "-o", "out.xml"], ["verify", "t.xml", "t.xml"],
               ["verify", "t.xml", "t.xml", "--json"], ["convert", "t.xml", "-o", "out.pl"], ["lint", "t.xml"],
               ["lint", "t.xml", "--json"], ["check", "t.xml"], ["show", "t.xml", "--json"]]
KNOWLEDGE_COMMANDS = [["check", "k.pl"], ["lint", "k.pl", "--json"], ["show", "k.pl"], ["compress", "k.pl", "--json"],
                      ["verify", "k.pl"], ["run", "k.pl", "--json"], ["query", "k.pl", "true"],
                      ["convert", "k.pl", "-o", "out.yaml"], ["export", "k.pl", "-o", "out.xml"]]


def where(draw, name: str) -> str:
    """The reference's path: beside the file, through `..`, or absolute outside its folder."""
    how = draw(st.sampled_from(["beside", "dotdot", "absolute"]))
    if how == "absolute":
        return str(OUTSIDE / name)
    return name if how == "beside" else f"sub/../{name}"


def probe(draw, argv, referring: str, text: str) -> None:
    marker = draw(MARKERS)
    secret = draw(secret_files(marker))
    name = draw(st.sampled_from(["secret.txt", "secret.xml", "secret.pl", ".env"]))
    path = where(draw, name)
    if os.path.isabs(path):
        (OUTSIDE / name).write_bytes(secret)
    files = ((referring, text.format(path=path, how=draw(st.sampled_from(["consult", "include", "ensure_loaded"])))
              .encode()), ("sub/keep", b""), (name, secret))
    case = Case(tuple(argv), files=files, output=argv[argv.index("-o") + 1] if "-o" in argv else None)
    outcome = invoke(case, GUARD)
    assert not violations(case, outcome), violations(case, outcome)
    assert outcome.status != 0
    shown = outcome.stdout + outcome.stderr + (outcome.output_after or b"").decode("utf-8", "replace")
    assert marker not in shown, (argv, shown[:2000])
    assert "\x1b" not in shown and "\x00" not in shown
    assert name in shown                     # the message names the file it could not read


@profile(60)
@given(st.data(), st.sampled_from(BT_COMMANDS))
def test_an_include_shows_nothing_of_a_file_that_is_not_a_tree(data, argv):
    probe(data.draw, argv, "t.xml", TREE)


@profile(60)
@given(st.data(), st.sampled_from(KNOWLEDGE_COMMANDS))
def test_a_consult_shows_nothing_of_a_file_that_is_not_prolog(data, argv):
    probe(data.draw, argv, "k.pl", KNOWLEDGE)


def test_the_file_named_on_the_command_line_is_quoted():
    """The line and its caret stay for the file the user named, its control characters escaped."""
    case = Case(("compress", "t.xml"), files=(("t.xml", b'<root BTCPP_format="4">\x1b[2J<a b=1/>'),))
    outcome = invoke(case, GUARD)
    assert outcome.status == 1
    assert "t.xml:1:" in outcome.stderr and "\\x1b[2J" in outcome.stderr and "\x1b" not in outcome.stderr
    line, caret = outcome.stderr.splitlines()[1:3]
    assert line[caret.index("^"):].startswith("\\x1b[2J")     # the caret under the escape it points at
