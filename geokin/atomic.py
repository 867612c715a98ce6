"""Write output files whole or not at all.

Every file geokin writes (CSV, JSON, NPZ, PNG, SVG, GIF, HTML, MP4) is
first written to a hidden temporary file in the same folder, named
``.<name>.<random>.partial<suffix>``, and renamed over the target only once
it is complete and on disk (:func:`os.replace`, atomic on one file system).
If anything goes wrong on the way, an error or Ctrl-C, the temporary file
is removed and the target is untouched: an interrupted run leaves the old
file or none, never half of a new one.

A symbolic link is followed: the file it points to is replaced, and the link
stays. A target that is not a regular file (a named pipe, a device) is
written directly, as there is no old file to keep. A file that cannot be
written (a folder that is read-only, a full disk) raises :class:`OutputError`
naming the target, not the temporary file.

Examples
--------
>>> import pathlib, tempfile
>>> folder = pathlib.Path(tempfile.mkdtemp())
>>> with replacing(folder / "out.txt", "w") as f:
...     _ = f.write("whole")
>>> (folder / "out.txt").read_text()
'whole'
>>> try:
...     with replacing(folder / "out.txt", "w") as f:
...         _ = f.write("half")
...         raise KeyboardInterrupt
... except KeyboardInterrupt:
...     pass
>>> (folder / "out.txt").read_text(), sorted(p.name for p in folder.iterdir())
('whole', ['out.txt'])
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
import signal
import stat
import threading

from .errors import GeokinError

__all__ = ["OutputError", "replacing", "replacing_path", "require_folder"]


class OutputError(GeokinError, OSError):
    """An output file cannot be written; the file it would replace is left as it was.

    Parameters
    ----------
    errno : int
    strerror : str
        What the system said.
    filename : str
        The output file (not the temporary one).

    Examples
    --------
    >>> import errno
    >>> print(OutputError(errno.ENOSPC, "No space left on device", "big.csv"))
    cannot write 'big.csv': No space left on device
    """

    def __str__(self):
        return f"cannot write {self.filename!r}: {self.strerror}"


def _output_error(err: OSError, target: str) -> OutputError:
    return OutputError(err.errno, err.strerror or str(err), target)


def require_folder(path: str | os.PathLike[str]) -> None:
    """Raise :class:`OutputError` unless the folder that would hold ``path`` exists.

    Check it before the work whose result the file would hold: a missing
    folder is then reported before a long job, not after it, and in the same
    words whatever the file.

    Examples
    --------
    >>> try:
    ...     require_folder("no/such/folder/out.csv")
    ... except OutputError as err:
    ...     print(err)
    cannot write 'no/such/folder/out.csv': the folder 'no/such/folder' does not exist
    """
    folder = os.path.dirname(os.fspath(path)) or "."
    if os.path.isdir(folder):
        return
    if os.path.exists(folder):
        raise OutputError(errno.ENOTDIR, f"{folder!r} is not a folder", os.fspath(path))
    raise OutputError(errno.ENOENT, f"the folder {folder!r} does not exist", os.fspath(path))


@contextlib.contextmanager
def _interrupts_held():
    """Hold back SIGINT and SIGTERM while a rename or a clean-up runs to its end.

    A signal that comes meanwhile is delivered when the block ends. Only the
    main thread receives Python's signals, so only there is anything held.
    """
    held = {signal.SIGINT, signal.SIGTERM}
    if not (hasattr(signal, "pthread_sigmask")
            and threading.current_thread() is threading.main_thread()):
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _create_temporary(target: str) -> tuple[int, str]:
    """Create a new hidden file beside ``target``; return its descriptor and path.

    The file gets the permissions a new file would (0666 less the umask),
    not the 0600 of :func:`tempfile.mkstemp`.
    """
    folder, name = os.path.split(target)
    stem, suffix = os.path.splitext(name)
    # names are limited to 255 bytes: keep the temporary one well short of that
    stem, suffix = stem[:80], suffix[:20]
    while True:
        temp = os.path.join(folder, f".{stem}.{secrets.token_hex(4)}.partial{suffix}")
        try:
            return os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666), temp
        except FileExistsError:  # pragma: no cover - 32 random bits already taken
            continue


def _finish(temp: str, target: str):
    """Flush ``temp`` to disk, give it the target's permissions and rename it over the target."""
    with open(temp, "rb") as f:
        os.fsync(f.fileno())
    with contextlib.suppress(OSError):  # keep the permissions of the file replaced
        os.chmod(temp, stat.S_IMODE(os.stat(target).st_mode))
    os.replace(temp, target)


@contextlib.contextmanager
def replacing_path(path):
    """Give a temporary path to write to; rename it over ``path`` when the block succeeds.

    For writers that open a file by name themselves (ffmpeg). The temporary
    path ends with the same suffix as ``path``, so a writer that picks its
    format by the suffix picks the same one.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write. Its folder must exist.

    Yields
    ------
    str
        An empty file's path in the same folder, hidden; or the target itself
        if it is not a regular file.

    Raises
    ------
    OutputError
        If the file cannot be written; the target is then untouched.
    """
    target = os.fspath(path)
    if os.path.islink(target):
        target = os.path.realpath(target)
    try:
        special = not stat.S_ISREG(os.stat(target).st_mode)
    except OSError:  # not there yet
        special = False
    if special:  # a pipe or a device: write into it
        yield target
        return
    temp = None
    try:
        try:
            fd, temp = _create_temporary(target)
            os.close(fd)
        except OSError as err:
            raise _output_error(err, target) from err
        try:
            yield temp
        except OSError as err:
            if err.filename is not None or isinstance(err, GeokinError):
                raise  # about another file, or already said
            raise _output_error(err, target) from err  # a write that failed: a full disk
        with _interrupts_held():
            try:
                _finish(temp, target)
            except OSError as err:
                raise _output_error(err, target) from err
    except BaseException:
        if temp is not None:
            with _interrupts_held(), contextlib.suppress(OSError):
                os.unlink(temp)
        raise


@contextlib.contextmanager
def replacing(path, mode: str = "wb", **kwargs):
    """Open a temporary file to write; rename it over ``path`` when the block succeeds.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write. Its folder must exist.
    mode : {"wb", "w"}
        Binary or text.
    **kwargs
        Passed to :func:`open` (``encoding``, ``newline``).

    Yields
    ------
    file object
        Open for writing; closed when the block ends.

    Raises
    ------
    OutputError
        If the file cannot be written; the target is then untouched.
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"mode must be 'w' or 'wb', got {mode!r}")
    with replacing_path(path) as temp, open(temp, mode, **kwargs) as f:
        yield f
