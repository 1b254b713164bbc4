"""Behaviour trees as BehaviorTree.CPP 4 loads them: the data that the BT semantics, the
compression rewrites and the prover work on (docs/semantics.md, "Behaviour trees").

    Node      = Node(type, attrs, children, form, line, column)  one element of a <BehaviorTree>
    Attrs     = tuple[tuple[str, str], ...]      its attributes in document order, ID excepted
    NodeModel = NodeModel(type, kind, ports)     a node type's kind and ports (TreeNodesModel)
    Kind      = "Action" | "Condition" | "Control" | "Decorator" | "SubTree"
    Document  = Document(trees, main, models)    the <BehaviorTree>s by ID, the one that runs,
                                                 the TreeNodesModel entries, the BT.CPP version
                                                 (3: 3.8, 4) it was read under

`type` is the node's registration ID: the element's tag (`<ComputePathToPose .../>`), or the ID
of the generic forms (`<Action ID="ComputePathToPose" .../>`, whose tag `form` keeps so that
an export writes the element the way it was read). A leaf's identity in a trace is its type
and its ports by name (every attribute but `name` and the `_`-attributes, in no order: BT.CPP
keeps a node's ports in a map): two leaves with the same identity do the same thing to the
robot, whatever they are called and in whatever order their element writes the ports. `attrs`
keeps the document's order, so that a tree is written back as it was read.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field

Attrs = tuple[tuple[str, str], ...]
KINDS = ("Action", "Condition", "Control", "Decorator", "SubTree")
GENERIC_FORMS = frozenset(KINDS) - {"SubTree"}     # <Action ID="X"/>, <Condition ID=..>, ...


@dataclass(frozen=True)
class Node:
    """One node of a behaviour tree: its type, its attributes and its children."""

    type: str
    attrs: Attrs = ()
    children: tuple["Node", ...] = ()
    form: str = ""                                   # "Action" etc. for <Action ID=..>, else ""
    line: int = field(default=0, compare=False)
    column: int = field(default=0, compare=False)
    file: str = field(default="", compare=False)      # the file it was read from (an <include>d one)

    def attr(self, key: str, default: str | None = None) -> str | None:
        """The value of attribute `key`, or `default`."""
        for k, v in self.attrs:
            if k == key:
                return v
        return default

    @property
    def name(self) -> str:
        """The instance name BT.CPP shows (the `name` attribute, else the type)."""
        return self.attr("name") or self.type

    @property
    def ports(self) -> Attrs:
        """The port assignments: every attribute but `name` and the `_`-attributes."""
        return tuple((k, v) for k, v in self.attrs if k != "name" and not k.startswith("_"))

    @property
    def identity(self) -> tuple[str, Attrs]:
        """What a trace records of a tick of this node: its type and its ports, sorted by name."""
        # BT.CPP gives a node its ports by name (PortsRemapping is a map): `p="1" q="2"` and
        # `q="2" p="1"` are one node
        return (self.type, tuple(sorted(self.ports)))

    def with_children(self, children: tuple["Node", ...]) -> "Node":
        """This node over other children."""
        return Node(self.type, self.attrs, tuple(children), self.form, self.line, self.column, self.file)


@dataclass(frozen=True)
class Port:
    """A port a node type declares: direction (input, output, inout), name, default."""

    direction: str
    name: str
    default: str | None = None
    type: str = ""
    description: str = ""


@dataclass(frozen=True)
class NodeModel:
    """A node type as a TreeNodesModel declares it (or as a table of known nodes defines it)."""

    type: str
    kind: str
    ports: tuple[Port, ...] = ()


def subtree_ports(models) -> tuple[Port, ...]:
    """The ports of SubTree models of one ID merged as BT.CPP's loadSubtreeModel merges them."""
    # entry by entry, its input ports, then output, then inout; a later port of a name replaces
    # the one before (subtree_model.ports[name] = port), keeping its place
    ports: dict[str, Port] = {}
    for m in models:
        for direction in ("input", "output", "inout"):
            ports.update((p.name, p) for p in m.ports if p.direction == direction)
    return tuple(ports.values())


@dataclass(frozen=True)
class Document:
    """A BT.CPP document: its behaviour trees by ID, the ID of the main one, the node models."""

    trees: tuple[tuple[str, Node], ...]
    main: str
    models: tuple[NodeModel, ...] = ()
    includes: tuple[str, ...] = ()              # the files read through <include>, in order
    version: int = 4                            # the BT.CPP it was read under: 3 (3.8) or 4
    unmarked: bool = False                      # no BTCPP_format, no node of one version only, no
                                                # --btcpp: BT.CPP 3.8 and 4 both load it

    def tree(self, tree_id: str) -> Node | None:
        """The root of the behaviour tree `tree_id`, or None."""
        for key, root in self.trees:
            if key == tree_id:
                return root
        return None

    @property
    def root(self) -> Node:
        """The root of the main tree."""
        root = self.tree(self.main)
        assert root is not None, self.main
        return root

    def model(self, node_type: str) -> NodeModel | None:
        """The model the document declares for `node_type`, or None."""
        for m in self.models:
            if m.type == node_type:
                return m
        return None

    def subtree_model(self, tree_id: str) -> NodeModel | None:
        """The SubTree model the document declares for the tree `tree_id`, or None."""
        return next((m for m in self.models if m.type == tree_id and m.kind == "SubTree"), None)

    def with_trees(self, trees: tuple[tuple[str, Node], ...]) -> "Document":
        """The same document over other trees."""
        return Document(tuple(trees), self.main, self.models, self.includes, self.version, self.unmarked)

    def under(self, version: int) -> "Document":
        """The same document read under BT.CPP `version` (3 or 4), no longer unmarked."""
        return Document(self.trees, self.main, self.models, self.includes, version, False)


def walk(node: Node) -> Iterator[Node]:
    """The nodes of the tree under `node`, in document order (pre-order)."""
    stack = [node]
    while stack:
        n = stack.pop()
        yield n
        stack.extend(reversed(n.children))


def size(document: Document) -> int:
    """The number of nodes in all the document's trees."""
    return sum(1 for _, root in document.trees for _ in walk(root))
