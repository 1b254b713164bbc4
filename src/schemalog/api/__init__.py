"""The API layer: what `import schemalog` exports (schemalog/__init__.py, docs/api.md) and
what the command line is built on (cli/ parses arguments, calls these and prints).

Public, through the package's names: knowledge (load, loads, Knowledge, QueryError), task
(Task, Compression), report (verify, Report, Counterexample), execution (Run), limits
(timeout=, max_memory=, LimitExceeded).

Private, for the command line and the notebooks: check, convert, generate, learning, figures,
workspace and answers (the query relations and Prolog answers the REPL shares), repl,
failures, arguments, choosing, outputs, notebook.
"""
