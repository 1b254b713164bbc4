"""Behaviour trees with BehaviorTree.CPP 4's semantics: the model, the node semantics, the
compression rewrites and their prover (docs/semantics.md, "Behaviour trees")."""
