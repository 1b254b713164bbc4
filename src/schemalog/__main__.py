"""`python -m schemalog` runs the command line."""

from .cli.main import run

run()
