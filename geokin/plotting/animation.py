"""Animations of a sweep: GIF, HTML page or MP4, a frame at a time.

:func:`animate` draws the mechanism (a :class:`~geokin.plotting.mechanism.Scene`)
at evenly chosen samples with the traced paths growing, and hands each frame
to a writer as soon as it is drawn: :class:`GifWriter`, :class:`PageWriter`
(one self-contained HTML page with a player) or ffmpeg for an ``.mp4``.
Memory does not grow with the number of frames, and
:func:`animation_estimate` says up front what the file and the drawing need,
so an animation that would not fit is refused before anything is drawn.
matplotlib and Pillow are imported inside the functions.
"""

from __future__ import annotations

import base64
import contextlib
import html
import io
import math
import os
import pathlib
import shutil
import sys
import time
import uuid

import numpy as np

from ..atomic import replacing, replacing_path, require_folder
from ..budgets import check_memory
from ..errors import GeokinError
from ..results import Sweep, short_name
from .layout import shown_text
from .mechanism import FIGSIZE, Scene, setup_axes

__all__ = [
    "ANIMATION_FORMATS",
    "DEFAULT_DPI",
    "DEFAULT_FRAMES",
    "INLINE_DPI",
    "INLINE_FRAMES",
    "MAX_FPS",
    "MAX_FRAMES",
    "MAX_INLINE_BYTES",
    "MIN_FPS",
    "AnimationHTML",
    "GifWriter",
    "PageWriter",
    "Progress",
    "animate",
    "animation_estimate",
    "animation_html",
    "frame_indices",
]

DEFAULT_FRAMES = 60
"""The frames of an animation unless more or fewer are asked for: a few seconds'
work on a 2-core machine (about 2 to 3 s for the mechanisms of ``constructions/``)."""

DEFAULT_DPI = 72
"""The resolution of an animation unless another is asked for: 576 by 432 pixels."""

MAX_FRAMES = 300
"""The most frames of an animation asked for with ``frames=None`` (every sample)."""

MIN_FPS, MAX_FPS = 0.01, 100.0
"""The frame rates an animation may have: a GIF counts delays in hundredths of a second."""

ANIMATION_FORMATS = (".gif", ".html", ".htm", ".mp4")

# bytes per pixel of one frame in the file: twice the most measured on constructions/ at
# 800 x 600 (0.023 for a GIF, whose frames hold what changed since the last; 0.107 for a page,
# a whole PNG in base64 per frame); for an .mp4, a guess well above what H.264 makes of such
# drawings
_FILE_BYTES_PER_PIXEL = {".gif": 0.05, ".html": 0.25, ".htm": 0.25, ".mp4": 0.03}


def frame_indices(n: int, frames: int | None) -> np.ndarray:
    """Return up to ``frames`` sample indices evenly spread over ``n`` samples.

    Parameters
    ----------
    n : int
        The number of samples.
    frames : int or None
        The frames wanted; None for every sample, at most :data:`MAX_FRAMES`.

    Raises
    ------
    GeokinError
        For ``frames`` that is not a positive integer.

    Examples
    --------
    >>> frame_indices(10, 4).tolist()
    [0, 3, 6, 9]
    >>> len(frame_indices(1000, None))
    300
    """
    if frames is None:
        frames = min(n, MAX_FRAMES)
    if isinstance(frames, bool) or not isinstance(frames, int | np.integer) or frames < 1:
        raise GeokinError(f"frames must be a positive integer, got {frames!r}")
    count = min(int(frames), n)
    return np.unique(np.linspace(0, n - 1, count).round().astype(int))


class Progress:
    """A text progress bar on stderr, shown on a terminal once a job takes over 2 s.

    Nothing is written where stderr is not a terminal (a log or a pipe).

    Parameters
    ----------
    label : str
        What is being done ("writing crank.gif").
    enabled : bool
        False to show nothing at all.
    stream : file, optional
        Where to write; ``sys.stderr`` by default.
    delay : float
        The seconds a job runs before the bar is shown.
    width : int
        The characters of the bar.
    """

    def __init__(self, label: str, enabled: bool, stream=None, delay: float = 2.0,
                 width: int = 30):
        self.label, self.enabled = label, enabled
        self.stream = stream if stream is not None else sys.stderr
        self.delay, self.width = delay, width
        self.start = time.monotonic()
        self.shown = False

    def __call__(self, current: int, total: int | None) -> None:
        """Show that frame ``current`` (from 0) of ``total`` (None if unknown) is written."""
        if not self.enabled:
            return
        done = current + 1
        if not self.shown:
            isatty = getattr(self.stream, "isatty", lambda: False)()
            if not (isatty and time.monotonic() - self.start >= self.delay):
                return
            self.shown = True
        if total:
            filled = min(int(self.width * done / total), self.width)
            bar = "#" * filled + "-" * (self.width - filled)
            self.stream.write(f"\r{self.label} [{bar}] {done}/{total}")
        else:
            self.stream.write(f"\r{self.label}: frame {done}")
        self.stream.flush()

    def close(self) -> None:
        """End the bar's line, if it was shown."""
        if self.shown:
            self.stream.write("\n")
            self.stream.flush()


class GifWriter:
    """Write a GIF a frame at a time: each frame is encoded and written as it comes.

    Only the previous frame is kept, to write each new one as the rectangle
    that changed (with its own palette) over the last, which is what makes
    an animation of a mechanism small.

    Parameters
    ----------
    stream : binary file
        Where the GIF is written.
    fps : float
        Frames per second.
    """

    def __init__(self, stream, fps: float):
        self.stream = stream
        self.duration = 1000.0 / fps  # milliseconds; the file keeps hundredths of a second
        self.previous: np.ndarray | None = None

    def add(self, rgb: np.ndarray) -> None:
        """Encode and write one frame, an (height, width, 3) array of uint8."""
        from PIL import GifImagePlugin, Image

        if self.previous is None:
            image = _paletted(Image.fromarray(rgb))
            header, _ = GifImagePlugin.getheader(image, None,
                                                 {"loop": 0, "duration": self.duration})
            self.stream.write(b"".join(header))
            box, local = (0, 0), False
        else:
            changed = np.any(rgb != self.previous, axis=2)
            rows, cols = np.flatnonzero(changed.any(axis=1)), np.flatnonzero(changed.any(axis=0))
            if rows.size:
                top, bottom, left, right = rows[0], rows[-1] + 1, cols[0], cols[-1] + 1
            else:  # nothing changed: one pixel keeps the frame and its delay
                top, bottom, left, right = 0, 1, 0, 1
            image = _paletted(Image.fromarray(rgb[top:bottom, left:right]))
            box, local = (int(left), int(top)), True
        self.stream.write(b"".join(GifImagePlugin.getdata(
            image, box, duration=self.duration, disposal=1, include_color_table=local)))
        self.previous = rgb.copy()

    def finish(self) -> None:
        """Write the end of the file."""
        self.stream.write(b";")  # the GIF trailer


def _paletted(image):
    """Return an RGB image with an adaptive palette of at most 256 colours, undithered."""
    from PIL import Image

    return image.convert("P", palette=Image.Palette.ADAPTIVE, colors=256)


_PLAYER_STYLE = """
.geokin-player img {{ display: block; max-width: 100%; height: auto; border: 1px solid #dddddd; }}
.geokin-player .controls {{ display: flex; gap: 0.3em; align-items: center; margin-top: 0.5em;
                            max-width: {width}px; }}
.geokin-player button {{ font-size: 1.1em; min-width: 2.4em; }}
.geokin-player input[type=range] {{ flex: 1; }}
"""

_PLAYER = """<div class="geokin-player">
<img id="{prefix}frame" width="{width}" height="{height}" alt="{title}"{src}>
<div class="controls">
<button id="{prefix}first" title="first frame">&#x23EE;</button>
<button id="{prefix}back" title="one frame back">&#x23F4;&#x2502;</button>
<button id="{prefix}play" title="play or pause">&#x23F8;</button>
<button id="{prefix}forward" title="one frame forward">&#x2502;&#x23F5;</button>
<button id="{prefix}last" title="last frame">&#x23ED;</button>
<input id="{prefix}slider" type="range" min="0" max="{last}" value="0">
<span id="{prefix}counter"></span>
<label><input id="{prefix}loop" type="checkbox" checked> loop</label>
</div>
</div>
"""

# plays the array ``frames`` defined before it, in the elements of _PLAYER
_PLAYER_SCRIPT = """(function () {{
  var interval = {interval};
  var element = function (id) {{ return document.getElementById("{prefix}" + id); }};
  var image = element("frame"), slider = element("slider"), counter = element("counter");
  var play = element("play"), loop = element("loop");
  var current = 0, timer = null;
  function show(i) {{
    current = Math.min(Math.max(i, 0), frames.length - 1);
    image.src = frames[current];
    slider.value = current;
    counter.textContent = (current + 1) + " / " + frames.length;
  }}
  function stop() {{
    if (timer !== null) {{ clearInterval(timer); timer = null; }}
    play.innerHTML = "&#x25B6;";
  }}
  function tick() {{
    if (current + 1 < frames.length) {{ show(current + 1); }}
    else if (loop.checked) {{ show(0); }}
    else {{ stop(); }}
  }}
  function start() {{
    if (timer === null) {{ timer = setInterval(tick, interval); play.innerHTML = "&#x23F8;"; }}
  }}
  play.onclick = function () {{ if (timer === null) {{ start(); }} else {{ stop(); }} }};
  element("first").onclick = function () {{ stop(); show(0); }};
  element("back").onclick = function () {{ stop(); show(current - 1); }};
  element("forward").onclick = function () {{ stop(); show(current + 1); }};
  element("last").onclick = function () {{ stop(); show(frames.length - 1); }};
  slider.oninput = function () {{ stop(); show(parseInt(slider.value, 10)); }};
  show(0);
  start();
}})();
"""

_PAGE_HEAD = """<!DOCTYPE html>
<html>
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>
body {{ font-family: sans-serif; margin: 1em; }}
""" + _PLAYER_STYLE + """</style>
</head>
<body>
"""

_PAGE_FRAMES = """<script>
var frames = [
"""

_PAGE_TAIL = """];
</script>
<script>
{script}</script>
</body>
</html>
"""


def _png_data(rgb: np.ndarray) -> bytes:
    """Return a frame, an (height, width, 3) array of uint8, as a PNG data URL."""
    from PIL import Image

    png = io.BytesIO()
    Image.fromarray(rgb).save(png, format="PNG")
    return b"data:image/png;base64," + base64.b64encode(png.getvalue())


class PageWriter:
    """Write an animation as one self-contained HTML page, a frame at a time.

    The page holds every frame as a PNG in base64 and a small player
    (play, pause, step, a slider, loop), and fetches nothing from the web.
    Each frame is written out as soon as it is drawn.

    Parameters
    ----------
    stream : binary file
        Where the page is written.
    fps : float
        Frames per second, as the player plays them.
    title : str
        The page's title.
    size : (int, int)
        The width and height of a frame in pixels.
    frames : int
        The number of frames that will be added.
    """

    def __init__(self, stream, fps: float, title: str, size: tuple[int, int], frames: int):
        self.stream = stream
        self.fps = fps
        width, height = size
        title = html.escape(shown_text(title))
        self.stream.write((_PAGE_HEAD.format(title=title, width=width)
                           + _PLAYER.format(prefix="", width=width, height=height, title=title,
                                            last=frames - 1, src="")
                           + _PAGE_FRAMES).encode("utf-8"))

    def add(self, rgb: np.ndarray) -> None:
        """Encode one frame, an (height, width, 3) array of uint8, as PNG and write it."""
        self.stream.write(b'"' + _png_data(rgb) + b'",\n')

    def finish(self) -> None:
        """Write the player and the end of the page."""
        script = _PLAYER_SCRIPT.format(interval=f"{1000.0 / self.fps:.6g}", prefix="")
        self.stream.write(_PAGE_TAIL.format(script=script).encode("utf-8"))


def animation_estimate(frames: int, width: int, height: int, suffix: str, *, samples: int = 0,
                       traces: int = 0) -> tuple[int, int]:
    """Estimate the file size and the memory of an animation, before drawing it.

    Frames are streamed to the file, so the memory does not grow with their
    number: it is a few copies of one frame, plus the traced paths that
    matplotlib keeps while drawing them (``traces`` paths of up to
    ``samples`` points). The file grows by about a frame's compressed size
    per frame.

    Parameters
    ----------
    frames : int
    width, height : int
        The size of a frame in pixels.
    suffix : {".gif", ".html", ".htm", ".mp4"}
    samples : int
        The samples of the sweep animated.
    traces : int
        The number of traced paths.

    Returns
    -------
    file_bytes, memory_bytes : int

    Examples
    --------
    >>> file_bytes, memory_bytes = animation_estimate(3000, 800, 600, ".gif")
    >>> f"{file_bytes / 1e6:.0f} MB, {memory_bytes / 1e6:.0f} MB"
    '72 MB, 11 MB'
    """
    pixels = int(width) * int(height)
    file_bytes = int(frames * pixels * _FILE_BYTES_PER_PIXEL[suffix]) + 4096
    # the canvas (RGBA), this and the last frame (RGB), the palette or PNG copy
    memory_bytes = pixels * (4 + 3 + 3 + 4 + 8) + 48 * samples * traces
    return file_bytes, memory_bytes


def _check_room(path, frames, width, height, suffix, samples, traces):
    """Refuse, up front, an animation whose file or drawing would not fit.

    The file must fit on the disk, the drawing in the memory budget of
    :func:`geokin.budgets.check_memory`.
    """
    file_bytes, memory_bytes = animation_estimate(frames, width, height, suffix,
                                                  samples=samples, traces=traces)
    animation = f"an animation of {frames:,} frames of {width} x {height} pixels"
    try:
        free = shutil.disk_usage(path.parent).free
    except OSError:
        free = None
    if free is not None and file_bytes > free:
        raise GeokinError(f"cannot write {str(path)!r}: {animation} needs about "
                          f"{_megabytes(file_bytes)} on disk and {_megabytes(memory_bytes)} "
                          f"of memory, but only {_megabytes(free)} are free there; ask for "
                          "fewer frames, fewer pixels (a lower dpi) or an .mp4")
    check_memory(memory_bytes, what=f"cannot write {str(path)!r}: drawing {animation}",
                 advice="ask for fewer samples, fewer traced points or fewer pixels "
                        "(a lower dpi)")


def _megabytes(count: int) -> str:
    return f"{count / 1e6:,.0f} MB" if count >= 1e6 else f"{count / 1e6:.2f} MB"


def animate(sweep: Sweep, path: str | os.PathLike[str], *, fps: float = 25,
            frames: int | None = DEFAULT_FRAMES, dpi: float = DEFAULT_DPI,
            progress: bool = True) -> pathlib.Path:
    """Write an animation of the motion, the traced paths growing with it.

    The writer is chosen by the extension: ``.gif``, ``.html`` (one
    self-contained page with the frames embedded and a player) or ``.mp4``
    (needs ffmpeg). Samples that cannot be assembled show the last
    assembled pose, faded, with the reason; if none can be, each frame
    shows what is known at its sample (see
    :func:`~geokin.plotting.mechanism.plot_mechanism`).

    Each frame goes to the file as soon as it is drawn, so memory does not
    grow with the number of frames; an animation whose file would not fit
    on the disk, or whose drawing would not fit in the memory budget
    (:func:`geokin.budgets.memory_budget`), is refused before anything is
    drawn (see :func:`animation_estimate`). The file is
    written whole or not at all (see :mod:`geokin.atomic`).

    Parameters
    ----------
    sweep : Sweep
    path : str or os.PathLike
        The file to write, ending in ``.gif``, ``.html`` or ``.mp4``.
    fps : float
        Frames per second, from :data:`MIN_FPS` to :data:`MAX_FPS`.
    frames : int or None
        The number of frames: that many samples, evenly chosen (every
        sample if there are fewer); :data:`DEFAULT_FRAMES` (60) by default,
        which takes a few seconds. None for every sample, at most
        :data:`MAX_FRAMES`.
    dpi : float
        Pixels per inch of the 8 by 6 inch drawing: :data:`DEFAULT_DPI`
        (72, 576 by 432 pixels) by default; 100 gives 800 by 600.
    progress : bool
        Show a progress bar on stderr when it is a terminal and writing
        takes more than about 2 s.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    GeokinError
        For an unknown extension, an ``.mp4`` without ffmpeg, bad ``fps``,
        ``frames`` or ``dpi``, or a file that would not fit on the disk.
    geokin.atomic.OutputError
        For a folder that does not exist, or a file that cannot be written.
    BudgetError
        For a drawing that would need more than the memory budget.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from geokin import Construction, sweep
    >>> c = Construction("crank")
    >>> c.input("theta", samples=5)
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 10, "theta")
    >>> animate(sweep(c), "crank.avi")
    Traceback (most recent call last):
    ...
    geokin.errors.GeokinError: cannot animate to 'crank.avi': use a .gif, .html or .mp4 file
    >>> animate(sweep(c), "crank.gif", frames=3, progress=False)  # doctest: +SKIP
    PosixPath('crank.gif')
    """
    path = pathlib.Path(path)
    suffix = path.suffix.lower()
    if suffix not in ANIMATION_FORMATS:
        raise GeokinError(f"cannot animate to {str(path)!r}: use a .gif, .html or .mp4 file")
    _check_fps(fps)
    _check_dpi(dpi)
    indices = frame_indices(len(sweep), frames)
    from matplotlib import animation

    if suffix == ".mp4" and not animation.writers.is_available("ffmpeg"):
        raise GeokinError(
            f"cannot write {str(path)!r}: an .mp4 needs ffmpeg, which was not found. "
            "Install ffmpeg (for example 'apt install ffmpeg' or 'conda install ffmpeg') "
            "and make sure it is on PATH, or write a .gif or .html file instead")
    require_folder(path)

    fig, canvas, scene = _drawing(sweep, dpi)
    width, height = canvas.get_width_height()
    _check_room(path, len(indices), width, height, suffix, len(sweep),
                len(scene.trace_lines))
    _lay_out(fig, scene, int(indices[0]))

    def frames_drawn():
        for k, index in enumerate(indices):
            scene.update(int(index), grow=True)
            yield k

    bar = Progress(f"writing {path.name}", progress)
    try:
        if suffix == ".mp4":
            _write_movie(fig, path, fps, frames_drawn(), len(indices), bar)
        else:
            with replacing(path, "wb") as f:
                writer: GifWriter | PageWriter
                if suffix == ".gif":
                    writer = GifWriter(f, fps)
                else:
                    writer = PageWriter(f, fps, sweep.construction.name, (width, height),
                                         len(indices))
                draw = _blitter(canvas, scene)
                for k in frames_drawn():
                    writer.add(draw())
                    bar(k, len(indices))
                writer.finish()
    finally:
        bar.close()
    return path


def _drawing(sweep: Sweep, dpi: float | None = None):
    """Return a figure of its own (not pyplot's), its canvas and the mechanism's scene."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=FIGSIZE, layout="constrained", dpi=dpi)
    canvas = FigureCanvasAgg(fig)
    scene = Scene(sweep, fig.add_subplot())
    return fig, canvas, scene


def _lay_out(fig, scene: Scene, first: int) -> None:
    """Draw the first frame's axes, title and legend, and fix the layout for every frame."""
    ax = scene.ax
    scene.update(first)
    setup_axes(ax, scene.layout, None)
    if scene.drawn_paths:
        ax.legend(handles=scene.drawn_paths, loc="upper left", bbox_to_anchor=(1.01, 1.0),
                  fontsize=9, framealpha=0.9)
    # lay the figure out once: the frames keep the same axes
    fig.draw_without_rendering()
    fig.set_layout_engine("none")


def _blitter(canvas, scene: Scene):
    """Return a function drawing a frame: the scene's artists over the rest, drawn once.

    The axes, grid, ticks, title and legend stay the same in every frame, and
    drawing them took most of a frame's time: they are drawn once, and each
    frame only puts back that picture and draws the mechanism over it. The
    function returns the frame, an (height, width, 3) array of uint8.
    """
    ax = scene.ax
    moving = sorted(scene.artists, key=lambda artist: artist.get_zorder())
    for artist in moving:
        artist.set_animated(True)
    canvas.draw()
    background = canvas.copy_from_bbox(canvas.figure.bbox)

    def draw() -> np.ndarray:
        canvas.restore_region(background)
        for artist in moving:
            ax.draw_artist(artist)
        return np.asarray(canvas.buffer_rgba())[..., :3]

    return draw


INLINE_FRAMES = DEFAULT_FRAMES
"""The frames of an inline animation unless more or fewer are asked for."""

INLINE_DPI = DEFAULT_DPI
"""The resolution of an inline animation: 576 by 432 pixels."""

MAX_INLINE_BYTES = 20_000_000
"""The largest inline animation made, in bytes of HTML (matplotlib's own limit for
an animation embedded in a notebook is the same)."""


class AnimationHTML(str):
    """An animation as self-contained HTML, which a notebook plays where it is shown.

    It is the HTML text itself (a ``str``), so ``IPython.display.HTML(animation)``
    shows it as any other HTML, and a notebook shows it directly as the last
    expression of a cell (through ``_repr_html_``); its ``repr`` is one short
    line, not megabytes of frames.

    Attributes
    ----------
    name : str
        The construction's name.
    frames : int
        The number of frames.
    fps : float
        Frames per second.
    """

    name: str
    frames: int
    fps: float

    def __new__(cls, text: str, name: str, frames: int, fps: float) -> AnimationHTML:
        """Return ``text`` as the animation of ``frames`` frames of construction ``name``."""
        made = super().__new__(cls, text)
        made.name, made.frames, made.fps = name, frames, fps
        return made

    def _repr_html_(self) -> str:
        return str(self)

    def __repr__(self) -> str:
        return (f"<AnimationHTML of {short_name(self.name)}: {self.frames} frames at "
                f"{self.fps:g} fps, {len(self):,} characters>")


def animation_html(sweep: Sweep, *, frames: int | None = INLINE_FRAMES, fps: float = 25,
                   dpi: float = INLINE_DPI) -> AnimationHTML:
    """Return an animation of the motion that plays inline in a notebook.

    The same drawing as :func:`animate`, with its player (play, pause, step,
    a slider, loop), as one self-contained HTML fragment: every frame is a
    PNG inside it, nothing is fetched from the web, and several animations
    in one notebook each play on their own. The first frame is also the
    picture's source, so a viewer that runs no script still shows it.
    IPython is not needed to make it.

    Parameters
    ----------
    sweep : Sweep
    frames : int or None
        The number of frames: that many samples, evenly chosen; None for
        every sample, at most :data:`MAX_FRAMES`.
    fps : float
        Frames per second, from :data:`MIN_FPS` to :data:`MAX_FPS`.
    dpi : float
        Pixels per inch of the 8 by 6 inch drawing.

    Returns
    -------
    AnimationHTML
        The HTML, a ``str`` that a notebook displays as an animation.

    Raises
    ------
    GeokinError
        For bad ``fps``, ``frames`` or ``dpi``, or an animation of more than
        :data:`MAX_INLINE_BYTES` (said before anything is drawn, with
        advice).
    BudgetError
        For a drawing that would need more than the memory budget.

    See Also
    --------
    animate : the same animation written to a GIF, an HTML page or an MP4.

    Examples
    --------
    >>> from geokin import Construction, sweep
    >>> c = Construction("crank")
    >>> c.input("theta", samples=9)
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 10, "theta")
    >>> movie = animation_html(sweep(c), frames=3, dpi=20)
    >>> movie  # doctest: +ELLIPSIS
    <AnimationHTML of 'crank': 3 frames at 25 fps, ... characters>
    >>> movie.count("data:image/png;base64,"), "<script>" in movie
    (4, True)
    """
    _check_fps(fps)
    _check_dpi(dpi)
    indices = frame_indices(len(sweep), frames)
    fig, canvas, scene = _drawing(sweep, dpi)
    width, height = canvas.get_width_height()
    animation = f"an inline animation of {len(indices):,} frames of {width} x {height} pixels"
    text_bytes, memory_bytes = animation_estimate(len(indices), width, height, ".html",
                                                  samples=len(sweep),
                                                  traces=len(scene.trace_lines))
    if text_bytes > MAX_INLINE_BYTES:
        raise GeokinError(f"{animation} would take about {_megabytes(text_bytes)}, more than "
                          f"the {_megabytes(MAX_INLINE_BYTES)} a notebook is given; ask for "
                          "fewer frames or a lower dpi, or write a file with animate()")
    check_memory(memory_bytes + text_bytes, what=f"drawing {animation}",
                 advice="ask for fewer frames or a lower dpi")
    _lay_out(fig, scene, int(indices[0]))
    draw = _blitter(canvas, scene)
    data = []
    for index in indices:
        scene.update(int(index), grow=True)
        data.append(_png_data(draw()).decode("ascii"))
    # ids of its own: a notebook holds many animations on one page
    prefix = f"geokin-{uuid.uuid4().hex}-"
    title = html.escape(shown_text(sweep.construction.name))
    player = _PLAYER.format(prefix=prefix, width=width, height=height, title=title,
                            last=len(data) - 1, src=f' src="{data[0]}"')
    script = _PLAYER_SCRIPT.format(interval=f"{1000.0 / fps:.6g}", prefix=prefix)
    frames_js = ",\n".join(f'"{frame}"' for frame in data)
    text = (f'<div class="geokin-animation">\n<style>{_PLAYER_STYLE.format(width=width)}'
            f"</style>\n{player}<script>\n(function () {{\nvar frames = [\n{frames_js}\n];\n"
            f"{script}}})();\n</script>\n</div>\n")
    return AnimationHTML(text, sweep.construction.name, len(data), float(fps))


def _check_dpi(dpi) -> None:
    if (isinstance(dpi, bool) or not isinstance(dpi, int | float)
            or not (math.isfinite(dpi) and 1 <= dpi <= 1000)):
        raise GeokinError(f"dpi must be a number from 1 to 1000, got {dpi!r}")


def _check_fps(fps) -> None:
    if (isinstance(fps, bool) or not isinstance(fps, int | float)
            or not MIN_FPS <= fps <= MAX_FPS):
        raise GeokinError(f"fps must be a number from {MIN_FPS:g} to {MAX_FPS:g}, got {fps!r}")


def _write_movie(fig, path, fps, drawn, count, bar):
    """Pipe the frames to ffmpeg, which writes a temporary file renamed into place."""
    import subprocess

    from matplotlib import animation

    with replacing_path(path) as temp:
        writer = animation.FFMpegWriter(fps=fps)
        writer.setup(fig, temp, dpi=fig.dpi)
        stopped = False
        try:
            for k in drawn:
                writer.grab_frame()
                bar(k, count)
        except BrokenPipeError:  # ffmpeg has stopped reading: finish() tells why
            stopped = True
        except BaseException:  # already failing: let ffmpeg go without hiding why
            with contextlib.suppress(Exception):
                writer.finish()
            raise
        try:
            writer.finish()
        except subprocess.CalledProcessError as err:
            said = (err.stderr or "").strip().splitlines()
            raise GeokinError(f"cannot write {str(path)!r}: ffmpeg stopped with status "
                              f"{err.returncode}" + (f": {said[-1]}" if said else "")) from None
        if stopped:
            raise GeokinError(f"cannot write {str(path)!r}: ffmpeg stopped before the last "
                              "frame")
