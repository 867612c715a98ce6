"""Reading and writing: construction scripts, and sweeps exported as tables.

- :mod:`~geokin.io.script`: construction scripts (TOML), read with
  :func:`load` / :func:`loads` and written with :func:`dump`;
- :mod:`~geokin.io.export`: a sweep's columns (:func:`columns`) written as
  CSV, JSON or NPZ, to an open file (:func:`write_csv`, :func:`write_json`,
  :func:`write_npz`) or to a path, whole or not at all (:func:`export_sweep`).
- :mod:`~geokin.io.numbers`: floats written as the shortest text that reads
  back exactly, the text of ``repr``, a whole array at a time with numpy
  (:func:`~geokin.io.numbers.shortest_texts`); CSV numbers are written so.
"""

from ..budgets import MAX_SCRIPT_BYTES
from .export import (
    EXPORT_FORMATS,
    columns,
    export_blocks,
    export_sweep,
    shortest_text,
    write_csv,
    write_json,
    write_npz,
)
from .script import OPS, dump, load, loads, script_steps

__all__ = [
    "EXPORT_FORMATS",
    "MAX_SCRIPT_BYTES",
    "OPS",
    "columns",
    "dump",
    "export_blocks",
    "export_sweep",
    "load",
    "loads",
    "script_steps",
    "shortest_text",
    "write_csv",
    "write_json",
    "write_npz",
]
