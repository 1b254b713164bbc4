"""The public API's layer: what `import schemalog` exports (see schemalog/__init__.py) and
what the command line is built on. knowledge (load, query, lint), task (Task, compress,
save, exports), report (verify), execution (Run), workspace and answers (the query
relations and Prolog answers the REPL shares)."""
