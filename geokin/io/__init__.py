"""Reading and writing: construction scripts, and sweeps exported as tables.

- :mod:`~geokin.io.script`: construction scripts (TOML), read with
  :func:`load` / :func:`loads` and written with :func:`dump`;
- :mod:`~geokin.io.export`: a sweep's columns written as CSV, JSON or NPZ.
"""

from ..budgets import MAX_SCRIPT_BYTES
from .script import OPS, dump, load, loads, script_steps

__all__ = ["MAX_SCRIPT_BYTES", "OPS", "dump", "load", "loads", "script_steps"]
