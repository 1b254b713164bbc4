"""`python -m schemalog` runs the command line."""

from .cli import run

run()
