"""What `schemalog compress` shows of one compression besides the trees: its figures as JSON
(docs/formats.md) and the panels of the paper's Figure 2, whose middle one, the merge with
perceptual aliasing, is a second compression (propagate none) searched for aliased behaviours.

    compression_json(small, report)   -> dict      figure2(small, sympy_budget) -> (panels, initial)

The panels are drawn by the command line (formats.render: DOT, pictures).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .. import defaults

if TYPE_CHECKING:
    from .report import Report
    from .task import Task


def compression_json(small: Task, report: Report | None = None) -> dict:
    """A compressed task's figures, notes and tree as `compress --json` prints them (with its
    verification, when proved)."""
    from ..formats.render import tree_json

    result = small.compression
    data = {"task": small.original.name, "propagate": result.propagate,
            "nodes_before": result.nodes_before, "nodes_after": result.nodes_after,
            "depth_before": result.depth_before, "depth_after": result.depth_after,
            "reduction_degree": round(result.reduction_degree, 4),
            "conditions": {"simplified": result.conditions_simplified,
                           "needed_sympy": result.conditions_needing_sympy},
            "notes": list(result.notes), "tree": tree_json(small.tree)}
    if report is not None:
        data["verification"] = report.as_json()
    return data


def figure2(small: Task, sympy_budget: int = defaults.SYMPY_BUDGET) -> tuple[list, frozenset]:
    """The paper's Figure 2's panels: the learned tree, the merge with perceptual aliasing
    (propagate none, its aliased behaviours marked), and the merge `small` is; and the initial
    state they are coloured in."""
    from ..formats.render import aliased_behaviours, figure2_panels

    original = small.original.tree
    initial = small.original.initial_atoms()
    merged, complete = aliased_behaviours(original, small.tree, initial)
    searched = "" if complete else "in the first 2,000 reachable states"
    propagate = small.compression.propagate
    if propagate == "none":
        return figure2_panels(original, small.tree, propagate, initial,
                              merged_aliased=merged, searched=searched), initial
    aliasing = small.original.compress("none", sympy_budget=sympy_budget).tree
    return figure2_panels(original, small.tree, propagate, initial, aliasing,
                          aliased_behaviours(original, aliasing, initial)[0], merged, searched), initial
