"""Behaviour trees in and out of BehaviorTree.CPP 4 XML: everything BT.CPP 4 loads, as bt.model.

    read_bt(text, file, read, models=(), main=None) -> Document   a <root> document and its includes;
                                          text a sequence of (text, file): several read as one program
    read_models(text, file)               -> models       the <TreeNodesModel> of a nodes file
    write_bt(document)                    -> str          a BTCPP_format="4" document BT.CPP and Groot2 load
    infer_models(document)                -> models       the models write_bt adds for undeclared node types

The XML read (BT.CPP's xml_parsing.cpp, BTCPP_format 4):

    <root BTCPP_format="4" main_tree_to_execute="Main">
      <include path="other.xml"/>                     read through read(path), relative to this file
      <BehaviorTree ID="Main">                        exactly one node under each tree
        <Sequence name="s">                           Node("Sequence", (("name", "s"),), children)
          <ComputePathToPose goal="{goal}"/>          Node("ComputePathToPose", (("goal", "{goal}"),))
          <Action ID="Say" message="hi"/>             Node("Say", (("message", "hi"),), form="Action")
          <SubTree ID="Sub" goal="{goal}" _autoremap="true"/>
                                                      Node("SubTree", (("ID", "Sub"), ("goal", "{goal}"),
                                                           ("_autoremap", "true")))
        </Sequence>
      </BehaviorTree>
      <TreeNodesModel>                                NodeModel("Say", "Action", (Port("input",
        <Action ID="Say">                                  "message", "hello", "std::string", "What to say"),))
          <input_port name="message" type="std::string" default="hello">What to say</input_port>
        </Action>
      </TreeNodesModel>
    </root>

A node's `type` is its registration ID: the tag, or the ID of the generic forms <Action>,
<Condition>, <Control>, <Decorator> (whose tag `form` keeps, their ID left out of `attrs`). A
<SubTree> is Node("SubTree") with its ID among its attributes where the document put it, so its
remapping is kept exactly, in order. Attribute values are read as BT.CPP's tinyxml2 reads them:
`&&`, `<` and unknown `&name;` in a value are text (BT.CPP's own tutorials write scripts such
as `if="A>B && color != BLUE"`, which a strict XML parser calls malformed), the five XML
entities and character references are decoded, a newline in a value stays a newline, and a
bare `&` after a decoded reference reads as tinyxml2's in-place decoding leaves it (`&quot;&b`
is `"qb` to BT.CPP; see _decode). The rest of the XML is checked with defusedxml
(formats/btcpp.parse_xml: no entities, no external references, bounded size), which also gives
every element its line and column.

A single <BehaviorTree> without an ID is named `BehaviorTree_0` (then _1, ...), as BT.CPP names it
(one with ID="" is named "", as in BT.CPP). The main tree is `main` when given (BT.CPP's
createTree(name)), else the top file's main_tree_to_execute, else the only tree. Several documents
are read in order into one program, as registerBehaviorTreeFromFile reads file after file into one
factory (a folder's files: api/behaviour_trees.read_tree); a file reached twice is read once.
Node types that BT.CPP does not register and no model declares are accepted as opaque custom nodes. What BT.CPP
refuses is refused with file:line:column; the checks follow VerifyXML, createNodeFromXML and
recursivelyCreateSubtree of BT.CPP's src/xml_parsing.cpp (4.x): a wrong root element, a generic
form or <SubTree> without ID, a <BehaviorTree> without exactly one child (or without an ID beside
other elements, or named after a registered node), a second <TreeNodesModel> in one file, an
<Action>, <Condition>, <Control>, <Decorator> or <SubTree> right under <root> without ID in a file
with a <TreeNodesModel> (VerifyXML looks there, not in the TreeNodesModel), a decorator without
exactly one child, a control node without children, a leaf with children, a node type used both
as a leaf and with children in any trees read (BT.CPP refuses one use whatever the
registration), a <SubTree> with children, a main tree that does not exist, an <include> without
path or through ros_pkg (no ROS package index here), a tree's ID used as a node type (<CheckStatus/> for <SubTree
ID="CheckStatus"/>, or declared by a nodes file), a generic form as a ReactiveSequence's child,
and, only in the trees BT.CPP creates (the main tree and the SubTrees it reaches:
createNodeFromXML and recursivelyCreateSubtree check nothing else), an ID on a tag other than the
generic forms and <SubTree>, a generic form naming SubTree, a <SubTree> naming no tree, an
`_autoremap` that is not a boolean, a SubTree model's mandatory port left unremapped (the ports of
every model of the ID, as loadSubtreeModel merges them; one whose name no attribute can carry,
`name`, `_a` or "", is never remapped), and a node of BT.CPP's own with a port it does not
declare, a literal that does not convert or without a port its constructor needs (bt/ports.py).
Beyond BT.CPP, and said so: a BTCPP_format other than 4 (version 3 files named as such), an
include cycle or includes deeper than MAX_INCLUDE_DEPTH, a SubTree that contains itself (BT.CPP
recurses without end), a created tree (SubTrees expanded) deeper than MAX_TREE_DEPTH levels, and
two trees with one ID, in one file or two (BT.CPP keeps the last silently). The <SubTree> model entries of one tree
ID (in several files, or a nodes file) are one model in the Document, merged as loadSubtreeModel
merges them: a call's remapping takes their defaults (bt/semantics.call_identity). A file an
<include> reaches is quoted in no message until it is a <root> document (btcpp.read_included:
it may be any file the process reads).

write_bt writes every tree (in order), main_tree_to_execute and a <TreeNodesModel> with the
document's models, then a model for every other custom node type used (infer_models: kind from
the generic form, else a leaf is an Action, a node always over one child a Decorator, else a
Control; ports from the attributes used, `input` where a use gives a literal, else `inout`).
read_bt(write_bt(d)) == d for trees, main and models when d's models cover its custom node types;
otherwise the read-back models are d.models + infer_models(d). A port description is kept
stripped of surrounding white space (XML text between tags).
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from xml.sax.saxutils import escape

from ..bt.model import Attrs, Document, Node, NodeModel, Port, subtree_ports, walk
from ..bt.ports import BUILTIN, BUILTIN_V3, RESERVED, is_port_name, refusal, refusal_v3
from ..errors import SchemalogError, SourcePos, readable_name
from ..inputs import not_regular
from .btcpp import XNode, parse_xml, read_included
from .quoting import Unquotable, xml_attribute

MAX_INCLUDE_DEPTH = 16
MAX_TREE_DEPTH = 256             # levels of the tree BT.CPP creates, SubTrees expanded (defaults.MAX_DEPTH)
GENERIC = ("Action", "Condition", "Control", "Decorator")
PORT_TAGS = {"input_port": "input", "output_port": "output", "inout_port": "inout"}
PORT_TAG_OF = {v: k for k, v in PORT_TAGS.items()}

# Node types of BT.CPP 3 that version 4 does not register (renamed or removed).
V3_ONLY = {"SequenceStar": "SequenceWithMemory", "FallbackStar": "Fallback", "SubTreePlus": "SubTree",
           "BlackboardCheckInt": "Precondition", "BlackboardCheckDouble": "Precondition",
           "BlackboardCheckString": "Precondition", "RetryUntilSuccesful": "RetryUntilSuccessful"}
# Node types of BT.CPP 4 that 3.8 does not register (src/bt_factory.cpp of each)
V4_ONLY = frozenset(BUILTIN) - frozenset(BUILTIN_V3)
# Attributes BT.CPP 4 reads and 3.8 does not know: the pre/post-condition scripts, _autoremap
V4_ATTRIBUTES = RESERVED - {"name", "ID"}
# Attributes only 3.8 reads: a SubTree's __shared_blackboard, a SubTreePlus's __autoremap
# (recursivelyCreateTree, src/xml_parsing.cpp), and Parallel's 3.8 thresholds
V3_ATTRIBUTES = frozenset({"__shared_blackboard", "__autoremap"})


# ---------------------------------------------------------------------------
# XML as tinyxml2 reads it

@dataclass(frozen=True)
class _Element:
    """One element: tag, attributes in document order (values as tinyxml2 reads them), children,
    the text right after its start tag, and where it starts."""

    tag: str
    attrs: Attrs
    children: tuple["_Element", ...]
    text: str
    pos: SourcePos

    def get(self, key: str) -> str | None:
        """Return the value of attribute `key`, or None."""
        for k, v in self.attrs:
            if k == key:
                return v
        return None


_NAME = re.compile(r"[^\s/>=\"'<&]+")
_SPACE = re.compile(r"\s*")


_ENTITIES = ((b"quot", 0x22), (b"amp", 0x26), (b"apos", 0x27), (b"lt", 0x3C), (b"gt", 0x3E))
_MAX_CODE_POINT = 0x10FFFF


def _utf8(ucs: int) -> bytes:
    """Encode a code point as tinyxml2's ConvertUTF32ToUTF8 does (surrogates too; nothing past 4 bytes)."""
    if ucs < 0x80:
        return bytes((ucs,))
    if ucs < 0x800:
        return bytes((0xC0 | ucs >> 6, 0x80 | ucs & 0x3F))
    if ucs < 0x10000:
        return bytes((0xE0 | ucs >> 12, 0x80 | ucs >> 6 & 0x3F, 0x80 | ucs & 0x3F))
    if ucs < 0x200000:
        return bytes((0xF0 | ucs >> 18, 0x80 | ucs >> 12 & 0x3F, 0x80 | ucs >> 6 & 0x3F, 0x80 | ucs & 0x3F))
    return b""


def _character_reference(buf: bytearray, p: int) -> tuple[int, bytes] | None:
    """Read the reference `&#...;` at `p` as tinyxml2's GetCharacterRef does: (end, bytes), or None
    where it gives up (the `&` is then kept)."""
    n = len(buf)
    if p + 2 >= n:
        return p + 1, b""                       # "&#" ends the value: tinyxml2 drops the "&"
    hexadecimal = buf[p + 2] == 0x78            # only a lowercase x
    first = p + 3 if hexadecimal else p + 2
    if first >= n:
        return None
    semicolon = buf.find(b";", first)
    if semicolon < 0:
        return None
    ucs, mult, base = 0, 1, 16 if hexadecimal else 10
    k, stop = semicolon - 1, 0x78 if hexadecimal else 0x23   # digits are read right to left, to an x or #
    while buf[k] != stop:
        digit = int(chr(buf[k]), 16) if chr(buf[k]) in "0123456789abcdefABCDEF" else 99
        if digit >= base:
            return None
        ucs = (ucs + mult * digit) & 0xFFFFFFFF
        mult = min(mult * base, _MAX_CODE_POINT)
        k -= 1
    if ucs > _MAX_CODE_POINT:
        return None
    return semicolon + 1, _utf8(ucs)


def _decode(raw: str) -> str:
    """Decode an attribute value or text as tinyxml2's StrPair::GetStr does, in place: newlines
    normalised (CR LF, LF CR and CR become LF), the five entities and character references
    decoded, any other `&` skipped over, which leaves the byte that stood at the write position
    (the `&` itself until something before it was decoded: `&quot;&b` reads `"qb` in BT.CPP),
    the value ending at a NUL."""
    buf = bytearray(raw.encode("utf-8", "surrogateescape"))
    n, p, q = len(buf), 0, 0
    while p < n:
        c = buf[p]
        nxt = buf[p + 1] if p + 1 < n else 0
        if c in (0x0D, 0x0A):
            p += 2 if nxt == (0x0A if c == 0x0D else 0x0D) else 1
            buf[q] = 0x0A
            q += 1
        elif c == 0x26 and nxt == 0x23:
            ref = _character_reference(buf, p)
            if ref is None:
                buf[q] = c
                p, q = p + 1, q + 1
            else:
                p, data = ref
                buf[q:q + len(data)] = data
                q += len(data)
        elif c == 0x26:
            for name, value in _ENTITIES:
                if buf.startswith(name, p + 1) and p + 1 + len(name) < n and buf[p + 1 + len(name)] == 0x3B:
                    buf[q] = value
                    p, q = p + len(name) + 2, q + 1
                    break
            else:
                p, q = p + 1, q + 1             # tinyxml2: "fixme: treat as error?"
        else:
            buf[q] = c
            p, q = p + 1, q + 1
    return bytes(buf[:q]).split(b"\0", 1)[0].decode("utf-8", "surrogateescape")


def _tolerant(text: str) -> tuple[str, list[tuple[Attrs, str]]]:
    """Return (text a strict parser accepts, with the same shape and positions; each start tag's
    attributes and following text as tinyxml2 reads them, in document order)."""
    out = list(text)
    tags: list[tuple[Attrs, str]] = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c == "&":
            out[i] = "_"                        # the text is taken from here, decoded as tinyxml2 does
            i += 1
            continue
        if c != "<":
            i += 1
            continue
        for opener, closer in (("<!--", "-->"), ("<![CDATA[", "]]>"), ("<?", "?>"), ("<!", ">"), ("</", ">")):
            if text.startswith(opener, i):
                end = text.find(closer, i + len(opener))
                i = n if end < 0 else end + len(closer)
                break
        else:
            m = _NAME.match(text, i + 1)
            if not m:
                i += 1
                continue
            j, attrs = m.end(), []
            while True:
                j = _SPACE.match(text, j).end()
                name = _NAME.match(text, j)
                if not name:
                    break
                j = _SPACE.match(text, name.end()).end()
                if not text.startswith("=", j):
                    break
                j = _SPACE.match(text, j + 1).end()
                if j >= n or text[j] not in "\"'":
                    break
                end = text.find(text[j], j + 1)
                if end < 0:
                    break
                for k in range(j + 1, end):
                    if text[k] in "<&":
                        out[k] = "_"            # the value is taken from here, not from the parser
                attrs.append((name.group(), _decode(text[j + 1:end])))
                j = end + 1
            close = text.find(">", j)
            after = ""
            if close > 0 and text[close - 1] != "/":
                nxt = text.find("<", close + 1)
                after = text[close + 1:nxt if nxt >= 0 else n]
            tags.append((tuple(attrs), after))
            i = j
    return "".join(out), tags


def _parse(text: str, file: str) -> _Element:
    """Parse `text` into elements, well-formedness and limits checked by parse_xml."""
    strict, tags = _tolerant(text)
    try:
        root = parse_xml(strict, file)
    except SchemalogError as err:
        if err.source_line is not None and err.line:      # the line as written, not as made strict
            err.source_line = text.splitlines()[err.line - 1]
        raise
    order: list[XNode] = []
    stack = [root]
    while stack:
        x = stack.pop()
        order.append(x)
        stack.extend(reversed(x.children))
    if len(order) != len(tags):
        raise SchemalogError("the XML could not be read as BT.CPP reads it (start tags and elements do not "
                             "match)", SourcePos(file, 1, 1))
    index = {id(x): k for k, x in enumerate(order)}

    def build(x: XNode) -> _Element:
        attrs, after = tags[index[id(x)]]
        if tuple(k for k, _ in attrs) != tuple(x.attrs):
            raise SchemalogError(f"the attributes of <{x.tag}> could not be read as BT.CPP reads them",
                                 SourcePos(file, x.line, x.column))
        return _Element(x.tag, attrs, tuple(build(c) for c in x.children), _decode(after).strip(),
                        SourcePos(file, x.line, x.column))

    return build(root)


# ---------------------------------------------------------------------------
# Reading

def _fail(element: _Element, message: str):
    """Raise a SchemalogError at `element`."""
    raise SchemalogError(message, element.pos)


def _check_root(root: _Element) -> None:
    """Refuse a document that is not a BT.CPP 4 <root>."""
    if root.tag != "root":
        _fail(root, f"a BT.CPP document starts with <root BTCPP_format=\"4\">, not <{root.tag}> (BT.CPP: "
                    f"\"The XML must have a root node called <root>\")")
    seen = None
    for child in root.children:
        if child.tag == "TreeNodesModel":
            if seen is not None:
                _fail(child, "Only a single node <TreeNodesModel> is supported (BT.CPP)")
            seen = child


# A port's type as a TreeNodesModel writes it: a C++ type name, `std::vector<geometry_msgs::msg::
# PoseStamped>`, `unsigned int`, `std::chrono::duration<long, std::ratio<1l, 1000l> >`, `BT::Any`
_TYPE_NAME = re.compile(r"\s*(?:[A-Za-z_][A-Za-z0-9_]*|::|<|>|,|\*|&|[0-9]+[A-Za-z]*|\s+)+\s*")


def _type_name(text: str) -> bool:
    """Whether `text` reads as a C++ type name (names, ::, template arguments; brackets balanced)."""
    if not _TYPE_NAME.fullmatch(text) or not re.match(r"\s*(?:::)?[A-Za-z_]", text):
        return False
    depth = 0
    for c in text:
        depth += (c == "<") - (c == ">")
        if depth < 0:
            return False
    return depth == 0


def _models(root: _Element, seen: dict | None = None) -> list[NodeModel]:
    """Read the entries of the <TreeNodesModel> of `root`; an ID declared twice with different
    kinds (here, or in `seen`: ID -> (kind, element) of the files read before) is refused, as no
    program registers one ID as two kinds, and a port type that is no C++ type name too."""
    out = []
    seen = {} if seen is None else seen
    for block in root.children:
        if block.tag != "TreeNodesModel":
            continue
        for entry in block.children:
            if entry.tag not in (*GENERIC, "SubTree"):
                continue
            node_id = entry.get("ID")
            if not node_id:
                if entry.tag == "SubTree":
                    _fail(entry, "a <SubTree> model needs an ID")
                continue                        # BT.CPP ignores it
            ports = []
            for p in entry.children:
                if p.tag not in PORT_TAGS:
                    continue
                name = p.get("name")
                if name is None or (not name and entry.tag != "SubTree"):
                    if entry.tag == "SubTree":
                        _fail(p, "Missing attribute [name] in port (SubTree model)")
                    continue
                if p.get("type") is not None and not _type_name(p.get("type")):
                    _fail(p, f"type=\"{p.get('type')}\" is not a C++ type name (e.g. int, std::string, "
                             f"geometry_msgs::msg::PoseStamped, std::vector<double>)")
                ports.append(Port(PORT_TAGS[p.tag], name, p.get("default"), p.get("type") or "",
                                  p.text or (p.get("description") or "").strip()))
            first = seen.get(node_id)
            if first is not None and first[0] != entry.tag:
                _fail(entry, f"{node_id} is declared twice with different kinds: as <{entry.tag}> here, as "
                             f"<{first[0]}> at {first[1].pos} (a program registers one ID as one kind)")
            seen.setdefault(node_id, (entry.tag, entry))
            out.append(NodeModel(node_id, entry.tag, tuple(ports)))
    return out


def read_models(text: str, file: str = "<xml>", seen: dict | None = None) -> tuple[NodeModel, ...]:
    """Read the <TreeNodesModel> entries of a nodes file (such as Nav2's nav2_tree_nodes.xml);
    `seen` carries the IDs of the nodes files read before (_models)."""
    root = _parse(text, file)
    _check_root(root)
    version = root.get("BTCPP_format")
    if version is not None and version not in ("3", "4"):
        _fail(root, f"BTCPP_format=\"{version}\": schemalog reads BT.CPP 3 (3.8) and 4 files")
    return tuple(_models(root, seen))


def _tells(root: _Element, declared: frozenset[str]) -> tuple[list[tuple[_Element, str]], list[tuple[_Element, str]]]:
    """What in a file's trees only BT.CPP 3.8 reads, and what only BT.CPP 4 reads, each with the
    element it is on (a node type a nodes file declares is the program's own: no tell)."""
    v3: list[tuple[_Element, str]] = []
    v4: list[tuple[_Element, str]] = []
    stack = [c for c in reversed(root.children) if c.tag == "BehaviorTree"]
    while stack:
        e = stack.pop()
        stack.extend(reversed(e.children))
        if e.tag in declared:
            continue
        if e.tag in V3_ONLY or e.tag == "SubTreePlus":
            v3.append((e, f"<{e.tag}>"))
        elif e.tag in V4_ONLY:
            v4.append((e, f"<{e.tag}>"))
        for k, _ in e.attrs:
            if k in V3_ATTRIBUTES or (e.tag == "Parallel" and k in ("success_threshold", "failure_threshold")):
                v3.append((e, f"{k}= on <{e.tag}>"))
            elif k in V4_ATTRIBUTES or (e.tag == "Parallel" and k in ("success_count", "failure_count")):
                v4.append((e, f"{k}= on <{e.tag}>"))
    return v3, v4


@dataclass(frozen=True)
class _Tree:
    """A <BehaviorTree> as read: its ID, its element, its root node."""

    id: str
    element: _Element
    root: Node


class _Reader:
    def __init__(self, read, models: tuple[NodeModel, ...], version: int | None = None,
                 notes: list | None = None) -> None:
        self.forced = version                   # --btcpp: the version every file is read under
        self.version = version or 4
        self.unmarked = False
        self.notes = notes if notes is not None else []
        self.read = read
        self.trees: list[_Tree] = []
        self.models: list[NodeModel] = []
        self.subtree_models: list[NodeModel] = []       # every SubTree entry, in BT.CPP's reading order
        self.extra = models
        self.includes: list[str] = []
        self.read_paths: dict[str, _Element] = {}     # the root of every file read, by its real path
        self.decided = False                          # the version told by the first file read
        self.suffix = 0
        self.v3_hint = False

    def kind(self, node_type: str, form: str) -> str | None:
        """Return a node type's kind: BT.CPP's own, a nodes file's (what the program registers, which
        BT.CPP goes by), the document's own model's, the generic form's, or None (opaque)."""
        builtin = BUILTIN_V3 if self.version == 3 else BUILTIN
        if node_type in builtin:
            return builtin[node_type]
        for m in (*self.extra, *self.models):
            if m.type == node_type:
                return m.kind
        return form or None

    def document(self, text: str, file: str, chain: tuple[str, ...], via: _Element | None = None) -> _Element:
        """Read one file: its includes first (as BT.CPP does), then its models and trees; a file
        reached through an <include> (`via`) is quoted only once it is a BT.CPP <root> document."""
        root = _parse(text, file) if via is None else read_included(_parse, text, file, via.get("path"), via.pos)
        _check_root(root)
        self.read_paths[os.path.realpath(file)] = root
        if len(chain) == 1 and not self.decided:
            self.decide(root, file)
            self.decided = True
        else:
            self.check_mark(root)
        if len(chain) == 1 and root.get("BTCPP_format") is None and self.version == 4:
            self.v3_hint = True
        for child in root.children:
            if child.tag == "include":
                self.include(child, file, chain)
        if any(c.tag == "TreeNodesModel" for c in root.children):
            # VerifyXML, when the file has a TreeNodesModel, looks for a missing ID among <root>'s
            # own children (not the TreeNodesModel's): a stray <Action/> there is refused
            for child in root.children:
                if child.tag in (*GENERIC, "SubTree") and child.get("ID") is None:
                    _fail(child, f"<{child.tag}> under <root> without ID: BT.CPP refuses it in a file with "
                                 f"a <TreeNodesModel> (The attribute [ID] is mandatory)")
        own = _models(root)
        self.subtree_models.extend(m for m in own if m.kind == "SubTree")
        self.models.extend(m for m in own if all(m.type != k.type for k in self.models))
        elements = len(root.children)
        for child in root.children:
            if child.tag == "BehaviorTree":
                self.tree(child, elements)
        return root

    def decide(self, root: _Element, file: str) -> None:
        """The version the files are read under: --btcpp's, else the top file's BTCPP_format, else
        its tells (what only one version reads), else 4, loaded alike by 3.8 (`unmarked`)."""
        mark = root.get("BTCPP_format")
        if self.forced is not None:
            if mark != str(self.forced) and mark is not None:
                self.notes.append(f"note: {root.pos}: BTCPP_format=\"{mark}\", read under BT.CPP "
                                  f"{_named(self.forced)} as --btcpp says")
            return
        if mark in ("3", "4"):
            self.version = int(mark)
            return
        if mark is not None:
            _fail(root, f"BTCPP_format=\"{mark}\": schemalog reads BT.CPP 3 (3.8) and 4 files; give the version "
                        f"with --btcpp 3 or --btcpp 4")
        declared = frozenset(m.type for m in self.extra if m.kind != "SubTree")
        v3, v4 = _tells(root, declared)
        if v3 and v4:
            (e3, w3), (e4, w4) = v3[0], v4[0]
            first, second = sorted(((e3, w3, "3"), (e4, w4, "4")), key=lambda t: (t[0].pos.line, t[0].pos.column))
            _fail(second[0], f"{second[1]} is BT.CPP {_named(int(second[2]))}'s only, and {first[1]} at "
                             f"{first[0].pos} is BT.CPP {_named(int(first[2]))}'s only: the file has no "
                             f"BTCPP_format, so its version cannot be told (mark it, or give --btcpp 3 or 4)")
        if v3:
            self.version = 3
        elif v4:
            self.version = 4
        else:
            self.unmarked = True

    def check_mark(self, root: _Element) -> None:
        """Refuse a file (included, or read after the first) marked for another version than the
        files are read under; one marked for the version an unmarked first file is read under
        (4) tells the program's version."""
        mark = root.get("BTCPP_format")
        if mark is None or mark == str(self.version):
            if mark is not None and self.forced is None:
                self.unmarked = False
            return
        if self.forced is not None:
            self.notes.append(f"note: {root.pos}: BTCPP_format=\"{mark}\", read under BT.CPP "
                              f"{_named(self.forced)} as --btcpp says")
            return
        _fail(root, f"BTCPP_format=\"{mark}\" in a file read with one read under BT.CPP {_named(self.version)}: "
                    f"one program reads every file under one version (give --btcpp to choose it)")

    def include(self, element: _Element, file: str, chain: tuple[str, ...]) -> None:
        """Read the file an <include> names, relative to the including file."""
        path = element.get("path")
        if path is None:
            _fail(element, "Invalid <include> tag: missing 'path' attribute (BT.CPP)")
        if element.get("ros_pkg") is not None and not os.path.isabs(path):
            _fail(element, f"<include ros_pkg={element.get('ros_pkg')!r}>: schemalog has no ROS package index; "
                           f"give the path relative to this file")
        if self.read is None:
            _fail(element, f"<include path={path!r}>: includes are read only from files")
        target = os.path.normpath(os.path.join(os.path.dirname(file), path))
        real = os.path.realpath(target)
        if target in chain or any(os.path.realpath(f) == real for f in chain):
            _fail(element, f"recursive include: {' -> '.join([*chain, target])}")
        if len(chain) > MAX_INCLUDE_DEPTH:
            _fail(element, f"includes nest deeper than {MAX_INCLUDE_DEPTH} files")
        what = not_regular(target)
        if what is not None:            # a FIFO would wait for a writer without end
            _fail(element, f"<include path={path!r}>: names {what}, not a file: BT.CPP includes files")
        if real in self.read_paths:
            # read already (another file includes it too, or it is one of the files given): BT.CPP
            # loads it again and registers the same trees and models anew, which changes nothing
            return
        try:
            text = self.read(target)
        except SchemalogError as err:
            _fail(element, f"<include path={path!r}>: {err.message}")
        except OSError as err:
            _fail(element, f"<include path={path!r}>: {err.strerror or err}")
        self.includes.append(target)
        self.document(text, target, (*chain, target), element)

    def tree(self, element: _Element, elements: int) -> None:
        """Register one <BehaviorTree>."""
        tree_id = element.get("ID")
        if not tree_id and elements > 1:
            _fail(element, "The tag <BehaviorTree> must have the attribute [ID] (BT.CPP: an unnamed tree "
                           "must be the only element of <root>)")
        if tree_id is None:                     # ID="" names the tree "" (BT.CPP's loadDocImpl)
            tree_id = f"BehaviorTree_{self.suffix}"
            self.suffix += 1
        if tree_id in (BUILTIN_V3 if self.version == 3 else BUILTIN):
            _fail(element, "The attribute [ID] of tag <BehaviorTree> must not use the name of a registered "
                           f"Node ({tree_id})")
        for other in self.trees:
            if other.id == tree_id:
                # BT.CPP's loadDocImpl keeps the last silently (tree_roots[name] = ...); Nav2 skips a
                # later file that defines an ID again: which tree runs would hang on the reading order
                _fail(element, f"BehaviorTree {tree_id} is defined twice (first at {other.element.pos}): "
                               f"BT.CPP would keep the one read last")
        if len(element.children) != 1:
            _fail(element, f"The tag <BehaviorTree> with ID '{tree_id}' must have exactly 1 child, not "
                           f"{len(element.children)}")
        self.trees.append(_Tree(tree_id, element, self.node(element.children[0])))

    def node(self, element: _Element) -> Node:
        """Convert one element of a tree to a Node, checked as BT.CPP checks it."""
        tag, node_id = element.tag, element.get("ID")
        if tag in V3_ONLY and self.v3_hint:
            _fail(element, f"<{tag}> is a BT.CPP 3 node (version 4 has {V3_ONLY[tag]}) and the file has no "
                           f"BTCPP_format=\"4\": a BT.CPP 3 file, read as one under --btcpp 3 (or without --btcpp)")
        if self.version == 3:
            self.v3_checks(element)
        if tag in (*GENERIC, "SubTree") and not node_id:
            _fail(element, f"The tag <{tag}> must have the attribute [ID]")
        if tag == "BehaviorTree":
            _fail(element, "a <BehaviorTree> inside a tree: trees are defined under <root> and used by <SubTree>")
        # an ID on another tag, an _autoremap that is not a boolean and a generic form naming
        # SubTree are refused where BT.CPP creates the node only (_subtree_checks); the rest is
        # checked before the children, as VerifyXML walks a tree (pre-order)
        count = len(element.children)
        if tag == "SubTreePlus" and self.version == 3:
            # SubtreePlusNode (3.8): a SubTree call whose remapping reads `{key}` as a key and
            # anything else as a constant; recursivelyCreateTree ignores its children, refused here
            if count:
                _fail(element, f"<SubTreePlus> with ID '{node_id}' has children, which BT.CPP 3.8 ignores; "
                               f"schemalog refuses them")
            if not node_id:
                _fail(element, "The node <SubTreePlus> must have the attribute [ID]")
            return Node("SubTreePlus", element.attrs, (), "", element.pos.line, element.pos.column, element.pos.file)
        if tag == "SubTree":
            if count:
                _fail(element, f"<SubTree> with ID '{node_id}' should not have any child")
            if node_id in (BUILTIN_V3 if self.version == 3 else BUILTIN):
                _fail(element, "The attribute [ID] of tag <SubTree> must not use the name of a registered "
                               f"Node ({node_id})")
            return Node("SubTree", element.attrs, (), "", element.pos.line, element.pos.column, element.pos.file)
        generic = tag in GENERIC
        node_type = node_id if generic else tag
        kind = self.kind(node_type, tag if generic else "")
        if kind == "Decorator" and count != 1:
            _fail(element, f"The node '{node_type}' must have exactly 1 child, not {count} (a decorator)")
        if kind == "Control" and count == 0:
            _fail(element, f"The node '{node_type}' must have 1 or more children (a control node)")
        if kind in ("Action", "Condition") and count:
            _fail(element, f"The node '{node_type}' must not have any child (an {kind.lower()})")
        if node_type == "ReactiveSequence":
            # VerifyXML looks a ReactiveSequence's children up by tag, so a generic form is an
            # unknown node there, and counts its async children (of BT.CPP's own, AsyncSequence)
            for child in element.children:
                if child.tag in GENERIC:
                    _fail(child, f"Unknown node type: {child.tag} (BT.CPP: a ReactiveSequence's children are "
                                 f"looked up by tag; write <{child.get('ID')}/>)")
            if sum(c.tag == "AsyncSequence" for c in element.children) > 1:
                _fail(element, "A ReactiveSequence cannot have more than one async child (BT.CPP)")
        children = tuple(self.node(c) for c in element.children)
        attrs = tuple((k, v) for k, v in element.attrs if not (generic and k == "ID"))
        return Node(node_type, attrs, children, tag if generic else "", element.pos.line, element.pos.column,
                    element.pos.file)


def _named(version: int) -> str:
    """A BT.CPP version as the messages name it: 3.8 or 4."""
    return "3.8" if version == 3 else "4"


def _v3_checks(reader: _Reader, element: _Element) -> None:
    """Refuse what BT.CPP 3.8 does not load in a tree read under 3.8: a node type of 4 only (3.8's
    VerifyXML: "Node not recognized"), RetryUntilSuccesful (3.8 registers it no more), a
    pre/post-condition attribute (a port of that name, which no node of 3.8 declares)."""
    tag = element.tag
    declared = any(m.type == tag for m in reader.extra)
    if tag in V4_ONLY and not declared:
        _fail(element, f"Node not recognized: {tag} (BT.CPP 3.8 does not register <{tag}>: it is BT.CPP 4's; "
                       f"{'its 3.8 counterpart is <SequenceStar>' if tag == 'SequenceWithMemory' else 'a 3.8 program registers it only as its own node, given with --nodes'})")
    if tag == "RetryUntilSuccesful" and not declared:
        _fail(element, "Node not recognized: RetryUntilSuccesful (BT.CPP 3.8 comments out the registration of the "
                       "misspelt name, src/bt_factory.cpp; write RetryUntilSuccessful)")
    for k, _ in element.attrs:
        if k in V4_ATTRIBUTES:
            _fail(element, f"{k}= is a BT.CPP 4 attribute (pre/post-conditions, _autoremap): BT.CPP 3.8 reads it as a "
                           f"port named {k}, which its own nodes refuse (Possible typo?) and no 3.8 program declares")


_Reader.v3_checks = _v3_checks


def _subtree_checks(reader: _Reader, main: str) -> None:
    """Check the trees BT.CPP creates, the main tree and the SubTrees it reaches, node by node in
    the order createNodeFromXML meets them: an ID on a tag that takes none, a generic form naming
    SubTree, a node of BT.CPP's own with attributes it refuses (bt/ports.py), a SubTree whose
    _autoremap is not a boolean, that names no tree, contains itself or leaves a mandatory port
    of its model unremapped. (A tree nothing reaches is never created, so BT.CPP checks none of this
    in it.)"""
    trees = {t.id: t for t in reader.trees}
    ports = {tree_id: {p.name: p for p in subtree_ports((m,))} for tree_id, m in _subtree_models(reader).items()}
    done: dict[str, int] = {}          # a tree checked whole, and the depth it was checked at

    def visit(tree_id: str, path: tuple[str, ...], depth: int) -> None:
        stack = [(trees[tree_id].root, depth)]
        while stack:
            n, level = stack.pop()
            stack.extend((c, level + 1) for c in reversed(n.children))
            where = SourcePos(n.file or trees[tree_id].element.pos.file, n.line, n.column)
            if level > MAX_TREE_DEPTH:
                # BT.CPP has no limit; the semantics and the provers recurse over the created tree
                chain = " -> ".join(path) if len(path) <= 8 else \
                    f"{' -> '.join(path[:3])} -> ... -> {' -> '.join(path[-3:])} ({len(path) - 1:,} SubTrees)"
                raise SchemalogError(f"the tree BT.CPP creates nests deeper than {MAX_TREE_DEPTH} levels here, "
                                     f"through {chain}: beyond schemalog's limit", where)
            if reader.version == 3:
                target = _v3_call_checks(n, where, trees, path)
                if target is not None and done.get(target, -1) < level + 1:
                    visit(target, (*path, target), level + 1)
                continue
            if not n.form and n.type != "SubTree" and n.attr("ID") is not None:
                raise SchemalogError(f"Attribute [ID] is not allowed in <{n.type}> (BT.CPP): only <Action>, "
                                     f"<Condition>, <Control>, <Decorator> and <SubTree> have one", where)
            if n.form and n.type == "SubTree":
                raise SchemalogError(f"<{n.form} ID=\"SubTree\"> (BT.CPP: Can't find a tree with name: SubTree): "
                                     f"a tree is called with <SubTree ID=\"TreeID\"/>", where)
            why = refusal(n.type, n.attrs) if n.type != "SubTree" or n.form else None
            if why is not None:
                raise SchemalogError(why, where)
            if n.type != "SubTree" or n.form:
                continue
            target = n.attr("ID")
            # BT.CPP reads _autoremap on a SubTree only (another node ignores it)
            autoremap = n.attr("_autoremap")
            if autoremap is not None and autoremap not in ("true", "TRUE", "True", "1", "false", "FALSE", "False", "0"):
                raise SchemalogError(f"_autoremap=\"{autoremap}\" is not a boolean (BT.CPP: invalid bool conversion)",
                                     where)
            if target not in trees:
                raise SchemalogError(f"<SubTree ID=\"{target}\"> names no BehaviorTree (BT.CPP: Can't find a "
                                     f"tree with name: {target})", where)
            if target in path:
                raise SchemalogError(f"SubTree {target} contains itself: {' -> '.join([*path, target])}", where)
            autoremap = n.attr("_autoremap", "false") in ("true", "TRUE", "True", "1")
            if not autoremap:
                for port in ports.get(target, {}).values():
                    # an attribute that is no port name (name, _a) remaps nothing
                    if (n.attr(port.name) is None or not is_port_name(port.name)) and not port.default:
                        raise SchemalogError(f"In the <TreeNodesModel> the <Subtree ID=\"{target}\"> is defining a "
                                             f"mandatory port called [{port.name}], but you are not remapping it",
                                             where)
            if done.get(target, -1) < level + 1:     # checked whole once at this depth or deeper: enough
                visit(target, (*path, target), level + 1)
        done[tree_id] = depth

    visit(main, (main,), 0)


def _v3_call_checks(n: Node, where: SourcePos, trees: dict, path: tuple) -> str | None:
    """_subtree_checks for a node of a tree read under BT.CPP 3.8 (createNodeFromXML and
    recursivelyCreateTree of 3.8's src/xml_parsing.cpp): an ID on another tag, a builtin's
    attributes, and a SubTree or SubTreePlus call: its tree, its __shared_blackboard or
    __autoremap a boolean (convertFromString<bool>); a SubTree model's ports are not read by 3.8.
    The tree a call names, to check next, or None."""
    call = n.type in ("SubTree", "SubTreePlus") and not n.form
    if not n.form and not call and n.attr("ID") is not None:
        raise SchemalogError(f"Attribute [ID] is not allowed in <{n.type}>: BT.CPP 3.8 reads it as a port of that "
                             f"name, which no node declares", where)
    why = refusal_v3(n.type, n.attrs) if not call else None
    if why is not None:
        raise SchemalogError(why, where)
    if not call:
        return None
    flag = "__shared_blackboard" if n.type == "SubTree" else "__autoremap"
    value = n.attr(flag)
    if value is not None and value not in ("true", "TRUE", "True", "1", "false", "FALSE", "False", "0"):
        raise SchemalogError(f"{flag}=\"{value}\" is not a boolean (BT.CPP 3.8: convertFromString<bool> throws)",
                             where)
    target = n.attr("ID")
    if target not in trees:
        raise SchemalogError(f"<{n.type} ID=\"{target}\"> names no BehaviorTree (BT.CPP 3.8: Can't find a tree "
                             f"with name: {target})", where)
    if target in path:
        raise SchemalogError(f"SubTree {target} contains itself: {' -> '.join([*path, target])}", where)
    return target


def _subtree_models(reader: _Reader) -> dict[str, NodeModel]:
    """BT.CPP's subtree_models: one model per tree ID, every entry of the ID merged (bt.model.subtree_ports)."""
    # read file by file, includes first, then the nodes files; an ID's entries are merged even
    # across files, as loadSubtreeModel fills one map for the whole factory
    entries: dict[str, list[NodeModel]] = {}
    for m in (*reader.subtree_models, *(m for m in reader.extra if m.kind == "SubTree")):
        entries.setdefault(m.type, []).append(m)
    return {tree_id: ms[0] if len(ms) == 1 else NodeModel(tree_id, "SubTree", subtree_ports(ms))
            for tree_id, ms in entries.items()}


def _children(node: Node) -> str:
    """How many children a node has, in words."""
    count = len(node.children)
    return f"{count} child{'ren' if count != 1 else ''}" if count else "no child"


def _kind_checks(reader: _Reader) -> None:
    """Refuse a node type used both as a leaf and with children, in any trees of any files read:
    BT.CPP registers a type as one kind, and VerifyXML checks every tree of every file against it."""
    # a type of known kind (BT.CPP's own, a model's) had each use checked against that kind
    # already (_Reader.node); an opaque type, or one written in two generic forms, is checked
    # here: whatever its registration, VerifyXML refuses one of the two uses (unregistered, both)
    first: dict[str, Node] = {}
    for t in reader.trees:
        for n in walk(t.root):
            if n.type in ("SubTree", "SubTreePlus") and not n.form:
                continue
            other = first.setdefault(n.type, n)
            if bool(other.children) != bool(n.children):
                where = SourcePos(n.file or t.element.pos.file, n.line, n.column)
                raise SchemalogError(
                    f"<{n.form or n.type}{f' ID={n.type!r}' if n.form else ''}> has {_children(n)} here and "
                    f"{_children(other)} at {SourcePos(other.file, other.line, other.column)}: BT.CPP registers a "
                    f"node type as a leaf or as a node with children, so it refuses one of the two uses however "
                    f"{n.type} is registered (\"must not have any child\" as an Action or Condition, \"must have "
                    f"1 or more children\" as a Control, \"exactly 1 child\" as a Decorator)", where)


def _tree_id_checks(reader: _Reader) -> None:
    """Refuse a tree ID that is also a node type: BT.CPP 4 calls a tree only through <SubTree>, so
    <CheckStatus/> naming the tree CheckStatus is "Node not recognized" unless CheckStatus is
    registered as a node, and then the tree's ID "must not use the name of a registered Node"."""
    trees = {t.id: t for t in reader.trees}
    for t in reader.trees:
        for n in walk(t.root):
            if n.type in trees and n.type not in ("SubTree", "SubTreePlus"):
                where = SourcePos(n.file or t.element.pos.file, n.line, n.column)
                raise SchemalogError(f"<{n.form or n.type}{f' ID={n.type!r}' if n.form else ''}> names the "
                                     f"BehaviorTree {n.type} as a node type; BT.CPP 4 refuses it (unregistered: "
                                     f"Node not recognized: {n.type}; registered: the tree's ID must not use the "
                                     f"name of a registered Node): call the tree with <SubTree ID=\"{n.type}\"/> "
                                     f"(the tree is at {trees[n.type].element.pos})", where)
    # a nodes file (`models`) stands for what the program registers; a document's own
    # TreeNodesModel registers nothing in BT.CPP, so a tree may share a name with one of its entries
    for m in reader.extra:
        if m.kind != "SubTree" and m.type in trees:
            _fail(trees[m.type].element, f"The attribute [ID] of tag <BehaviorTree> must not use the name of a "
                                         f"registered Node (BT.CPP): the nodes file declares {m.type} as "
                                         f"{'an' if m.kind[0] in 'AE' else 'a'} {m.kind}")


def _distinct(roots: list[_Element]) -> list[_Element]:
    """`roots` without repeats (a file named twice is read once), in order."""
    return list({id(r): r for r in roots}.values())


def _names(roots: list[_Element], most: int = 4) -> str:
    """The files of `roots` as a message lists them: the first few, then how many more."""
    names = [readable_name(r.pos.file) for r in _distinct(roots)]
    return ", ".join(names[:most]) + (f" and {len(names) - most} more" if len(names) > most else "")


def _agreed_main(reader: _Reader, roots: list[_Element]) -> tuple[str, _Element]:
    """The main tree of files none of which is given first (a folder's): the main_tree_to_execute
    they agree on, else the only tree; several, or none among several trees, is refused with the
    candidates (BT.CPP would take the first file opened's, which a folder's order does not say)."""
    named = [(r, r.get("main_tree_to_execute")) for r in _distinct(roots)
             if r.get("main_tree_to_execute") is not None]
    values = list(dict.fromkeys(v for _, v in named))
    if len(values) == 1:
        return values[0], named[0][0]
    if len(values) > 1:
        said = "; ".join(f"{r.pos}: main_tree_to_execute=\"{v}\"" for r, v in named)
        raise SchemalogError(f"the files read name different main trees ({said}): name the one to run with "
                             f"--task", named[1][0].pos)
    if len(reader.trees) == 1:
        return reader.trees[0].id, roots[0]
    called = {n.attr("ID") for t in reader.trees for n in walk(t.root) if n.type == "SubTree" and not n.form}
    candidates = [t.id for t in reader.trees if t.id not in called] or [t.id for t in reader.trees]
    raise SchemalogError(f"no file read names main_tree_to_execute, and the {len(_distinct(roots))} files ({_names(roots)}) "
                         f"define {len(reader.trees)} BehaviorTrees; the trees no <SubTree> calls: "
                         f"{', '.join(candidates[:10])}{f' and {len(candidates) - 10} more' if len(candidates) > 10 else ''}: name "
                         f"the one to run with --task")



def read_bt(text, file: str = "<xml>", read=None, models: tuple[NodeModel, ...] = (),
            main: str | None = None, *, main_from: int | None = 0, version: int | None = None,
            notes: list | None = None) -> Document:
    """Read a BT.CPP 4 document, or several as one program; `read(path) -> str` reads the files
    they include, `models` are node models from elsewhere (a nodes file: what the program
    registers) that the documents' own models take precedence over, except for a node type's
    kind, which BT.CPP takes from the registration (a TreeNodesModel registers nothing),
    `main` names the tree to run as BT.CPP's createTree(name) does (default, "" too: as createTreeFromText).

    `text` is one document's text (named `file`) or a sequence of (text, file) pairs, read in
    order into one program as BT.CPP's registerBehaviorTreeFromFile reads file after file into
    one factory: every check of one document holds for each, and across them (a tree ID defined
    twice, a node type used both as a leaf and with children, a SubTree naming a tree of another
    file). A file read already (through an <include>, or named twice) is not read again: BT.CPP
    would register the same trees anew. Without `main`, the main tree is the main_tree_to_execute
    of the document `main_from` indexes (BT.CPP's instantiateTree: the first document opened),
    else the only tree; with `main_from` None (a folder's files, none given first), the one
    main_tree_to_execute the documents agree on, else the only tree."""
    documents = ((text, file),) if isinstance(text, str) else tuple(text)
    if not documents:
        raise SchemalogError("no BT.CPP document to read")
    reader = _Reader(read, tuple(models), version, notes)
    roots: list[_Element] = []
    for body, name in documents:
        real = os.path.realpath(name)
        if real in reader.read_paths and os.path.isfile(name):
            roots.append(reader.read_paths[real])       # read already, through an <include> or named twice
            continue
        roots.append(reader.document(body, name, (os.path.normpath(name),)))
    root, single = roots[0], len(_distinct(roots)) == 1
    if not reader.trees:
        hint = (": it holds a <TreeNodesModel> only, a nodes file (give it with --nodes)"
                if any(c.tag == "TreeNodesModel" for c in root.children) else "")
        if not single:
            raise SchemalogError(f"the {len(_distinct(roots))} files read ({_names(roots)}) define no <BehaviorTree>")
        _fail(root, f"the document defines no <BehaviorTree>{hint}")
    _tree_id_checks(reader)
    _kind_checks(reader)
    ids = ", ".join(t.id for t in reader.trees)
    asked = main or None                # createTree("") is createTree(): the default main tree
    if asked is None and main_from is None:
        main, root = _agreed_main(reader, roots)
    else:
        if main_from is not None:
            root = roots[main_from]
        main = asked if asked is not None else root.get("main_tree_to_execute")
        if main is None:
            if len(reader.trees) != 1:
                where = "Your file must" if single else \
                    f"the first file ({readable_name(root.pos.file)}) names none, so the files read must"
                _fail(root, f"If you don't specify the attribute [main_tree_to_execute], {where} contain a "
                            f"single BehaviorTree (BT.CPP); {'it holds' if single else 'they hold'} "
                            f"{len(reader.trees)}: {ids} (name the one to run: --task on the command line)")
            main = reader.trees[0].id
    if all(t.id != main for t in reader.trees):
        named = f"the tree {main!r} asked for" if asked is not None else f"main_tree_to_execute=\"{main}\""
        _fail(root, f"{named} names no BehaviorTree; the {'document' if single else 'program'}'s "
                    f"trees: {ids}")
    _subtree_checks(reader, main)
    # the document's own models first, but each with the kind a nodes file registers its type as
    registered = {m.type: m.kind for m in reversed(reader.extra) if m.kind != "SubTree"}
    own = tuple(NodeModel(m.type, registered.get(m.type, m.kind), m.ports) if m.kind != "SubTree" else m
                for m in reader.models)
    merged = own + tuple(m for m in reader.extra if all(m.type != k.type for k in own))
    # a SubTree call gets the defaults of every model entry of its tree's ID (the semantics
    # reads them), so an ID's entries are kept as one, where the first stood
    calls = _subtree_models(reader)
    merged = tuple(calls.pop(m.type) if m.kind == "SubTree" else m for m in merged
                   if m.kind != "SubTree" or m.type in calls) + tuple(calls.values())
    return Document(tuple((t.id, t.root) for t in reader.trees), main, merged, tuple(reader.includes),
                    reader.version, reader.unmarked)


# ---------------------------------------------------------------------------
# Writing

_XML_NAME = re.compile(r"[A-Za-z_:][A-Za-z0-9_:.\-]*")


def _is_port(key: str) -> bool:
    """Tell whether attribute `key` can be a port (not reserved, not an `_`-attribute)."""
    return key not in RESERVED and not key.startswith("_")


def infer_models(document: Document) -> tuple[NodeModel, ...]:
    """Infer models for the custom node types the trees use and document.models does not declare."""
    declared = {m.type for m in document.models}
    kinds: dict[str, set[str]] = {}
    ports: dict[str, dict[str, str]] = {}
    for _, root in document.trees:
        for n in walk(root):
            builtin = BUILTIN_V3 if document.version == 3 else BUILTIN
            if n.type in builtin or n.type in declared or (n.type in ("SubTree", "SubTreePlus") and not n.form):
                continue
            kind = n.form or ("Action" if not n.children else "Decorator" if len(n.children) == 1 else "Control")
            kinds.setdefault(n.type, set()).add(kind)
            seen = ports.setdefault(n.type, {})
            for key, value in n.attrs:
                if _is_port(key):
                    literal = not (value.startswith("{") and value.endswith("}"))
                    seen[key] = "input" if literal or seen.get(key) == "input" else "inout"
    out = []
    for node_type, found in kinds.items():
        kind = next((k for k in GENERIC if k in found and k in ("Action", "Condition")), None) or (
            "Control" if "Control" in found else "Decorator")
        out.append(NodeModel(node_type, kind, tuple(Port(d, k) for k, d in ports[node_type].items())))
    return tuple(out)


def _name(text: str, what: str) -> str:
    """Return `text`, refused unless it is an XML name."""
    if not _XML_NAME.fullmatch(text):
        raise Unquotable(f"{what} {text!r} is not an XML name, so it cannot be written as one")
    return text


def _text(text: str) -> str:
    """Escape `text` as XML character data."""
    xml_attribute(text)                                     # raises Unquotable for what XML cannot hold
    return escape(text).replace("\r", "&#13;")


def _attrs(pairs) -> str:
    """Write attributes, each value quoted by xml_attribute."""
    return "".join(f" {_name(k, 'the attribute name')}={_value(k, v)}" for k, v in pairs)


def _value(name: str, value: str) -> str:
    """An attribute's value quoted, or Unquotable naming the attribute."""
    try:
        return xml_attribute(value)
    except Unquotable as err:
        raise Unquotable(f"the value of {name}: {err.message}") from None


def _node(n: Node, indent: str) -> list[str]:
    """Write the element of `n` and its children, one line each; what XML cannot hold is refused
    at the node's place in the file it was read from (tinyxml2 reads `p="&#x1;"`, XML has no U+0001)."""
    try:
        if n.form:
            head = f"{indent}<{_name(n.form, 'the form')} ID={xml_attribute(n.type)}{_attrs(n.attrs)}"
            tag = n.form
        else:
            tag = _name(n.type, "the node type")
            head = f"{indent}<{tag}{_attrs(n.attrs)}"
    except Unquotable as err:
        if not n.line or err.pos is not None:
            raise
        element = f"<{n.form} ID=\"{n.type}\">" if n.form else f"<{n.type}>"
        raise Unquotable(f"{element} cannot be written back: {err.message}",
                         SourcePos(n.file, n.line, n.column)) from None
    if not n.children:
        return [head + "/>"]
    lines = [head + ">"]
    for c in n.children:
        lines += _node(c, indent + "  ")
    return [*lines, f"{indent}</{tag}>"]


def _model(m: NodeModel) -> list[str]:
    """Write the TreeNodesModel entry of `m`."""
    head = f"    <{_name(m.kind, 'the model kind')} ID={xml_attribute(m.type)}"
    if not m.ports:
        return [head + "/>"]
    lines = [head + ">"]
    for p in m.ports:
        pairs = [("name", p.name)] + ([("type", p.type)] if p.type else []) + (
            [("default", p.default)] if p.default is not None else [])
        port = f"      <{PORT_TAG_OF[p.direction]}{_attrs(pairs)}"
        lines.append(port + (f">{_text(p.description)}</{PORT_TAG_OF[p.direction]}>" if p.description else "/>"))
    return [*lines, f"    </{m.kind}>"]


def write_bt(document: Document) -> str:
    """Write a BTCPP_format="4" document (BTCPP_format="3" for one read under 3.8) of every tree, in the document's order, with a TreeNodesModel."""
    trees = document.trees
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             f'<root BTCPP_format="{document.version}" main_tree_to_execute={xml_attribute(document.main)}>']
    for tree_id, root in trees:
        lines.append(f"  <BehaviorTree ID={xml_attribute(tree_id)}>")
        lines += _node(root, "    ")
        lines.append("  </BehaviorTree>")
    models = (*document.models, *infer_models(document))
    lines.append("  <TreeNodesModel>" if models else "  <TreeNodesModel/>")
    for m in models:
        lines += _model(m)
    if models:
        lines.append("  </TreeNodesModel>")
    lines += ["</root>", ""]
    return "\n".join(lines)


__all__ = ["read_bt", "read_models", "write_bt", "infer_models", "BUILTIN", "MAX_INCLUDE_DEPTH"]
