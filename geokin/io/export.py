"""Sweeps exported as tables: CSV, JSON and NPZ files of named columns.

:func:`columns` turns a :class:`~geokin.results.Sweep` into a table, a dict
of column name to a 1-D array with one value per sample, in this order:

- one column per input, named as the input: radians for an angle input;
- ``valid``: whether each sample can be assembled;
- with a :class:`~geokin.kinematics.Motion`: ``time`` (seconds from the
  first sample) and ``flagged`` (1 where the rates may be less accurate
  than stated, as near a toggle);
- where the sweep changes branch, or when asked: ``<node>.branch``, 0 or 1
  for every two-root node, as the input value alone no longer tells the
  samples apart;
- per point ``<point>.x`` and ``<point>.y``, and with a motion
  ``<point>.vx .vy`` (per second) and ``<point>.ax .ay`` (per second
  squared): NaN where a sample cannot be assembled, except for ground
  points (:attr:`~geokin.construction.Compiled.ground`), whose place is
  known at every sample, and whose rates are 0;
- per link asked for, ``<link>.angle`` (the direction from its first point
  to its second, unwrapped along the sweep: :func:`~geokin.kinematics.link_angles`),
  and with a motion ``<link>.omega`` and ``<link>.alpha``, its angular
  velocity and acceleration;
- per slider asked for, ``<slider>.position``, its block's position along
  its guide from the guide's first point
  (:func:`~geokin.kinematics.slider_positions`), and with a motion
  ``<slider>.velocity`` and ``<slider>.acceleration`` along the guide.

:func:`write_csv`, :func:`write_json` and :func:`write_npz` write a table to
a file already open; :func:`export_sweep` writes a sweep or a table to a
path, in the format its suffix names, whole or not at all.

Formats
-------
CSV
    A header of the names, then one row per sample. Numbers are written as
    the shortest text that reads back exactly, whole numbers without ``.0``
    (``20``, ``0.1``, ``1e-300``); NaN as ``nan``; boolean columns as 1 and 0.
JSON
    One object of arrays, in the column order; boolean columns as ``true``
    and ``false``, ``null`` for NaN and infinities.
NPZ
    numpy's archive of one ``.npy`` array per column, with its dtype; read
    it with :func:`numpy.load`. Any column name works, even ``file`` or
    ``allow_pickle``, which :func:`numpy.savez` would take for its own
    arguments.

Units
-----
Python is in radians: the input columns of :func:`columns` hold the
sweep's own values, link angles are radians (per second, per second
squared for their rates). ``geokin trace`` writes angles in degrees, the
script's unit: it asks for ``degrees=True``, which gives link angles in
degrees (deg/s, deg/s^2), and passes the input values it swept, as typed,
in ``inputs``, since converting the radians back (``np.degrees``) can land
an ulp away from them (22.499999999999996 for 22.5). From Python,
``degrees=True`` alone converts the angle inputs too::

    columns(s, inputs={name: np.degrees(v) for name, v in s.inputs.items()})
    columns(s, links=["crank"], degrees=True)

Examples
--------
>>> import io
>>> import numpy as np
>>> import geokin
>>> c = geokin.Construction("crank")
>>> c.input("theta")
>>> c.fixed("O", 0, 0)
>>> c.polar("A", "O", 2, "theta")
>>> s = geokin.sweep(c, [0.0, np.pi / 2])
>>> table = columns(s, ["A"])
>>> list(table)
['theta', 'valid', 'A.x', 'A.y']
>>> text = io.StringIO()
>>> write_csv(table, text)
>>> print(text.getvalue(), end="")
theta,valid,A.x,A.y
0,1,2,0
1.5707963267948966,1,1.2246467991473532e-16,2
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
import pathlib
import shutil
import tempfile
import zipfile
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import IO, TextIO, cast

import numpy as np
from numpy.lib import format as npy_format
from numpy.typing import ArrayLike

from ..atomic import replacing
from ..errors import ConstructionError, did_you_mean
from ..kinematics import Motion, link_angles, slider_positions
from ..results import Sweep
from ..units import angles_to_script, to_script_array
from .numbers import FIELD_WIDTH, text_fields

__all__ = ["EXPORT_FORMATS", "columns", "export_blocks", "export_sweep", "shortest_text",
           "write_csv", "write_json", "write_npz"]

EXPORT_FORMATS = (".csv", ".json", ".npz")
"""The suffixes :func:`export_sweep` writes, in any case."""

_ROWS_JOINED = 8192  # CSV rows joined at a time: their bytes stay in the cache


def columns(sweep: Sweep, points: Sequence[str] | None = None, *, motion: Motion | None = None,
            branches: bool | None = None,
            inputs: Mapping[str, ArrayLike] | None = None,
            links: Sequence[str] = (), sliders: Sequence[str] = (),
            degrees: bool = False) -> dict[str, np.ndarray]:
    """Return a sweep as a table: column name to a 1-D array of one value per sample.

    Parameters
    ----------
    sweep : Sweep
    points : sequence of str, optional
        The points whose columns to give, in this order (default: every
        point, in the construction's order).
    motion : Motion, optional
        Velocities and accelerations of this sweep (:func:`geokin.motion`):
        adds ``time``, ``flagged`` and ``<point>.vx .vy .ax .ay``.
    branches : bool, optional
        Whether to give a ``<node>.branch`` column for every two-root node
        (default: where the sweep changes branch at least once).
    inputs : mapping of str to array_like, optional
        The values for the input columns, one array per input of the sweep,
        in place of the sweep's own (radians for an angle input): for
        instance the values a script gave, in degrees.
    links : sequence of str, optional
        Declared links whose ``<link>.angle`` to give, in this order, with a
        motion also ``<link>.omega`` and ``<link>.alpha`` (default: none).
    sliders : sequence of str, optional
        Declared sliders whose ``<slider>.position`` to give, in this order,
        with a motion also ``<slider>.velocity`` and
        ``<slider>.acceleration`` (default: none).
    degrees : bool, optional
        Give link angles and their rates in degrees (deg, deg/s, deg/s^2),
        as a script would, and angle inputs in degrees unless ``inputs``
        gives their values; radians by default.

    Returns
    -------
    dict of str to ndarray
        Inputs, ``valid``, then ``time`` and ``flagged``, the branches, the
        points, the links and the sliders (see :mod:`geokin.io.export`).
        ``valid`` and ``flagged`` are boolean, branches 0.0 or 1.0; the
        arrays may be read-only views of the sweep's.

    Raises
    ------
    ConstructionError
        If an input has the name of another column (``valid``, or ``time``
        or ``flagged`` with a motion): both cannot be written.
    KeyError
        For a point, link or slider the construction does not have.
    ValueError
        If ``motion`` is of another sweep, or ``inputs`` does not give one
        array of the sweep's length for each input.

    Examples
    --------
    >>> import numpy as np
    >>> import geokin
    >>> c = geokin.Construction("crank")
    >>> c.input("theta")
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 2, "theta")
    >>> s = geokin.sweep(c, [0.0, np.pi])
    >>> table = columns(s, ["A"], motion=geokin.motion(s, speed=2 * np.pi))
    >>> list(table)
    ['theta', 'valid', 'time', 'flagged', 'A.x', 'A.y', 'A.vx', 'A.vy', 'A.ax', 'A.ay']
    >>> table["theta"], table["time"]
    (array([0.        , 3.14159265]), array([0. , 0.5]))
    >>> columns(s, ["A"], inputs={"theta": [0, 180]})["theta"]
    array([  0., 180.])

    A link's angle, in degrees as ``geokin trace`` writes it:

    >>> c.link("crank", "O", "A")
    >>> s = geokin.sweep(c, [0.0, np.pi / 2, np.pi])
    >>> table = columns(s, [], links=["crank"], degrees=True)
    >>> list(table), table["crank.angle"].round(12)
    (['theta', 'valid', 'crank.angle'], array([  0.,  90., 180.]))
    """
    n = len(sweep)
    if motion is not None and not _same_motion(motion.sweep, sweep):
        raise ValueError("motion is of another sweep: compute it with geokin.motion(sweep)")
    compiled = sweep.construction
    declared_links = [link.name for link in compiled.links]
    declared_sliders = [slider.name for slider in compiled.sliders]
    for name in links:
        if name not in declared_links:
            raise KeyError(f"no link {name!r}{did_you_mean(name, declared_links)}")
    for name in sliders:
        if name not in declared_sliders:
            raise KeyError(f"no slider {name!r}{did_you_mean(name, declared_sliders)}")
    if inputs is None:
        values: Mapping[str, ArrayLike] = sweep.inputs
        if degrees:
            values = {name: to_script_array(compiled.inputs[name], v)
                      for name, v in sweep.inputs.items()}
    else:
        if set(inputs) != set(sweep.inputs):
            raise ValueError(f"inputs must give the sweep's inputs {list(sweep.inputs)}, "
                             f"got {list(inputs)}")
        values = inputs
    table: dict[str, np.ndarray] = {}

    def add(name: str, array: ArrayLike) -> None:
        if name in table:  # only an input can have a column's name: the others have a dot
            raise ConstructionError(f"column {name!r} would be written twice: an input has "
                                    "that name; rename the input to export it")
        table[name] = np.asarray(array)

    for name in sweep.inputs:
        column = np.asarray(values[name], dtype=float)
        if column.shape != (n,):
            raise ValueError(f"inputs[{name!r}] must have shape ({n},), got {column.shape}")
        add(name, column)
    add("valid", sweep.valid.copy())
    if motion is not None:
        add("time", motion.time)
        add("flagged", motion.flagged)
    if branches or (branches is None and sweep.events):
        for node, branch in sweep.branches.items():
            add(f"{node}.branch", branch.astype(float))
    for point in sweep.points if points is None else points:
        # a ground point is where it is at every sample, assembled or not: only the
        # points that move are unknown where the mechanism cannot be assembled
        ground = compiled.step_named(point).node.name in compiled.ground
        x, y = sweep.points.xy(point) if ground else sweep[point].T
        add(f"{point}.x", x)
        add(f"{point}.y", y)
        if motion is not None:
            v, a = motion.velocity[point], motion.acceleration[point]
            if ground:  # and it stands still
                v, a = np.zeros((n, 2)), np.zeros((n, 2))
            add(f"{point}.vx", v[:, 0])
            add(f"{point}.vy", v[:, 1])
            add(f"{point}.ax", a[:, 0])
            add(f"{point}.ay", a[:, 1])
    angle = angles_to_script if degrees else np.asarray
    if links:
        angles = link_angles(sweep)
        for link in links:
            add(f"{link}.angle", angle(angles[link]))
            if motion is not None:
                add(f"{link}.omega", angle(motion.angular_velocity[link]))
                add(f"{link}.alpha", angle(motion.angular_acceleration[link]))
    if sliders:
        positions = slider_positions(sweep)
        for slider in sliders:
            add(f"{slider}.position", positions[slider])
            if motion is not None:
                add(f"{slider}.velocity", motion.slider_velocity[slider])
                add(f"{slider}.acceleration", motion.slider_acceleration[slider])
    return table


def _same_motion(a: Sweep, b: Sweep) -> bool:
    """Whether two sweeps are one motion: the same, or of one construction alike throughout.

    Two sweeps of a construction at the same inputs, parameters and branches
    are the same motion, made twice.
    """
    def alike(x: Mapping[str, np.ndarray], y: Mapping[str, np.ndarray]) -> bool:
        return x.keys() == y.keys() and all(np.array_equal(x[k], y[k]) for k in x)

    return a is b or (a.construction is b.construction and alike(a.inputs, b.inputs)
                      and alike(a.parameters, b.parameters) and alike(a.branches, b.branches)
                      and np.array_equal(a.valid, b.valid))


def _arrays(table: Mapping[str, ArrayLike]) -> dict[str, np.ndarray]:
    """Return a table's columns as arrays, checked: string names, 1-D, of one length."""
    arrays = {}
    for name, column in table.items():
        if not isinstance(name, str):
            raise TypeError(f"a column's name must be a string, got {name!r}")
        array = np.asarray(column)
        if array.ndim != 1:
            raise ValueError(f"column {name!r} must be one-dimensional, got shape {array.shape}")
        arrays[name] = array
    lengths = {len(a) for a in arrays.values()}
    if len(lengths) > 1:
        raise ValueError("columns of different lengths: "
                         + ", ".join(f"{name!r} has {len(a)}" for name, a in arrays.items()))
    return arrays


def shortest_text(value: float) -> str:
    """Write a number as the shortest text that reads back exactly, without a ``.0``.

    Examples
    --------
    >>> [shortest_text(v) for v in (16.0, 0.25, 1e-320, -0.0, float("nan"))]
    ['16', '0.25', '1e-320', '-0', 'nan']
    """
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def _csv_cells(array: np.ndarray) -> np.ndarray:
    """Format one column: 1 and 0 for booleans, else the shortest exact decimal.

    Returns the cells as rows of ASCII bytes, left-aligned, padded with NUL
    bytes, as narrow as the longest cell: the text of :func:`shortest_text`
    for every value, written by :func:`~geokin.io.numbers.text_fields` (a
    column of one value is formatted once).

    Examples
    --------
    >>> cells = _csv_cells(np.array([20.0, -0.0, 0.1, 1e16, np.nan, -np.inf]))
    >>> cells.view(f"S{cells.shape[1]}").ravel().tolist()
    [b'20', b'-0', b'0.1', b'1e+16', b'nan', b'-inf']
    """
    if array.dtype == bool:
        return (array.view(np.uint8) + np.uint8(ord("0")))[:, None]
    values = array.astype(float)
    if values.size and values[0] == values[0] and (values == values[0]).all():
        text = np.frombuffer(shortest_text(values[0]).encode("ascii"), dtype=np.uint8)
        return np.broadcast_to(text, (values.size, text.size))
    fields = text_fields(values)
    # as wide as the longest text: the bytes in use in any row, 8 at a time
    words = fields.view("<u8")
    used = np.array([np.bitwise_or.reduce(words[:, i]) for i in range(words.shape[1])])
    width = np.flatnonzero(used.view(np.uint8))
    return fields[:, :width[-1] + 1] if width.size else fields[:, :1]


def _csv_rows(cells: Sequence[np.ndarray]) -> bytes:
    """Join columns of cells (see :func:`_csv_cells`) as CSV rows: commas, a line feed each."""
    widths = [c.shape[1] + 1 for c in cells]
    rows = np.empty((len(cells[0]), sum(widths)), dtype=np.uint8)
    end = 0
    for c, width in zip(cells, widths, strict=True):
        if c.strides[1] == 1:  # a cell copied as one item of its bytes, not byte by byte
            rows[:, end:end + width - 1].view(f"V{width - 1}")[...] = c.view(f"V{width - 1}")
        else:
            rows[:, end:end + width - 1] = c
        rows[:, end + width - 1] = ord(",")
        end += width
    rows[:, -1] = ord("\n")
    # every cell's NUL padding dropped at once: what is left is the rows as text
    return rows[rows != 0].tobytes()


def write_csv(columns: Mapping[str, ArrayLike], stream: IO[str] | IO[bytes], *,
              rows_per_write: int = 32_768, header: bool = True) -> None:
    """Write a table as CSV: a header of names, then one row per sample.

    Numbers are written as the shortest text that reads back exactly
    (:func:`shortest_text`), formatted a block of rows at a time with numpy
    (:func:`~geokin.io.numbers.text_fields`).

    Parameters
    ----------
    columns : mapping of str to array_like
        The table (see :func:`columns`): 1-D columns of one length.
    stream : text or binary file
        Open for writing; a text file opened with ``newline=""`` ends each
        row with a line feed on every system, as a binary file does. Names
        go to a binary file in UTF-8.
    rows_per_write : int, optional
        Rows formatted and written at a time, so a long table never exists
        whole as text in memory.
    header : bool, optional
        Whether to write the names first: not for the rows of a table
        written block by block after its first block.

    Examples
    --------
    >>> import io
    >>> import numpy as np
    >>> text = io.StringIO()
    >>> write_csv({"t": [0.0, 0.1, 20.0], "x": [np.nan, 1e-300, -2.5],
    ...            "ok": np.array([False, True, True])}, text)
    >>> print(text.getvalue(), end="")
    t,x,ok
    0,nan,0
    0.1,1e-300,1
    20,-2.5,1
    """
    arrays = _arrays(columns)
    # names are quoted only where CSV needs it: a comma, a quote, a line break
    names = io.StringIO()
    if header:
        csv.writer(names, lineterminator="\n").writerow(arrays)
    write: Callable[[bytes], object]
    if isinstance(stream, (io.RawIOBase, io.BufferedIOBase)) or "b" in getattr(stream, "mode",
                                                                                 ""):
        binary = cast(IO[bytes], stream)
        binary.write(names.getvalue().encode("utf-8"))
        write = binary.write
    else:
        text = cast(IO[str], stream)
        text.write(names.getvalue())

        def write(data: bytes) -> None:
            text.write(data.decode("ascii"))

    blocks = list(arrays.values())
    total = len(blocks[0]) if blocks else 0
    for start in range(0, total, rows_per_write):
        # a block of rows at a time: formatting goes column by column, then the rows are
        # joined a few thousand at a time, which stay in the cache
        cells = [_csv_cells(a[start:start + rows_per_write]) for a in blocks]
        for i in range(0, len(cells[0]), _ROWS_JOINED):
            write(_csv_rows([c[i:i + _ROWS_JOINED] for c in cells]))


def _json_cells(array: np.ndarray) -> bytes:
    """Format one column for JSON, the values joined by ``", "``.

    Booleans are true and false, numbers written as ``repr`` writes them
    (:func:`~geokin.io.numbers.text_fields`), null for NaN and infinities.

    Examples
    --------
    >>> _json_cells(np.array([0.5, 2.0, np.nan, -np.inf]))
    b'0.5, 2.0, null, null'
    """
    if array.dtype == bool:
        fields = np.where(array, b"true", b"false").view(np.uint8).reshape(array.size, -1)
    else:
        values = array.astype(float)
        fields = text_fields(values, point_zero=True)
        fields[~np.isfinite(values)] = np.frombuffer(b"null".ljust(FIELD_WIDTH, b"\0"),
                                                     dtype=np.uint8)
    cells = np.empty((array.size, fields.shape[1] + 2), dtype=np.uint8)
    cells[:, :-2] = fields
    cells[:, -2:] = np.frombuffer(b", ", dtype=np.uint8)
    return cells[cells != 0].tobytes()[:-2]


def write_json(columns: Mapping[str, ArrayLike], stream: TextIO, *,
               values_per_write: int = 100_000) -> None:
    """Write a table as one JSON object of arrays (null where not a finite number).

    Parameters
    ----------
    columns : mapping of str to array_like
        The table (see :func:`columns`): 1-D columns of one length.
    stream : text file
        Open for writing.
    values_per_write : int, optional
        Values formatted and written at a time, so a long table never
        exists whole as text in memory.

    Examples
    --------
    >>> import io
    >>> import numpy as np
    >>> text = io.StringIO()
    >>> write_json({"t": [0.0, 0.5], "x": [np.nan, 2.0], "ok": np.array([False, True])}, text)
    >>> print(text.getvalue(), end="")
    {"t": [0.0, 0.5], "x": [null, 2.0], "ok": [false, true]}
    """
    stream.write("{")
    for k, (name, array) in enumerate(_arrays(columns).items()):
        stream.write(("" if k == 0 else ", ") + json.dumps(name) + ": [")
        for start in range(0, len(array), values_per_write):
            cells = _json_cells(array[start:start + values_per_write]).decode("ascii")
            stream.write(("" if start == 0 else ", ") + cells)
        stream.write("]")
    stream.write("}\n")


def write_npz(columns: Mapping[str, ArrayLike], file: IO[bytes]) -> None:
    """Write a table as an NPZ archive: one ``<name>.npy`` array per column.

    The archive is the one :func:`numpy.savez` writes, built here so that a
    column may have any name: ``savez`` takes the arrays as keywords, and
    a column named ``file`` or ``allow_pickle`` would be taken for its own
    argument.

    Parameters
    ----------
    columns : mapping of str to array_like
        The table (see :func:`columns`): 1-D columns of one length, of
        numbers or booleans (no Python objects: the archive holds no pickle).
    file : binary file
        Open for writing.

    Examples
    --------
    >>> import io
    >>> import numpy as np
    >>> archive = io.BytesIO()
    >>> write_npz({"file": [1.5, 2.0], "allow_pickle": np.array([True, False])}, archive)
    >>> _ = archive.seek(0)
    >>> data = np.load(archive)
    >>> data["file"], data["allow_pickle"]
    (array([1.5, 2. ]), array([ True, False]))
    """
    arrays = _arrays(columns)
    with zipfile.ZipFile(file, mode="w", compression=zipfile.ZIP_STORED,
                         allowZip64=True) as archive:
        for name, array in arrays.items():
            with archive.open(f"{name}.npy", mode="w", force_zip64=True) as member:
                npy_format.write_array(member, array, allow_pickle=False)


def export_blocks(tables: Iterable[Mapping[str, ArrayLike]], path: str | os.PathLike[str],
                  rows: int) -> pathlib.Path:
    """Write a table made block by block (its rows in order) to a CSV or NPZ file.

    For tables too long to hold whole: each block is written as it comes,
    and memory stays that of one block. The file is the one
    :func:`export_sweep` writes of the whole table, written whole or not at
    all (an NPZ's columns wait in hidden files beside it until the last block).

    Parameters
    ----------
    tables : iterable of mappings of str to array_like
        The blocks: the same columns in the same order, consecutive rows.
    path : str or os.PathLike
        A ``.csv`` or ``.npz`` file; its folder must exist.
    rows : int
        The rows of all blocks together.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    ValueError
        For another suffix, blocks whose rows do not add up to ``rows``, or
        a block whose columns (names, order, kinds) are not the first's;
        the file is then left as it was.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> blocks = ({"i": np.arange(k, k + 2.0), "ok": np.ones(2, bool)} for k in (0, 2, 4))
    >>> path = export_blocks(blocks, folder / "t.npz", 6)
    >>> np.load(path)["i"].tolist(), sorted(p.name for p in folder.iterdir())
    ([0.0, 1.0, 2.0, 3.0, 4.0, 5.0], ['t.npz'])
    """
    path = pathlib.Path(path)
    kind = path.suffix.lower()
    if kind not in (".csv", ".npz"):
        raise ValueError(f"cannot write {str(path)!r} block by block: use a .csv or .npz file")
    written = 0
    kinds: list[tuple[str, np.dtype]] = []

    def checked(table):
        """Return a block's columns, refused unless they are the first block's, in order."""
        arrays = _arrays(table)
        these = [(name, a.dtype) for name, a in arrays.items()]
        if kinds and these != kinds:
            raise ValueError(f"a block's columns {[n for n, _ in these]} are not the first "
                             f"block's {[n for n, _ in kinds]} (or not of the same kinds)")
        kinds[:] = these
        return arrays

    if kind == ".csv":
        with replacing(path, "w", encoding="utf-8", newline="") as f:
            for i, table in enumerate(tables):
                arrays = checked(table)
                write_csv(arrays, f, header=i == 0)
                written += len(next(iter(arrays.values()), ()))
            if written != rows:
                raise ValueError(f"the blocks hold {written} rows, not {rows}")
        return path
    with tempfile.TemporaryDirectory(dir=path.parent, prefix=f".{path.name}.") as folder, \
            contextlib.ExitStack() as files:
        # each column an .npy file of all rows, appended to as the blocks come
        columns_written: dict[str, IO[bytes]] = {}
        for table in tables:
            arrays = checked(table)
            size = len(next(iter(arrays.values()), ()))
            for name, array in arrays.items():
                if name not in columns_written:
                    file: IO[bytes] = files.enter_context(
                        open(os.path.join(folder, f"{len(columns_written)}.npy"), "wb"))
                    header = npy_format.header_data_from_array_1_0(array)
                    header["shape"] = (rows,)
                    npy_format.write_array_header_1_0(file, header)
                    columns_written[name] = file
                columns_written[name].write(np.ascontiguousarray(array).tobytes())
            written += size
        if written != rows:
            raise ValueError(f"the blocks hold {written} rows, not {rows}")
        for written_file in columns_written.values():
            written_file.flush()
        with replacing(path, "wb") as f, zipfile.ZipFile(
                f, mode="w", compression=zipfile.ZIP_STORED, allowZip64=True) as archive:
            for i, name in enumerate(columns_written):
                with archive.open(f"{name}.npy", mode="w", force_zip64=True) as member, \
                        open(os.path.join(folder, f"{i}.npy"), "rb") as source:
                    shutil.copyfileobj(source, member, 2**22)
    return path


def export_sweep(data: Sweep | Mapping[str, ArrayLike], path: str | os.PathLike[str],
                 points: Sequence[str] | None = None, *, motion: Motion | None = None,
                 branches: bool | None = None,
                 inputs: Mapping[str, ArrayLike] | None = None,
                 links: Sequence[str] = (), sliders: Sequence[str] = (),
                 degrees: bool = False) -> pathlib.Path:
    """Write a sweep, or a table of columns, to a CSV, JSON or NPZ file.

    The format is the path's suffix, in any case: ``.csv``, ``.json`` or
    ``.npz``. The file is written whole or not at all
    (:func:`geokin.atomic.replacing`): an error or Ctrl-C meanwhile leaves
    the file that was there, or none.

    Parameters
    ----------
    data : Sweep or mapping of str to array_like
        A sweep, made into a table by :func:`columns` with the options
        below; or a table already made.
    path : str or os.PathLike
        The file to write; its folder must exist.
    points, motion, branches, inputs, links, sliders, degrees
        As for :func:`columns`; only with a sweep.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    ValueError
        For a suffix other than those of :data:`EXPORT_FORMATS`.
    geokin.atomic.OutputError
        If the file cannot be written; the file there is left as it was.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import numpy as np
    >>> import geokin
    >>> c = geokin.Construction("crank")
    >>> c.input("theta")
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 2, "theta")
    >>> s = geokin.sweep(c, np.linspace(0, np.pi, 5))
    >>> path = export_sweep(s, pathlib.Path(tempfile.mkdtemp()) / "crank.npz", ["A"])
    >>> data = np.load(path)
    >>> list(data), bool((data["A.x"] == s["A"][:, 0]).all())
    (['theta', 'valid', 'A.x', 'A.y'], True)
    """
    path = pathlib.Path(path)
    kind = path.suffix.lower()
    if kind not in EXPORT_FORMATS:
        raise ValueError(f"cannot export to {str(path)!r}: use a .csv, .json or .npz file")
    if isinstance(data, Sweep):
        table = columns(data, points, motion=motion, branches=branches, inputs=inputs,
                        links=links, sliders=sliders, degrees=degrees)
    elif (any(given is not None for given in (points, motion, branches, inputs))
          or links or sliders or degrees):
        raise TypeError("points, motion, branches, inputs, links, sliders and degrees make "
                        "a table of a sweep; a table is written as it is")
    else:
        table = _arrays(data)  # checked before the file is opened
    if kind == ".npz":
        with replacing(path, "wb") as f:
            write_npz(table, f)
    else:
        with replacing(path, "w", encoding="utf-8", newline="") as f:
            (write_csv if kind == ".csv" else write_json)(table, f)
    return path
