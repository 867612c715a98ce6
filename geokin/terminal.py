r"""Text from scripts made safe to show: control characters escaped, long text shortened.

A script is hostile until shown otherwise. A name, a description or a key
holding an escape sequence could retitle the terminal, clear the screen or
hide the rest of a message; a newline would break an error's one line; a
ten-megabyte name would bury it. Everything geokin prints that came from a
script or a command line passes through :func:`escape`, and what it quotes
in an error through :func:`shorten`.

Examples
--------
>>> print(escape("six-bar\x1b]0;owned\x07"))
six-bar\x1b]0;owned\x07
>>> shorten("x" * 1000, 20)
'xxxxxxxxxxxxx…xxxxxx [1,000 characters]'
"""

from __future__ import annotations

import re

__all__ = ["LONG_TEXT", "MAX_MESSAGE", "clip_message", "escape", "one_line", "shorten"]

LONG_TEXT = 80
"""The most characters of one name or value quoted in a message."""

MAX_MESSAGE = 2000
"""The most characters of one message printed on a terminal."""

_NAMED = {"\t": "\\t", "\n": "\\n", "\r": "\\r"}


def _escape_char(ch: str) -> str:
    if ch in _NAMED:
        return _NAMED[ch]
    code = ord(ch)
    if code <= 0xFF:
        return f"\\x{code:02x}"
    if code <= 0xFFFF:
        return f"\\u{code:04x}"
    return f"\\U{code:08x}"


def escape(text: str) -> str:
    r"""Return ``text`` with every character that is not printable written as an escape.

    Escaped are the C0 and C1 control characters (ESC, BEL, newline, tab
    and the others), DEL, the format characters (bidirectional overrides,
    zero-width spaces, the byte-order mark), line and paragraph separators,
    lone surrogates and unassigned code points: everything Python's
    :meth:`str.isprintable` refuses except the plain space. They are
    written as Python writes them: ``\n``, ``\x1b``, ``\u202e``. The
    result is one line that changes nothing on a terminal but the text shown.

    Parameters
    ----------
    text : str

    Returns
    -------
    str

    Examples
    --------
    >>> print(escape("mm\n\x1b[2J\u202egnp.exe"))
    mm\n\x1b[2J\u202egnp.exe
    >>> escape("plain text, ünïcödé and 中文") == "plain text, ünïcödé and 中文"
    True
    """
    if text.isprintable():
        return text
    return "".join(ch if ch.isprintable() else _escape_char(ch) for ch in text)


def shorten(text: str, limit: int = LONG_TEXT) -> str:
    """Return ``text``, or its start and end around an ellipsis if it is over ``limit``.

    A shortened text ends with its length in brackets, so that a reader
    knows it was cut.

    Parameters
    ----------
    text : str
    limit : int
        The most characters kept of ``text`` (at least 10).

    Returns
    -------
    str

    Examples
    --------
    >>> shorten("l3")
    'l3'
    >>> shorten("a" * 50 + "b" * 50, 30)
    'aaaaaaaaaaaaaaaaaaaa…bbbbbbbbb [100 characters]'
    """
    cut = cut_text(text, limit)
    return text if cut is text else f"{cut} [{len(text):,} characters]"


def cut_text(text: str, limit: int = LONG_TEXT) -> str:
    """Return ``text`` if it is short, else its start and end around an ellipsis.

    The one rule by which geokin shortens what it shows: :func:`shorten` adds
    the length, :func:`geokin.errors.quote` quotes the result.

    Examples
    --------
    >>> cut_text("a" * 50 + "b" * 50, 30)
    'aaaaaaaaaaaaaaaaaaaa…bbbbbbbbb'
    """
    limit = max(int(limit), 10)
    if len(text) <= limit:
        return text
    tail = (limit - 1) // 3
    head = limit - 1 - tail
    return f"{text[:head]}…{text[len(text) - tail:]}"


def one_line(text: str, limit: int = MAX_MESSAGE) -> str:
    r"""Return text fit to print as one line: shortened to ``limit`` characters, then escaped.

    Unlike :func:`clip_message`, long words (a deep path) are kept whole
    unless the whole text is too long.

    Examples
    --------
    >>> print(one_line("geokin: error: bad\nname\x1b[2J"))
    geokin: error: bad\nname\x1b[2J
    >>> len(one_line("x" * 10_000_000)) < MAX_MESSAGE + 30
    True
    """
    return escape(shorten(text, limit))


_LONG_RUN = re.compile(rf"\S{{{LONG_TEXT + 1},}}")
_QUOTED = re.compile(r"([^\w]*)(.*?)([^\w]*)", re.DOTALL)


def _shorten_run(run: str) -> str:
    """Shorten one long word of a message, its quotes and punctuation kept whole."""
    match = _QUOTED.fullmatch(run)
    assert match is not None  # every part of the pattern may be empty
    before, core, after = match.groups()
    if not core:  # punctuation only
        before, core, after = "", run, ""
    cut = cut_text(core, LONG_TEXT)
    return run if cut is core else f"{before}{cut}{after} [{len(core):,} characters]"


def clip_message(message: str, limit: int = MAX_MESSAGE) -> str:
    r"""Return a message fit to print as one line of reasonable length.

    Every run of more than :data:`LONG_TEXT` characters without a space (a
    huge number, name or expression quoted in the message) is shortened,
    the whole is escaped, and a message still over ``limit`` characters
    keeps its start and end.

    Parameters
    ----------
    message : str
    limit : int
        The most characters of the result, before the length note.

    Returns
    -------
    str

    Examples
    --------
    >>> len(clip_message("got " + "9" * 400))
    101
    >>> clip_message("got " + "9" * 400)[-20:]
    '999 [400 characters]'
    >>> print(clip_message("two\nlines"))
    two\nlines
    """
    if len(message) > LONG_TEXT:
        message = _LONG_RUN.sub(lambda match: _shorten_run(match.group()), message)
    return shorten(escape(message), limit)
