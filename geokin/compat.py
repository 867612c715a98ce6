"""Names kept from earlier versions of geokin, each with a DeprecationWarning.

A renamed keyword still works through :func:`renamed_keywords`, a renamed
attribute through :func:`renamed_attribute`; both say what to write instead.
The README's "Renamed in this version" table lists them all.

Examples
--------
>>> @renamed_keywords(input="input_name")
... def pick(input_name=None):
...     return input_name
>>> import warnings
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     pick(input="theta")
'theta'
>>> print(caught[0].message)
pick(input=...) is now pick(input_name=...); the old name will be removed
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = ["renamed_attribute", "renamed_keywords"]

F = TypeVar("F", bound=Callable[..., Any])


def renamed_keywords(**renames: str) -> Callable[[F], F]:
    """Let a function take the old names of renamed keywords, with a DeprecationWarning.

    Parameters
    ----------
    **renames : str
        Each old keyword and its new name.
    """
    def decorate(function: F) -> F:
        @functools.wraps(function)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            if not kwargs or renames.keys().isdisjoint(kwargs):
                return function(*args, **kwargs)  # no old name: the common case, quickly
            for old, new in renames.items():
                if old in kwargs:
                    if new in kwargs:
                        raise TypeError(f"{function.__name__}() got both {old}= and {new}=; "
                                        f"{old} is the old name of {new}")
                    warnings.warn(f"{function.__name__}({old}=...) is now "
                                  f"{function.__name__}({new}=...); the old name will be "
                                  "removed", DeprecationWarning, stacklevel=2)
                    kwargs[new] = kwargs.pop(old)
            return function(*args, **kwargs)

        return wrapper  # type: ignore[return-value]

    return decorate


def renamed_attribute(old: str, new: str) -> property:
    """Return a read-only property ``old`` that gives ``new``, with a DeprecationWarning."""
    def getter(self: object) -> Any:
        warnings.warn(f"{type(self).__name__}.{old} is now {type(self).__name__}.{new}; the "
                      "old name will be removed", DeprecationWarning, stacklevel=2)
        return getattr(self, new)

    return property(getter, doc=f"The old name of :attr:`{new}` (deprecated).")
