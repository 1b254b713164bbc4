"""`python -m schemalog` runs the command line."""

try:
    from .cli.main import run
except KeyboardInterrupt:         # Ctrl-C while starting: no traceback, the status shells expect
    raise SystemExit(130) from None

run()
