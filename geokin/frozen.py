"""Read-only arrays and mappings, for results that do not change once made.

Examples
--------
>>> import numpy as np
>>> a = read_only(np.zeros(2))
>>> a.flags.writeable
False
>>> m = read_only_mapping({"x": 1})
>>> m["x"] = 2
Traceback (most recent call last):
...
TypeError: 'mappingproxy' object does not support item assignment
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from types import MappingProxyType
from typing import Any, TypeVar

import numpy as np

__all__ = ["Frozen", "read_only", "read_only_mapping"]

K = TypeVar("K")
F = TypeVar("F", bound="Frozen")


def read_only(array: np.ndarray) -> np.ndarray:
    """Return ``array`` marked read-only (a view where it is not already so)."""
    if array.flags.writeable:
        array = array.view()
        array.setflags(write=False)  # what flags.writeable = False does, twice as fast
    return array


_EMPTY: Mapping[Any, Any] = MappingProxyType({})
"""The read-only empty mapping, shared: nothing can be put in it."""


def read_only_mapping(mapping: Mapping[K, Any]) -> Mapping[K, Any]:
    """Return a read-only view of a copy of ``mapping``, its arrays made read-only."""
    if not mapping:
        return _EMPTY
    return MappingProxyType({key: read_only(value) if isinstance(value, np.ndarray) else value
                             for key, value in mapping.items()})


_MAPPINGS = (dict, MappingProxyType, Mapping)  # the abstract class last: its test is slow


class Frozen:
    """A frozen dataclass whose mapping fields are read-only views, and that pickles.

    Subclasses list the fields to protect in ``_read_only``; mapping proxies
    do not pickle, so a frozen object is rebuilt from plain copies.
    """

    _read_only: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        for name in self._read_only:
            value = getattr(self, name)
            if isinstance(value, np.ndarray):
                object.__setattr__(self, name, read_only(value))
            elif isinstance(value, _MAPPINGS):
                object.__setattr__(self, name, read_only_mapping(value))

    @classmethod
    def _made_read_only(cls: type[F], **fields: Any) -> F:
        """Make one from every field, its arrays and mappings already read-only.

        What the engine makes for every sweep, without the dataclass's
        checks: the caller guarantees what ``__post_init__`` would make sure
        of (see :func:`read_only` and :func:`read_only_mapping`).
        """
        made = object.__new__(cls)
        made.__dict__.update(fields)
        return made

    def __reduce__(self) -> tuple[Any, ...]:
        values = [getattr(self, f.name) for f in dataclasses.fields(self)  # type: ignore
                  if f.init]
        plain = [dict(v) if isinstance(v, MappingProxyType) else v for v in values]
        return (type(self), tuple(plain))
