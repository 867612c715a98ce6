"""Tests of geokin.plotting: figures, files and animations, headless (Agg)."""

import io
import itertools
import math
import re
import shutil
import subprocess
import sys

import matplotlib
import matplotlib.backends.backend_agg
import matplotlib.figure
import matplotlib.pyplot as plt
import numpy as np
import pytest
import shapely
from matplotlib import animation
from mechanisms import five_bar, offset_slider_crank
from PIL import Image

from geokin import BudgetError, Construction, ConstructionError, GeokinError, budgets, sweep
from geokin import plotting as gp
from geokin.analysis import cranks
from geokin.plotting import animation as ga
from geokin.plotting.layout import Layout, input_text, pose_drawn
from geokin.plotting.mechanism import Scene

BAR_WIDTH = 5.0  # the line width of a two-point link


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def four_bar(crank=10.0, links=True):
    """Ground (0,0)-(40,0), crank 10, coupler 35, rocker 30, coupler point P."""
    c = Construction("four-bar")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 40, 0)
    c.polar("A", "O2", crank, "theta")
    c.circle_circle("B", ("A", "O4"), (35, 30), branch="left")
    c.polar("P", "A", 20, np.radians(30), reference=("A", "B"))
    if links:
        c.link("crank", "O2", "A")
        c.link("coupler", "A", "B", "P")
        c.link("rocker", "B", "O4")
        c.trace("P")
    return c


def slider_crank():
    c = Construction("slider-crank")
    c.input("theta")
    c.fixed("O", 0, 0)
    c.fixed("G", 1, 0)
    c.polar("A", "O", 10, "theta")
    c.line_circle("B", ("O", "G"), "A", 30, branch="second")
    c.link("crank", "O", "A")
    c.link("rod", "A", "B")
    c.slider("block", "B", ("O", "G"))
    return c


def samples(n):
    return np.linspace(0, 2 * np.pi, n)


def bars(ax):
    return [line for line in ax.get_lines() if line.get_linewidth() == BAR_WIDTH]


def texts(ax):
    return {t.get_text() for t in ax.texts}


def test_four_bar_artists():
    s = sweep(four_bar(), samples(73))
    ax = gp.plot_mechanism(s, 6)
    assert isinstance(ax, matplotlib.axes.Axes)
    # path of P, crank and rocker bars, two ground lines, joints, loose points, references
    assert len(ax.get_lines()) == 8
    assert len(bars(ax)) == 2
    # two pivot triangles, two hatched grounds, the coupler plate, the input arrow
    assert len(ax.patches) == 6
    hatched = [p for p in ax.patches if p.get_hatch()]
    assert len(hatched) == 2
    (plate,) = [p for p in ax.patches if 0 < p.get_facecolor()[3] < 0.5]  # translucent
    np.testing.assert_allclose(plate.get_xy()[:3], [s["A"][6], s["B"][6], s["P"][6]])
    assert {"O2", "O4", "A", "B", "P", "θ = 30.0°"} <= texts(ax)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["path of P"]
    trace = ax.get_lines()[0]
    np.testing.assert_allclose(trace.get_xydata(), s["P"])
    assert ax.get_aspect() == 1.0
    assert ax.get_title() == "four-bar"


def test_view_includes_the_whole_motion():
    s = sweep(four_bar(), samples(73))
    ax = gp.plot_mechanism(s)
    ax.figure.canvas.draw()
    xy = np.concatenate([s[p] for p in ("O2", "O4", "A", "B", "P")])
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert x0 < xy[:, 0].min() and xy[:, 0].max() < x1
    assert y0 < xy[:, 1].min() and xy[:, 1].max() < y1


def test_slider_block_sits_on_its_point():
    s = sweep(slider_crank(), samples(37))
    fig, ax = gp.figure_mechanism(s, 4, title="")
    block = [p for p in ax.patches if p.get_facecolor()[:3] == matplotlib.colors.to_rgb(
        "#f4d58d")]
    assert len(block) == 1
    corners = block[0].get_xy()[:4]
    np.testing.assert_allclose(corners.mean(axis=0), s["B"][4], atol=1e-9)
    size = Layout(s).size
    np.testing.assert_allclose(np.ptp(corners, axis=0), [3.2 * size, 2 * size])
    # the guide's direction point G is shown by the guide line, not labelled
    assert "G" not in texts(ax) and {"O", "A", "B"} <= texts(ax)
    assert len(bars(ax)) == 2
    assert ax.get_title() == ""
    # paths of every point that is not fixed
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["path of A", "path of B"]


def driven_pin():
    """A pin S pushed along the x axis by a length input; an arm O-B and a rod B-S."""
    c = Construction("driven pin")
    c.input("s", kind="length", range=(0, 5), samples=11)
    c.fixed("O", -10, 0)
    c.fixed("G", 0, 0)
    c.fixed("S", "s", 0)  # fixed kind, but it moves with s
    c.circle_circle("B", ("O", "S"), (12, 8), branch="left")
    c.link("arm", "O", "B")
    c.link("rod", "B", "S")
    c.slider("block", "S", ("O", "G"))
    return c


def inclined_guide():
    """A slider on a fixed guide through G at 30 degrees, its second point H given by polar."""
    c = Construction("inclined guide")
    c.input("theta", samples=37)
    c.fixed("O", 0, 0)
    c.fixed("G", 0, 10)
    c.polar("H", "G", 70, np.radians(30))
    c.polar("A", "O", 20, "theta")
    c.line_circle("B", ("G", "H"), "A", 70, branch="second")
    c.link("crank", "O", "A")
    c.link("rod", "A", "B")
    c.slider("block", "B", ("G", "H"))
    return c


def test_a_guide_given_by_its_angle_is_drawn_as_ground():
    """H, polar from the fixed G at a constant angle, is ground: a hatched guide, H unmarked."""
    c = inclined_guide()
    assert c.compile().ground == {"O", "G", "H"}
    ax = gp.plot_mechanism(sweep(c), 4)
    (triangle,) = pivot_triangles(ax)  # O only: G and H are shown by the guide
    np.testing.assert_allclose(triangle.get_xy()[0], [0, 0])
    assert len([p for p in ax.patches if p.get_hatch()]) == 2  # under O, under the block
    assert "H" not in texts(ax) and "G" not in texts(ax)


def test_guide_points_in_the_frame_link_are_shown_by_the_guide_not_as_pivots():
    """The frame declared as a link of O, G and H: still one pivot, O; G and H unmarked."""
    c = inclined_guide()
    c.link("frame", "O", "G", "H")
    layout = Layout(sweep(c))
    assert layout.pivots == ["O"]
    ax = gp.plot_mechanism(sweep(c), 4)
    (triangle,) = pivot_triangles(ax)
    np.testing.assert_allclose(triangle.get_xy()[0], [0, 0])
    assert "H" not in texts(ax) and "G" not in texts(ax)


def slotted_lever(*frame):
    """A quick return whose lever is its slot, the line from its pivot O1 through the pin A.

    The ram B runs on the fixed guide C-G; ``frame`` is the frame link's points.
    """
    c = Construction("quick return, slotted lever by its slot")
    c.input("theta")
    c.fixed("O1", 0, 0)
    c.fixed("O2", 0, 60)
    c.fixed("C", 0, 120)
    c.fixed("G", 1, 120)
    c.polar("A", "O2", 40, "theta")
    c.line_line("B", ("O1", "A"), ("C", "G"))
    c.link("frame", *frame)
    c.link("crank", "O2", "A")
    c.slider("pin_block", "A", ("O1", "A"))
    c.slider("ram", "B", ("C", "G"))
    return c


def test_the_ground_point_of_a_turning_guide_is_a_pivot():
    """Blocks in a slot through the lever's pivot O1 and the moving pin A: O1 is a pivot.

    The ram's guide C-G is fixed: C, named in the frame link, is shown by it.
    """
    c = slotted_lever("O1", "O2", "C")
    c.slider("ram_block", "B", ("O1", "A"))
    assert Layout(sweep(c)).pivots == ["O1", "O2"]


@pytest.mark.parametrize("frame, follower", [
    (("O2", "C"), False),   # the frame link leaves the lever's pivot out
    (("O2", "C"), True),    # and a fixed guide starts at the lever's pivot
    (("O1", "O2"), True),   # that guide, with the pivot in the frame link
])
def test_a_turning_guide_pivots_on_its_ground_point_whatever_else_uses_it(frame, follower):
    """O1 carries the slotted lever, a guide through the moving pin A: always a pivot.

    With ``follower``, a second block D runs on the fixed line from O1 through H.
    """
    c = slotted_lever(*frame)
    if follower:
        c.fixed("H", 1, 0)
        c.line_circle("D", ("O1", "H"), "A", 120, branch="second")
        c.link("rod", "A", "D")
        c.slider("follower", "D", ("O1", "H"))
    s = sweep(c)
    assert s.valid.all()
    assert "O1" in Layout(s).pivots
    ax = gp.plot_mechanism(s, 10)
    tips = [tuple(np.round(t.get_xy()[0], 9)) for t in pivot_triangles(ax)]
    assert (0.0, 0.0) in tips and (0.0, 60.0) in tips


def pivot_triangles(ax):
    grey = matplotlib.colors.to_rgba("#d9d9d9")
    return [p for p in ax.patches if p.get_facecolor() == grey]


def test_a_fixed_point_driven_by_an_input_is_no_ground_pivot():
    c = driven_pin()
    assert c.compile().ground == {"O", "G"}
    s = sweep(c)
    ax = gp.plot_mechanism(s, 4)
    (triangle,) = pivot_triangles(ax)  # O only, not S
    np.testing.assert_allclose(triangle.get_xy()[0], s["O"][4])
    # hatched: O's ground and the guide O-G under the block, nothing under S
    assert len([p for p in ax.patches if p.get_hatch()]) == 2
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["path of S", "path of B"]
    assert "S" in texts(ax)


def test_without_links_bars_join_each_point_to_what_it_is_built_on():
    s = sweep(four_bar(links=False), samples(37))
    ax = gp.plot_mechanism(s)
    ends = {frozenset(map(tuple, line.get_xydata().round(9))) for line in bars(ax)}
    expected = {frozenset((tuple(s[a][0].round(9)), tuple(s[b][0].round(9))))
                for a, b in [("O2", "A"), ("A", "B"), ("O4", "B"), ("A", "P"), ("B", "P")]}
    assert ends == expected
    assert len(ax.get_legend().get_texts()) == 3  # A, B and P are traced


def test_traces_chosen_and_checked():
    s = sweep(four_bar(), samples(19))
    ax = gp.plot_mechanism(s, traces=["A", "B"])
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["path of A", "path of B"]
    with pytest.raises(ConstructionError,
                       match=r"^cannot trace: no point 'p'; did you mean 'P'\?$"):
        gp.plot_mechanism(s, traces=["p"])
    with pytest.raises(ConstructionError, match=r"^cannot trace 7: name a point with a string$"):
        gp.plot_mechanism(s, traces=[7])
    # a name is found as the construction declares it (in NFKC), and drawn so
    ax = gp.plot_mechanism(s, traces=["\uff30"])  # a fullwidth P
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["path of P"]


def test_index_checked():
    s = sweep(four_bar(), samples(19))
    assert "θ = 360.0°" in texts(gp.plot_mechanism(s, -1))
    with pytest.raises(GeokinError, match="out of range"):
        gp.plot_mechanism(s, 19)


def test_save_png_has_the_figure_size_in_pixels(tmp_path):
    with matplotlib.rc_context({"figure.dpi": 40}):
        fig, _ = gp.figure_mechanism(sweep(four_bar(), samples(19)))
    path = gp.save(fig, tmp_path / "four-bar.png")
    width, height = (fig.get_size_inches() * fig.dpi).round().astype(int)
    assert (width, height) == (320, 240)
    rgb = plt.imread(path)[..., :3]
    assert rgb.shape[:2] == (height, width)
    assert (rgb < 0.9).any(axis=2).mean() > 0.02  # not a blank picture
    for color in gp.LINK_COLORS[:3]:  # the crank, the coupler's edge and the rocker are drawn
        assert (np.abs(rgb - matplotlib.colors.to_rgb(color)).max(axis=2) < 0.02).sum() >= 10


def test_save_svg(tmp_path):
    fig, _ = gp.figure_mechanism(sweep(four_bar(), samples(19)))
    path = gp.save(fig, tmp_path / "four-bar.svg")
    assert "<svg" in path.read_text()


def test_save_unknown_extension(tmp_path):
    fig, _ = gp.figure_mechanism(sweep(four_bar(), samples(5)))
    with pytest.raises(GeokinError, match=r"\.png or \.svg"):
        gp.save(fig, tmp_path / "four-bar.jpg")
    with pytest.raises(GeokinError, match="does not exist"):
        gp.save(fig, tmp_path / "missing" / "four-bar.png")


@pytest.fixture
def small_frames():
    """Figures at 25 dpi; the animations below ask for it too (200 x 150 pixels)."""
    with matplotlib.rc_context({"figure.dpi": 25}):
        yield


def test_animate_gif_frame_count(tmp_path, small_frames):
    path = gp.animate(sweep(four_bar(), samples(37)), tmp_path / "four-bar.gif", dpi=25, frames=5,
                      progress=False)
    assert path == tmp_path / "four-bar.gif"
    with Image.open(path) as gif:
        assert gif.n_frames == 5


def test_animate_html_embeds_its_frames(tmp_path, small_frames):
    path = gp.animate(sweep(slider_crank(), samples(37)), tmp_path / "slider.html", dpi=25,
                      frames=4, progress=False)
    page = path.read_text()
    assert "<html" in page or "<script" in page
    assert page.count("data:image/png;base64") == 4
    assert [p.name for p in tmp_path.iterdir()] == ["slider.html"]  # nothing beside it
    # nothing fetched from the web: the buttons are drawn with text symbols
    assert "stylesheet" not in page and "fa fa-" not in page and "http" not in page
    assert page.startswith("<!DOCTYPE html>") and "<title>" in page


def test_animate_mp4_needs_ffmpeg(tmp_path, monkeypatch):
    monkeypatch.setattr(animation.writers, "is_available", lambda name: False)
    with pytest.raises(GeokinError, match="ffmpeg") as error:
        gp.animate(sweep(four_bar(), samples(5)), tmp_path / "four-bar.mp4")
    assert ".gif" in str(error.value) and ".html" in str(error.value)
    assert not (tmp_path / "four-bar.mp4").exists()


@pytest.mark.parametrize("name", ["four-bar.avi", "four-bar"])
def test_animate_unknown_extension(tmp_path, name):
    with pytest.raises(GeokinError, match=r"\.gif, \.html or \.mp4"):
        gp.animate(sweep(four_bar(), samples(5)), tmp_path / name)


def test_frames_checked(tmp_path):
    with pytest.raises(GeokinError, match="frames"):
        gp.animate(sweep(four_bar(), samples(5)), tmp_path / "a.gif", frames=0)
    with pytest.raises(GeokinError, match="fps"):
        gp.animate(sweep(four_bar(), samples(5)), tmp_path / "a.gif", fps=0)


def test_the_status_of_one_picture_moves_off_the_mechanism():
    """Chebyshev's double rocker at 200 deg, where it cannot be assembled: its last pose,
    at 101.5 deg, reaches into the upper left corner, where a four-line status would
    cover the crank pin; the status goes to a corner that covers no bar, path or label."""
    c = Construction("Chebyshev")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 20, 0)
    c.polar("A", "O2", 25, "theta")
    c.circle_circle("B", ("A", "O4"), (10, 25), branch="right")
    c.along("P", ("A", "B"), 5)
    c.link("crank", "O2", "A")
    c.link("coupler", "A", "P", "B")
    c.link("rocker", "O4", "B")
    c.trace("P")
    s = sweep(c)
    fig = matplotlib.figure.Figure(figsize=gp.FIGSIZE, layout="constrained")
    ax = gp.plot_mechanism(s, 200, ax=fig.add_subplot())
    status = ax.texts[-1]
    assert "cannot be assembled at 'B'" in status.get_text()
    fig.draw_without_rendering()
    box = status.get_window_extent()
    crossed = [a for a in [*ax.lines, *ax.patches]
               if a.get_visible() and a.get_transform().transform_path(
                   a.get_path()).intersects_bbox(box, filled=False)]
    labels = [t for t in ax.texts[:-1] if t.get_visible() and t.get_window_extent().overlaps(box)]
    assert crossed == [] and labels == []


def test_invalid_samples_plot_and_animate(tmp_path, small_frames):
    s = sweep(four_bar(crank=30.0), samples(37))  # cannot reach around theta = 180°
    assert s.valid.any() and not s.valid.all()
    bad = int(np.flatnonzero(~s.valid)[0])
    ax = gp.plot_mechanism(s, bad)
    status = ax.texts[-1].get_text()
    assert "cannot be assembled at 'B'" in status
    drawn = pose_drawn(s, bad)
    assert s.valid[drawn] and status.endswith(f"drawn: the pose at {input_text(s, drawn)}")
    faded = [a for a in ax.patches if a.get_alpha() is not None and a.get_alpha() < 0.5]
    assert faded  # the last assembled pose, faded
    path = gp.animate(s, tmp_path / "partial.gif", dpi=25, frames=12, progress=False)
    with Image.open(path) as gif:
        assert gif.n_frames == 12


def dark_pixels_near(image, ax, xy, radius=12):
    """Count the dark pixels of a drawn figure's image within ``radius`` pixels of data ``xy``.

    Dark: darker than the grid and the white background, as a symbol or a bar is.
    """
    x, y = ax.transData.transform(xy)
    row, column = int(round(image.shape[0] - y)), int(round(x))
    window = image[max(row - radius, 0):row + radius, max(column - radius, 0):column + radius]
    return int((window[..., :3].min(axis=-1) < 120).sum())


def rendered(fig):
    canvas = matplotlib.backends.backend_agg.FigureCanvasAgg(fig)
    canvas.draw()
    return np.asarray(canvas.buffer_rgba())


def test_a_sweep_that_never_assembles_shows_what_is_known():
    # the crank (200) cannot bring its pin within reach of coupler and rocker (35, 30)
    s = sweep(four_bar(crank=200.0), samples(9))
    assert not s.valid.any()
    fig, ax = gp.figure_mechanism(s, 2)
    status = ax.texts[-1].get_text()
    assert status == ("θ = 90.0°\nno sample can be assembled:\nnode 'B' fails at all 9 "
                      "samples:\nno intersection: the curves do not meet")
    # the pivots and the crank, which are known; nothing of what comes after B
    shown = {a.get_text() for a in ax.texts if a.get_visible()} - {status}
    assert shown == {"O2", "O4", "A"}
    assert sum(p.get_visible() for p in ax.patches if p.get_hatch()) == 2  # two grounds
    crank = [line for line in bars(ax) if line.get_visible()]
    assert len(crank) == 1
    np.testing.assert_allclose(crank[0].get_xydata(), [[0, 0], [0, 200]], atol=1e-9)
    assert not any(line.get_visible() for line in bars(ax)[1:])  # the rocker
    assert ax.get_legend() is None  # no path of P to show
    # a view round what is known, the crank's circle included, not the unit square
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert x0 < -200 and x1 > 200 and y0 < -200 and y1 > 200 and x1 - x0 < 1000
    image = rendered(fig)
    for pivot in ((0, 0), (40, 0)):
        assert dark_pixels_near(image, ax, pivot) > 10, pivot
    assert dark_pixels_near(image, ax, (150, -150)) == 0  # and not everywhere


def test_a_sweep_that_never_assembles_with_nothing_moving_known():
    # the ground pivots alone are known: the view is round them, not the unit square
    c = Construction("too short")
    c.input("theta")
    c.fixed("O2", 100, 50)
    c.fixed("O4", 140, 50)
    c.circle_circle("B", ("O2", "O4"), ("5 + 0 * theta", 5), branch="left")
    c.link("left", "O2", "B")
    c.link("right", "B", "O4")
    s = sweep(c, samples(5))
    fig, ax = gp.figure_mechanism(s)
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert x0 < 100 and x1 > 140 and y0 < 50 < y1 and x1 - x0 < 80
    image = rendered(fig)
    for pivot in ((100, 50), (140, 50)):
        assert dark_pixels_near(image, ax, pivot) > 10, pivot


def test_the_view_is_the_mechanism_far_from_the_origin():
    # the artists are made at the origin before they are moved: the view must not hold it
    c = Construction("far")
    c.input("theta")
    c.fixed("O2", 1000, 1000)
    c.fixed("O4", 1040, 1000)
    c.polar("A", "O2", 10, "theta")
    c.circle_circle("B", ("A", "O4"), (35, 30), branch="left")
    c.link("crank", "O2", "A")
    c.link("coupler", "A", "B")
    c.link("rocker", "B", "O4")
    ax = gp.plot_mechanism(sweep(c, samples(37)))
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert 900 < x0 < 990 and 1040 < x1 < 1100 and 900 < y0 < 990 and 1000 < y1 < 1100
    # what the axes held before stays in view
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    gp.plot_mechanism(sweep(c, samples(37)), ax=ax)
    assert ax.get_xlim()[0] < 0 < 1040 < ax.get_xlim()[1]


def test_an_animation_of_a_sweep_that_never_assembles_shows_the_crank_turning(tmp_path,
                                                                              small_frames):
    s = sweep(four_bar(crank=200.0), samples(9))
    path = gp.animate(s, tmp_path / "never.gif", dpi=25, frames=3, progress=False)
    with Image.open(path) as gif:
        assert gif.n_frames == 3
        frames = []
        for k in range(3):
            gif.seek(k)
            frames.append(np.asarray(gif.convert("RGB"), dtype=int))
    assert (frames[0] != frames[1]).any()  # the crank turns; the pivots stay


def test_progress_bar_only_on_a_terminal_and_a_slow_job():
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    log = io.StringIO()  # not a terminal: never, however slow
    bar = ga.Progress("writing a.gif", True, stream=log, delay=0.0)
    for i in range(3):
        bar(i, 3)
    bar.close()
    assert log.getvalue() == ""

    quick = Terminal()  # a terminal, but the job is not slow yet
    bar = ga.Progress("writing a.gif", True, stream=quick, delay=60.0)
    bar(0, 3)
    assert quick.getvalue() == ""

    slow = Terminal()
    bar = ga.Progress("writing a.gif", True, stream=slow, delay=0.0)
    bar(0, 2)
    bar(1, 2)
    bar.close()
    assert slow.getvalue().endswith("[" + "#" * 30 + "] 2/2\n")

    unknown = Terminal()
    bar = ga.Progress("writing a.gif", True, stream=unknown, delay=0.0)
    bar(6, None)
    assert unknown.getvalue().endswith("frame 7")

    off = Terminal()
    bar = ga.Progress("writing a.gif", False, stream=off, delay=0.0)
    bar(0, 4)
    assert off.getvalue() == ""


def test_length_input_and_turning_guide():
    c = Construction("inverted slider")
    c.input("s", kind="length", range=(0, 10), samples=11)
    c.fixed("O", 0, 0)
    c.fixed("C", 0, -20)
    c.polar("A", "O", 10, "s / 10")
    c.along("T", ("C", "A"), 40)
    c.link("crank", "O", "A")
    c.link("guide", "C", "T")
    c.slider("block", "A", ("C", "T"))
    s = sweep(c)
    ax = gp.plot_mechanism(s, 5)
    assert "s = 5" in texts(ax)
    (block,) = [p for p in ax.patches if p.get_facecolor()[:3] == matplotlib.colors.to_rgb(
        "#f4d58d")]
    corners = block.get_xy()[:4]
    along = (s["T"][5] - s["C"][5]) / 40
    np.testing.assert_allclose((corners[1] - corners[0]) @ along,
                               np.hypot(*(corners[1] - corners[0])))


def guide_segments(s, index):
    """The guide line drawn for each slider at sample ``index``: its two ends, by slider name."""
    fig, ax = plt.subplots()
    scene = Scene(s, ax)
    scene.update(index)
    ends = {}
    for slider, _, guide, _, _ in scene.blocks:
        ends[slider.name] = np.column_stack(guide.get_data())
    return scene.layout, ends


@pytest.mark.parametrize("index", [0, 45, 90, 135, 200, 300])
def test_a_guide_in_a_lever_covers_the_blocks_travel_not_the_mechanism(index):
    """The quick return's slot: from the lever's pivot O1 to past the blocks, never behind O1."""
    from geokin import load
    from geokin.kinematics import slider_positions

    s = sweep(load("constructions/quick_return.toml"))
    layout, ends = guide_segments(s, index)
    margin = 2.5 * layout.size
    travel = slider_positions(s)
    o1, lever = s["O1"][index], s["L"][index] - s["O1"][index]
    u = lever / np.hypot(*lever)
    for name in ("pin_block", "ram_block"):
        a, b = (ends[name] - o1) @ u  # where the drawn guide starts and ends along the lever
        lo, hi = np.nanmin(travel[name]), np.nanmax(travel[name])
        assert a >= -1e-9 and b <= max(170.0, hi + margin) + 1e-9  # on the lever O1-L
        assert a <= lo and b >= hi  # the whole travel of the block
        assert b - a <= hi - lo + 2 * margin + 1e-9
        # on the lever's line, not across the mechanism
        np.testing.assert_allclose((ends[name] - o1) @ [-u[1], u[0]], 0, atol=1e-9)
    # the ram's fixed guide reaches back to its first point C, and over the ram's stroke
    a, b = ends["ram"][:, 0]
    lo, hi = np.nanmin(travel["ram"]), np.nanmax(travel["ram"])
    np.testing.assert_allclose([a, b], [lo - margin, hi + margin])


def test_a_block_that_keeps_its_place_on_a_moving_guide_gets_a_short_guide():
    """The six-bar's block C stays 70 from Ap along Ap-M: its guide is about the block."""
    from geokin import load

    s = sweep(load("constructions/sixbar.toml"))
    for index in (0, 12, 40, 80):
        layout, ends = guide_segments(s, index)
        a, b = ends["block"]
        np.testing.assert_allclose(np.hypot(*(b - a)), 5 * layout.size, rtol=1e-6)
        np.testing.assert_allclose((a + b) / 2, s["C"][index], atol=1e-6)
        assert np.hypot(*(b - a)) < 0.2 * np.ptp(layout.bounds(), axis=0).max()


def drawn(s, index):
    """The mechanism at sample ``index`` on a figure of the command's size, drawn."""
    fig = matplotlib.figure.Figure(figsize=gp.FIGSIZE, layout="constrained")
    matplotlib.backends.backend_agg.FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    gp.plot_mechanism(s, index, ax=ax)
    fig.canvas.draw()
    return ax


@pytest.mark.parametrize("index", [0, 2, 10, 20, 40, 61, 85, 106])
def test_labels_of_points_close_together_do_not_hide_each_other(index):
    """The six-bar's D, mid and A0 are 10 and 20 apart in a drawing 200 across."""
    import shapely

    from geokin import load

    s = sweep(load("constructions/sixbar.toml"))
    ax = drawn(s, index)
    renderer = ax.figure.canvas.get_renderer()
    boxes = {t.get_text(): t.get_window_extent(renderer) for t in ax.texts
             if t.get_text() in s.points}
    assert {"D", "mid", "A0"} <= set(boxes)
    for a, b in itertools.combinations(boxes, 2):
        assert not boxes[a].overlaps(boxes[b]), (a, b)
    for a in ("D", "mid", "A0"):  # in display units, a few pixels apart at least
        for b in ("D", "mid", "A0"):
            if a < b:
                gap = shapely.box(*boxes[a].extents).distance(shapely.box(*boxes[b].extents))
                assert gap >= 2.0, (a, b, gap)
    # and no label on another point
    for name, box in boxes.items():
        for other in boxes:
            xy = ax.transData.transform(s[other][index])
            assert other == name or not box.contains(*xy), (name, other)


def ground_symbols(ax):
    """The triangles and the hatched strips of the ground pivots, as shapely polygons."""
    import shapely

    grey = matplotlib.colors.to_rgba("#d9d9d9")
    return [shapely.Polygon(p.get_xy()) for p in ax.patches
            if p.get_hatch() or p.get_facecolor() == grey]


def test_ground_symbols_of_pivots_close_together_do_not_overlap():
    from geokin import load

    s = sweep(load("constructions/sixbar.toml"))
    ax = drawn(s, 0)
    symbols = ground_symbols(ax)
    assert len(symbols) == 8  # D, mid, A0, B0: a triangle and a strip each
    biggest = max(p.area for p in symbols)
    for a, b in itertools.combinations(symbols, 2):
        assert a.intersection(b).area <= 0.02 * biggest  # a triangle's base on its strip
    layout = Layout(s)
    # D keeps its symbol below; mid and A0, with the frame running through them, do not
    down = 1.5 * np.pi
    assert layout.ground_directions["D"] == layout.ground_directions["B0"] == pytest.approx(down)
    assert layout.ground_directions["mid"] != pytest.approx(down)
    # smaller where pivots are 10 apart, as large as the others' where there is room
    assert layout.ground_sizes["D"] == layout.ground_sizes["B0"] == layout.size
    assert 0.6 * layout.size <= layout.ground_sizes["mid"] < layout.size


def test_a_pivot_with_room_keeps_its_ground_symbol_below():
    s = sweep(four_bar(), samples(37))
    layout = Layout(s)
    assert layout.ground_directions == pytest.approx({"O2": 1.5 * np.pi, "O4": 1.5 * np.pi})
    assert layout.ground_sizes == {"O2": layout.size, "O4": layout.size}
    ax = gp.plot_mechanism(s, 3)
    o2 = pivot_triangles(ax)[0].get_xy()
    np.testing.assert_allclose(o2[0], s["O2"][3])
    assert np.all(o2[1:3, 1] < s["O2"][3][1])  # the base below the pivot


@pytest.mark.parametrize("values, sense", [(samples(9), 1.0), (samples(9)[::-1], -1.0)])
def test_input_arrow_turns_with_the_crank(values, sense):
    s = sweep(four_bar(), values)
    ax = gp.plot_mechanism(s, 3)
    (arrow,) = [p for p in ax.patches if isinstance(p, matplotlib.patches.FancyArrowPatch)]
    assert np.sign(arrow.get_connectionstyle().rad) == sense  # bulging outwards


def test_input_arrow_sits_on_the_crank_not_on_a_helper_point():
    c = four_bar()
    c.polar("H", "O4", 5, "theta")  # turned by the input too, but on no link
    s = sweep(c, samples(9))
    assert cranks(c)[0].tip == "A" and Layout(s).crank == cranks(c)[0]
    ax = gp.plot_mechanism(s, 2)
    (arrow,) = [p for p in ax.patches if isinstance(p, matplotlib.patches.FancyArrowPatch)]
    path = arrow.get_path()
    assert path.codes[2] == path.CURVE3
    ends = path.vertices[[0, 2]]  # where the arc starts and ends (the head shortens it a little)
    radius = np.hypot(*(ends - s["O2"][2]).T)
    np.testing.assert_allclose(radius, radius[0], rtol=0.02)  # an arc about O2
    assert radius[0] <= np.hypot(*(s["A"][2] - s["O2"][2]))


def test_plot_input_output():
    s = sweep(four_bar(crank=30.0), samples(37))
    angle = np.degrees(np.arctan2(*(s["B"] - s["O4"])[:, ::-1].T))
    fig, ax = plt.subplots()
    assert gp.plot_input_output(s, {"rocker angle": angle}, ax=ax) is ax
    (line,) = ax.get_lines()
    np.testing.assert_allclose(line.get_xdata(), np.degrees(s.input_values))
    assert np.isnan(line.get_ydata()[~s.valid]).all()
    assert ax.get_xlabel() == "theta (deg)"
    # the one curve's label names the y axis; of two, the legend tells them apart
    assert ax.get_ylabel() == "rocker angle"
    fig, ax = plt.subplots()
    gp.plot_input_output(s, {"x": s["B"][:, 0], "y": s["B"][:, 1]}, ax=ax, ylabel="B (mm)")
    assert ax.get_ylabel() == "B (mm)"
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["x", "y"]
    with pytest.raises(GeokinError, match="one value per sample"):
        gp.plot_input_output(s, angle[:5], ax=ax)


def test_axes_carry_the_construction_units():
    """Lengths in the script's unit on the mechanism's axes; none named without one."""
    c = four_bar()
    c.units = "mm"
    ax = gp.plot_mechanism(sweep(c, samples(9)))
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("x (mm)", "y (mm)")
    fig, ax = plt.subplots()
    ax = gp.plot_mechanism(sweep(four_bar(), samples(9)), ax=ax)
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("x", "y")


def test_a_length_input_is_plotted_in_the_construction_units():
    c = Construction("pushed", units="in")
    c.input("s", kind="length", range=(0, 5), samples=6)
    c.fixed("O", 0, 0)
    c.polar("A", "O", "10 + s", 0.5)
    s = sweep(c)
    ax = gp.plot_input_output(s, {"x of A": s["A"][:, 0]})
    assert ax.get_xlabel() == "s (in)"


def test_import_geokin_does_not_import_matplotlib():
    code = "import sys, geokin, geokin.plotting; print('matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "False"


def test_an_animation_by_default_has_60_frames_at_72_dpi(tmp_path, monkeypatch):
    """A few seconds' work: not every sample of a long sweep, nor 800 x 600 pixels."""
    import inspect

    defaults = inspect.signature(gp.animate).parameters
    assert defaults["frames"].default == gp.DEFAULT_FRAMES == 60
    assert defaults["dpi"].default == gp.DEFAULT_DPI == 72
    frames = []
    monkeypatch.setattr(ga.GifWriter, "add", lambda self, rgb: frames.append(rgb.shape))
    gp.animate(sweep(four_bar(), samples(361)), tmp_path / "a.gif", progress=False)
    assert frames == [(432, 576, 3)] * 60
    # the inline animation of a notebook has the same defaults
    inline = inspect.signature(gp.animation_html).parameters
    assert (inline["frames"].default, inline["dpi"].default) == (60, 72)


def test_blitted_frames_are_the_drawing():
    """The frames draw the mechanism over a background drawn once: the same picture."""
    s = sweep(four_bar(), samples(37))
    fig, canvas, scene = ga._drawing(s, 30)
    ga._lay_out(fig, scene, 0)
    draw = ga._blitter(canvas, scene)
    other, other_canvas, other_scene = ga._drawing(s, 30)
    ga._lay_out(other, other_scene, 0)
    for index in (5, 20):
        scene.update(index, grow=True)
        other_scene.update(index, grow=True)
        other_canvas.draw()
        whole = np.asarray(other_canvas.buffer_rgba())[..., :3]
        frame = draw()
        differ = np.any(frame != whole, axis=2)
        # the same but for the rims of a few joint markers, rounded a little apart
        assert differ.mean() < 0.01
        assert np.abs(frame.astype(int) - whole).mean() < 0.5


def test_frame_choice_is_even_and_capped():
    assert ga.frame_indices(5, 10).tolist() == [0, 1, 2, 3, 4]
    assert ga.frame_indices(361, None).size == 300
    assert ga.frame_indices(361, 400).size == 361


def test_kinematics_figure_has_angle_velocity_and_acceleration_against_time():
    from geokin.kinematics import motion
    from geokin.plotting import figure_kinematics

    c = Construction("four-bar")
    c.input("theta", samples=73)
    c.fixed("O2", 0, 0)
    c.fixed("O4", 40, 0)
    c.polar("A", "O2", 10, "theta")
    c.circle_circle("B", ("A", "O4"), (35, 30), branch="left")
    c.link("crank", "O2", "A")
    c.link("coupler", "A", "B")
    c.link("rocker", "O4", "B")
    m = motion(sweep(c))
    fig, axes = figure_kinematics(m)
    assert len(axes) == 3 and axes[-1].get_xlabel() == "time (s)"
    # degrees throughout, as geokin trace --derivatives writes them
    assert [ax.get_ylabel() for ax in axes] == ["angle (deg)", "ω (deg/s)", "α (deg/s²)"]
    assert all(len(ax.get_lines()) == 3 for ax in axes)
    np.testing.assert_allclose(axes[1].get_lines()[0].get_ydata(), 360.0)  # deg/s
    plt.close(fig)
    with pytest.raises(GeokinError, match="did you mean 'rocker'"):
        figure_kinematics(m, links=["roker"])


def test_a_link_that_turns_fully_is_wrapped_and_broken_at_each_wrap():
    """The six-bar's crank runs 0..1792 deg; drawn within ±180, with no line across the axes."""
    from geokin import load
    from geokin.kinematics import motion

    m = motion(sweep(load("constructions/sixbar.toml")))
    fig, axes = gp.figure_kinematics(m)
    lines = {line.get_label(): line for line in axes[0].get_lines()}
    assert set(lines) == {"crank (wrapped to ±180°)", "coupler", "rocker", "output"}
    crank = lines["crank (wrapped to ±180°)"]
    x, y = crank.get_xdata(), crank.get_ydata()
    finite = np.isfinite(y)
    assert np.all((y[finite] >= -180) & (y[finite] <= 180))
    # the samples themselves lie in (-180, 180]; -180 only where a wrap starts again
    on_samples = np.isin(x, m.time)
    assert np.all(y[on_samples & finite] > -180)
    # five wraps in 1792 deg (at 180, 540, ..., 1620), each a gap, never a jump across
    assert np.isnan(y).sum() == 5
    step = np.abs(np.diff(y))
    assert np.nanmax(step) < 20  # 16 deg a sample
    np.testing.assert_allclose(np.degrees(m.angle["crank"]) % 360, y[on_samples] % 360,
                               atol=1e-9)
    # the rocker does not turn fully: drawn as it runs, not wrapped
    np.testing.assert_array_equal(lines["rocker"].get_ydata(), np.degrees(m.angle["rocker"]))
    lo, hi = axes[0].get_ylim()
    assert hi - lo < 500  # the rockers are not flattened by five turns of the crank


def test_wrap_degrees_breaks_both_ways_and_keeps_gaps():
    from geokin.plotting.charts import wrap_degrees

    x, y = wrap_degrees(np.arange(5.0), [170.0, 190.0, np.nan, 170.0, -200.0])
    assert x.tolist() == [0.0, 0.5, 0.5, 0.5, 1.0, 2.0, 3.0, 3.0 + 350 / 370,
                          3.0 + 350 / 370, 3.0 + 350 / 370, 4.0]
    # up through 180 at x = 0.5; down from 170 through -180 (and on as 160) at x = 3.95
    np.testing.assert_array_equal(y, [170.0, 180.0, np.nan, -180.0, -170.0, np.nan, 170.0,
                                      -180.0, np.nan, 180.0, 160.0])
    for edge in (-540.0, -180.0, 180.0, 540.0):  # on the edge: 180, the interval's end
        assert wrap_degrees([0.0], [edge])[1].tolist() == [180.0]


# -- streamed, whole or nothing -------------------------------------------------------


def test_gif_frames_are_what_was_drawn(tmp_path, small_frames, monkeypatch):
    drawn = []
    add = ga.GifWriter.add
    monkeypatch.setattr(ga.GifWriter, "add", lambda self, rgb: (drawn.append(rgb.copy()),
                                                                 add(self, rgb)))
    path = gp.animate(sweep(four_bar(), samples(37)), tmp_path / "f.gif", dpi=25, frames=8, fps=20,
                      progress=False)
    with Image.open(path) as gif:
        assert (gif.n_frames, gif.info["loop"]) == (8, 0)
        for k, expected in enumerate(drawn):
            gif.seek(k)
            assert gif.info["duration"] == 50
            decoded = np.asarray(gif.convert("RGB"), dtype=int)
            # each frame holds what changed since the last, in a palette of 256 colours
            assert np.abs(decoded - expected).mean() < 1.0
    assert not np.array_equal(drawn[0], drawn[-1])


def test_gif_writer_writes_each_frame_as_it_comes():
    stream = io.BytesIO()
    writer = ga.GifWriter(stream, fps=10)
    sizes = []
    rng = np.random.default_rng(0)
    frame = rng.integers(0, 256, size=(60, 80, 3), dtype=np.uint8) // 64 * 64  # 64 colours
    for _ in range(4):
        frame[rng.integers(60), :] = rng.integers(256, size=3)  # a line changes
        writer.add(frame)
        sizes.append(stream.tell())
    writer.finish()
    assert sizes == sorted(set(sizes))  # bytes out after every frame, none held back
    assert sizes[1] - sizes[0] < sizes[0] / 4  # a frame after the first: only its change
    with Image.open(io.BytesIO(stream.getvalue())) as gif:
        assert gif.n_frames == 4
        gif.seek(3)
        assert np.array_equal(np.asarray(gif.convert("RGB")), frame)


def test_html_writer_writes_each_frame_as_it_comes():
    stream = io.BytesIO()
    writer = ga.PageWriter(stream, 25, "<b>crank</b> \x1b[2J", (80, 60), 3)
    sizes = [stream.tell()]
    for level in (0, 128, 255):
        writer.add(np.full((60, 80, 3), level, np.uint8))
        sizes.append(stream.tell())
    writer.finish()
    page = stream.getvalue().decode()
    assert sizes == sorted(set(sizes))
    assert page.count("data:image/png;base64,") == 3 and page.rstrip().endswith("</html>")
    assert "<title>&lt;b&gt;crank&lt;/b&gt; \\x1b[2J</title>" in page
    assert "var interval = 40;" in page


@pytest.mark.parametrize("suffix", [".gif", ".html"])
def test_an_animation_that_would_not_fit_on_the_disk_is_refused_up_front(
        tmp_path, monkeypatch, suffix):
    class Usage:
        free = 1_000_000

    monkeypatch.setattr(ga.shutil, "disk_usage", lambda folder: Usage)
    drawn = []
    monkeypatch.setattr(Scene, "update", lambda self, *a, **k: drawn.append(a))
    with pytest.raises(GeokinError) as error:
        gp.animate(sweep(four_bar(), samples(3000)), tmp_path / f"big{suffix}", frames=3000,
                   dpi=100)
    message = str(error.value)
    assert "an animation of 3,000 frames of 800 x 600 pixels needs about" in message
    assert "but only 1 MB are free there; ask for fewer frames" in message
    assert drawn == [] and list(tmp_path.iterdir()) == []


def test_an_animation_that_would_not_fit_in_memory_is_refused_up_front(tmp_path, monkeypatch):
    monkeypatch.setattr(budgets, "memory_budget", lambda: 5_000_000)
    with pytest.raises(BudgetError, match=r"cannot write '.*a\.gif': drawing an animation of 3 "
                       r"frames of 800 x 600 pixels needs about \d+ MB, more than the 5 MB "
                       r"budget \(.* memory\); ask for fewer samples") as error:
        gp.animate(sweep(four_bar(), samples(30)), tmp_path / "a.gif", frames=3, dpi=100)
    assert error.value.budget == 5_000_000 < error.value.needed
    assert list(tmp_path.iterdir()) == []
    file_bytes, memory_bytes = gp.animation_estimate(10, 800, 600, ".gif", samples=10**6,
                                                     traces=2)
    assert memory_bytes > 96e6  # the traced paths count, not only the frame


@pytest.mark.parametrize("suffix", [".gif", ".html"])
def test_an_interrupted_animation_leaves_the_old_file(tmp_path, small_frames, monkeypatch,
                                                      suffix):
    path = tmp_path / f"old{suffix}"
    path.write_bytes(b"the old animation")
    count = []

    def update(self, index, grow=False):
        count.append(index)
        if len(count) == 3:
            raise KeyboardInterrupt

    monkeypatch.setattr(Scene, "update", update)
    with pytest.raises(KeyboardInterrupt):
        gp.animate(sweep(four_bar(), samples(37)), path, dpi=25, frames=10, progress=False)
    assert path.read_bytes() == b"the old animation"
    assert [p.name for p in tmp_path.iterdir()] == [path.name]


def test_a_failing_save_leaves_the_old_picture(tmp_path, monkeypatch):
    fig, _ = gp.figure_mechanism(sweep(four_bar(), samples(5)))
    path = tmp_path / "old.png"
    path.write_bytes(b"the old picture")

    def savefig(stream, **kwargs):
        stream.write(b"\x89PNG half")
        raise OSError("disk full")

    monkeypatch.setattr(fig, "savefig", savefig)
    with pytest.raises(OSError, match="disk full"):
        gp.save(fig, path)
    assert path.read_bytes() == b"the old picture"
    assert [p.name for p in tmp_path.iterdir()] == ["old.png"]


def test_fps_outside_what_a_gif_can_hold(tmp_path):
    for fps in (1e-300, 0.001, 101, 1e300, float("nan")):
        with pytest.raises(GeokinError, match="fps must be a number from 0.01 to 100"):
            gp.animate(sweep(four_bar(), samples(5)), tmp_path / "a.gif", fps=fps)


def test_a_title_is_text_not_mathtext_nor_terminal_codes(tmp_path):
    c = four_bar()
    c.name = r"$\frac$ costs 5$ and \x1b[2J" + "\x1b[2J" + "x" * 1000
    fig, ax = gp.figure_mechanism(sweep(c, samples(5)))
    gp.save(fig, tmp_path / "title.png")  # "$\frac$" would stop mathtext
    title = ax.get_title()
    assert title.startswith(r"$\frac$ costs 5$ and \x1b[2J\x1b[2Jxxx")
    assert title.endswith("[1,032 characters]")
    # broken into lines that fit the figure, each of them printable
    lines = title.splitlines()
    assert len(lines) > 1 and all(line.isprintable() and len(line) <= 80 for line in lines)


@pytest.fixture
def fake_ffmpeg(tmp_path, monkeypatch):
    """An ffmpeg that copies the raw frames it is given to its output file, or fails."""
    def install(script):
        program = tmp_path / "bin" / "ffmpeg"
        program.parent.mkdir(exist_ok=True)
        program.write_text("#!/bin/sh\n" + script)
        program.chmod(0o755)
        monkeypatch.setitem(matplotlib.rcParams, "animation.ffmpeg_path", str(program))
    return install


@pytest.mark.skipif(sys.platform == "win32", reason="a shell script stands for ffmpeg")
def test_mp4_frames_go_to_ffmpeg_and_its_file_into_place(tmp_path, small_frames, fake_ffmpeg):
    fake_ffmpeg('for last; do :; done\ncat > "$last"\n')
    path = tmp_path / "old.mp4"
    path.write_bytes(b"the old movie")
    gp.animate(sweep(four_bar(), samples(37)), path, dpi=25, frames=5, progress=False)
    width, height = 200, 150  # 8 x 6 inches at 25 dpi
    assert path.stat().st_size == 5 * width * height * 4  # five RGBA frames
    assert [p.name for p in tmp_path.iterdir() if p.is_file()] == ["old.mp4"]


@pytest.mark.skipif(sys.platform == "win32", reason="a shell script stands for ffmpeg")
def test_a_failing_ffmpeg_is_an_error_and_leaves_the_old_file(tmp_path, small_frames,
                                                              fake_ffmpeg):
    fake_ffmpeg("echo 'Unknown encoder libx264' >&2\nexit 1\n")
    path = tmp_path / "old.mp4"
    path.write_bytes(b"the old movie")
    with pytest.raises(GeokinError, match=r"ffmpeg stopped with status 1: Unknown encoder"):
        gp.animate(sweep(four_bar(), samples(37)), path, dpi=25, frames=5, progress=False)
    assert path.read_bytes() == b"the old movie"
    assert [p.name for p in tmp_path.iterdir() if p.is_file()] == ["old.mp4"]


PLAYER_CHECK = """
const fs = require("fs");
const page = fs.readFileSync(process.argv[2], "utf8");
const scripts = [...page.matchAll(/<script>([\\s\\S]*?)<\\/script>/g)].map(m => m[1]);
const elements = {};
const document = { getElementById: id => (elements[id] = elements[id] ||
  { id: id, value: "0", checked: id === "loop", innerHTML: "", textContent: "", src: "" }) };
let timer = null, interval = null;
const setInterval = (f, ms) => { timer = f; interval = ms; return 1; };
const clearInterval = () => { timer = null; };
const frames = new Function("document", "setInterval", "clearInterval",
  scripts.join("\\n") + "; return frames;")(document, setInterval, clearInterval);
const seen = [];
const shown = () => seen.push([frames.indexOf(elements.frame.src), elements.counter.textContent]);
shown(); timer(); shown(); timer(); timer(); shown();  // plays on, loops to the start
elements.play.onclick(); shown(); seen.push(timer === null);
elements.last.onclick(); shown(); elements.back.onclick(); shown();
elements.slider.value = "0"; elements.slider.oninput(); shown();
console.log(JSON.stringify({seen: seen, interval: interval, frames: frames.length,
                            distinct: new Set(frames).size}));
"""


@pytest.mark.skipif(shutil.which("node") is None, reason="node runs the page's player")
def test_the_html_player_plays_steps_and_loops(tmp_path, small_frames):
    import base64
    import json

    path = gp.animate(sweep(four_bar(), samples(37)), tmp_path / "p.html", dpi=25, frames=3, fps=20,
                      progress=False)
    check = tmp_path / "check.js"
    check.write_text(PLAYER_CHECK)
    done = subprocess.run(["node", str(check), str(path)], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    result = json.loads(done.stdout)
    for frame in path.read_text().split('"data:image/png;base64,')[1:]:
        assert base64.b64decode(frame.split('"')[0]).startswith(b"\x89PNG")
    assert (result["frames"], result["distinct"], result["interval"]) == (3, 3, 50)
    assert result["seen"] == [[0, "1 / 3"], [1, "2 / 3"], [0, "1 / 3"], [0, "1 / 3"], True,
                              [2, "3 / 3"], [1, "2 / 3"], [0, "1 / 3"]]


def test_an_inline_animation_is_html_a_notebook_plays():
    from IPython.display import HTML

    s = sweep(four_bar(), samples(37))
    movie = gp.animation_html(s, frames=4, fps=20, dpi=20)
    assert isinstance(movie, str) and movie._repr_html_() == movie
    assert repr(movie) == f"<AnimationHTML of 'four-bar': 4 frames at 20 fps, {len(movie):,} " \
                          "characters>"
    # every frame, and the first again as the picture a viewer without scripts shows
    frames = movie.split('"data:image/png;base64,')
    assert len(frames) == 6 and frames[1].split('"')[0] == frames[2].split('"')[0]
    assert "<!DOCTYPE" not in movie and "http" not in movie and "var interval = 50;" in movie
    assert HTML(movie)._repr_html_() == movie
    other = gp.animation_html(s, frames=2, dpi=20)
    ids = set(re.findall(r'id="(geokin-\w+-)frame"', movie + other))
    assert len(ids) == 2  # each animation plays its own elements


def test_an_inline_animation_too_large_for_a_notebook_is_refused_up_front():
    s = sweep(four_bar(), samples(37))
    with pytest.raises(GeokinError, match=r"more than the 20 MB a notebook is given; ask for "
                                          r"fewer frames or a lower dpi"):
        gp.animation_html(s, frames=300, dpi=300)
    with pytest.raises(GeokinError, match="dpi must be a number from 1 to 1000"):
        gp.animation_html(s, dpi=float("nan"))
    with pytest.raises(GeokinError, match="fps must be a number"):
        gp.animation_html(s, fps=0)


INLINE_CHECK = """
const fs = require("fs");
const page = fs.readFileSync(process.argv[2], "utf8");
const scripts = [...page.matchAll(/<script>([\\s\\S]*?)<\\/script>/g)].map(m => m[1]);
const elements = {};
const document = { getElementById: id => (elements[id] = elements[id] ||
  { id: id, value: "0", checked: id.endsWith("loop"), innerHTML: "", textContent: "", src: "" }) };
const timers = [];
const setInterval = (f, ms) => { timers.push(f); return timers.length; };
const clearInterval = () => {};
for (const script of scripts) {
  new Function("document", "setInterval", "clearInterval", script)(document, setInterval,
                                                                    clearInterval);
}
timers.forEach(tick => tick());
const counters = Object.keys(elements).filter(id => id.endsWith("counter")).sort();
console.log(JSON.stringify({
  globals: typeof frames, timers: timers.length,
  counters: counters.map(id => elements[id].textContent),
  sources: counters.map(id => elements[id.replace(/counter$/, "frame")].src.length > 100)}));
"""


@pytest.mark.skipif(shutil.which("node") is None, reason="node runs the player")
def test_two_inline_animations_on_one_page_play_each_its_own_frames(tmp_path):
    import json

    s = sweep(four_bar(), samples(37))
    page = tmp_path / "notebook.html"
    page.write_text(gp.animation_html(s, frames=3, dpi=20)
                    + gp.animation_html(s, frames=5, dpi=20))
    check = tmp_path / "check.js"
    check.write_text(INLINE_CHECK)
    done = subprocess.run(["node", str(check), str(page)], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    result = json.loads(done.stdout)
    assert result["globals"] == "undefined"  # the frames stay inside each player
    assert result["timers"] == 2 and result["sources"] == [True, True]
    assert sorted(result["counters"]) == ["2 / 3", "2 / 5"]


@pytest.mark.parametrize("index", [0, 60, 90, 120, 180, 270, 300])
def test_labels_of_the_quick_returns_blocks_keep_off_the_ground_symbols(index):
    """At 90 and 270 degrees the ram's pin B is on C: its label goes beside, not on C's ground."""
    from geokin import load
    from geokin.plotting.layout import symbol_covers

    s = sweep(load("constructions/quick_return.toml"))
    fig = matplotlib.figure.Figure(figsize=gp.FIGSIZE, layout="constrained")
    canvas = matplotlib.backends.backend_agg.FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    scene = Scene(s, ax)
    scene.update(index)
    gp.mechanism.setup_axes(ax, scene.layout, None)
    canvas.draw()
    renderer = canvas.get_renderer()
    layout = scene.layout
    for name in ("A", "B"):  # the points on blocks
        box = scene.labels[name].get_window_extent(renderer)
        # a grid over the label's box, in data units
        xs, ys = np.meshgrid(np.linspace(box.x0, box.x1, 9), np.linspace(box.y0, box.y1, 5))
        grid = ax.transData.inverted().transform(np.column_stack([xs.ravel(), ys.ravel()]))
        for pivot in layout.pivots:
            covered = symbol_covers(s[pivot][index], layout.ground_directions[pivot],
                                    layout.ground_sizes[pivot], grid)
            assert not covered.any(), (name, pivot)


def test_a_link_is_wrapped_only_if_it_turns_fully_within_one_run():
    """A crank of 60 assembles at 0 to 78 deg and 282 to 360 deg only: across the gap the
    unwrapped angles of coupler and rocker span 360 deg, yet neither turns fully."""
    from geokin import load
    from geokin.kinematics import motion

    c = load("constructions/crank_rocker.toml").compile().with_parameters({"l2": 60})
    m = motion(sweep(c))
    assert not m.sweep.valid.all() and np.nanmax(m.angle["rocker"]) - np.nanmin(
        m.angle["rocker"]) >= 2 * np.pi - 1e-9
    fig, axes = gp.figure_kinematics(m)
    labels = {line.get_label() for line in axes[0].get_lines()}
    assert labels == {"crank", "coupler", "rocker"}
    plt.close(fig)


@pytest.mark.parametrize("offset", [30.0, -30.0])
def test_a_fixed_guides_ground_lies_away_from_the_mechanism(offset):
    """A slider-crank's guide clear above or below the crank: no bar crosses its ground."""
    s = sweep(offset_slider_crank(20, 70, offset, samples=73))
    # the crank's circle, of radius 20, stays on one side: the ground goes on the other
    assert Layout(s).guide_sides["slider"] == (1 if offset > 0 else -1)
    for i in range(0, 73, 6):
        ax = gp.plot_mechanism(s, i)
        # the guide's hatched strip: the one far longer than a pivot's
        [ground] = [p for p in ax.patches if p.get_hatch() and np.ptp(p.get_xy()[:, 0]) > 20]
        band = shapely.Polygon(ground.get_xy())
        for a, b in (("O", "A"), ("A", "B")):
            bar = shapely.LineString([s[a][i], s[b][i]])
            assert not bar.intersects(band.buffer(-1e-9)), (i, a, b)
        plt.close(ax.figure)


def test_each_input_that_turns_a_crank_gets_its_arrow():
    """A five-bar's two cranks each show the sense their input turns them in."""
    s = sweep(five_bar(second_turns=-1))  # the second crank turns clockwise
    assert [crank.tip for crank in Layout(s).driven] == ["A", "B"]
    ax = gp.plot_mechanism(s, 10)
    arrows = [p for p in ax.patches if isinstance(p, matplotlib.patches.FancyArrowPatch)]
    assert len(arrows) == 2
    for arrow, pivot, sense in zip(arrows, ((0, 0), (50, 0)), (1, -1), strict=True):
        tail, head = (np.array(point) - pivot for point in arrow._posA_posB)
        assert np.sign(tail[0] * head[1] - tail[1] * head[0]) == sense  # counter-clockwise: +
    plt.close(ax.figure)


@pytest.mark.parametrize("sense", [1, -1])
def test_a_point_an_input_pushes_gets_a_straight_arrow_away_from_its_ground(sense):
    """A piston B pushed along the x axis by a length input: the arrow shows its sense."""
    c = Construction("piston-driven crank")
    c.input("s", kind="length", range=(55, 85)[::sense], samples=31)
    c.fixed("O", 0, 0)
    c.fixed("G", 100, 0)
    c.fixed("B", "s", 0)
    c.circle_circle("A", ("O", "B"), (20, 70), branch="left")
    c.link("crank", "O", "A")
    c.link("rod", "A", "B")
    c.slider("piston", "B", ("O", "G"))
    s = sweep(c)
    layout = Layout(s)
    assert layout.pushed == [("B", "s")] and layout.driven == []
    ax = gp.plot_mechanism(s, 15)
    [arrow] = [p for p in ax.patches if isinstance(p, matplotlib.patches.FancyArrowPatch)]
    tail, head = (np.array(point) for point in arrow._posA_posB)
    assert np.sign(head[0] - tail[0]) == sense and head[1] == pytest.approx(tail[1])
    # beside the block, on the side away from the hatched ground
    ground = layout.guide_sides["piston"]  # the guide runs along +x: +1 is above
    assert np.sign(tail[1] - s["B"][15][1]) == -ground
    # O stands on the guide's ground, clear of the crank swinging above it
    assert ground == -1 and math.sin(layout.ground_directions["O"]) == pytest.approx(-1)
    plt.close(ax.figure)
