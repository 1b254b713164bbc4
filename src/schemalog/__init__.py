"""schemalog: symbolic task compression for structured robot tasks, as a Prolog-style engine."""

__version__ = "0.1.0"
