"""Results as a notebook shows them: short reprs, HTML tables and SVG pictures."""

import re
import subprocess
import sys
import time
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
from mechanisms import sixbar

import geokin
from geokin import Construction, display
from geokin.kinematics import input_derivatives

CONSTRUCTIONS = Path(__file__).parents[1] / "constructions"
LONG = "x" * 5000  # a name no repr should print whole


def long_named_sixbar():
    """Seed 003's six-bar under a very long name, its input renamed to a long one too."""
    c = sixbar()
    c.name = LONG
    return c


@pytest.fixture(scope="module")
def large():
    """A sweep of 200,000 samples, its motion, limits and report."""
    c = long_named_sixbar()
    s = geokin.sweep(c, np.linspace(0, 10 * np.pi, 200_000))
    return {"sweep": s, "motion": geokin.motion(s), "derivatives": input_derivatives(s),
            "limits": geokin.limits(c), "report": geokin.analyze(c)}


def test_reprs_stay_short_for_a_large_sweep(large):
    report = large["report"]
    shown = {name: repr(value) for name, value in large.items()}
    shown |= {f"{name}.{key}": repr(entry) for name in ("inputs", "transmission_angles",
                                                         "strokes", "curves")
              for key, entry in getattr(report, name).items()}
    shown |= {f"four_bars[{i}]": repr(bar) for i, bar in enumerate(report.four_bars)}
    for name, text in shown.items():
        assert len(text) < 200, (name, text)
        assert "\n" not in text, name
    assert shown["motion"] == (f"<Motion of {display_name()} driven by 'theta': 200000 "
                               f"samples, {int(large['motion'].flagged.sum())} flagged>")
    assert shown["sweep"].startswith(f"<Sweep of {display_name()}: 200000 samples, ")
    assert shown["limits"] == "<Limits of 'theta': turns fully>"
    assert shown["report"].startswith(f"<Report of {display_name()}: DOF 1, 1 input(s), "
                                      "four-bars: crank-rocker, ")


def display_name():
    return repr(f"{'x' * 26}…{'x' * 13} [5,000 characters]")


def test_a_repr_says_what_a_result_holds():
    c = sixbar()
    s = geokin.sweep(c)
    m = geokin.motion(s)
    assert repr(m) == f"<Motion of 'six-bar' driven by 'theta': 113 samples, " \
                      f"{int(m.flagged.sum())} flagged>"
    assert repr(m.derivatives) == ("<Derivatives by 'theta': 113 samples, step "
                                   f"{m.derivatives.step:.3g}, 0 without a stencil>")
    rocker = Construction("triple rocker")
    rocker.input("theta2", range=(-np.pi, np.pi))
    rocker.fixed("A", 0, 0)
    rocker.fixed("D", 7, 0)
    rocker.polar("B", "A", 5, "theta2")
    rocker.circle_circle("C", ("B", "D"), (6, 5), branch="left")
    assert repr(geokin.limits(rocker)) == ("<Limits of 'theta2': -2.30693 to 2.30693 "
                                           "(tangent at 'C', tangent at 'C')>")
    report = geokin.analyze(rocker, degrees=True)
    assert repr(report.inputs["theta2"]) == ("<InputReport (angle): 1 interval(s) from "
                                             "-132.177 to 132.177, 2 limit(s)>")
    assert repr(report.inputs["theta2"].limits[0]) == "<LimitReport: tangent at -132.177, " \
                                                      "node 'C'>"
    assert re.fullmatch(r"<FourBarReport at 'C': triple-rocker RRR1; ground 7, "
                        r"input 5, coupler 6, output 5>", repr(report.four_bars[0]))


# -- HTML ---------------------------------------------------------------------------

HOSTILE = '<script>alert("name")</script><img src=x onerror="alert(1)"> & \x1b[2J'
TAGS = {"table", "thead", "tbody", "tr", "th", "td", "div", "span", "details", "summary",
        "pre", "svg", "g", "title", "polyline", "rect"}


class Tags(HTMLParser):
    """Every tag and attribute of a page, and its text."""

    def __init__(self):
        super().__init__()
        self.tags, self.attributes, self.text = [], [], []

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        self.attributes += [name for name, _ in attrs]

    def handle_data(self, data):
        self.text.append(data)


def parsed(page):
    tags = Tags()
    tags.feed(page)
    tags.close()
    return tags


def crank(name="crank", **options):
    c = Construction(name, **options)
    c.input("theta")
    c.fixed("O", 0, 0)
    c.polar("A", "O", 10, "theta")
    c.link("crank", "O", "A")
    return c


def test_html_escapes_everything_from_a_script():
    c = crank(HOSTILE, description=HOSTILE, units=HOSTILE)
    s = geokin.sweep(c, np.linspace(0, np.pi, 19))
    pages = {"construction": c._repr_html_(), "compiled": c.compile()._repr_html_(),
             "sweep": s._repr_html_(), "motion": geokin.motion(s)._repr_html_(),
             "report": geokin.analyze(c)._repr_html_()}
    broken = Construction(HOSTILE)
    broken.fixed("O", 0, 0)
    broken.polar("A", "O", 10, "theta")
    pages["unfinished"] = broken._repr_html_()
    for what, page in pages.items():
        tags = parsed(page)
        assert set(tags.tags) <= TAGS, (what, set(tags.tags) - TAGS)
        assert not [a for a in tags.attributes if a.startswith("on")], what
        assert "\x1b" not in page, what
        # the name is shown, as text
        shown = "".join(tags.text)
        assert '<script>alert("name")</script>' in shown, what
    assert "unknown parameter or input" in "".join(parsed(pages["unfinished"]).text)


def test_a_construction_shows_its_inputs_in_the_units_of_its_script():
    c = geokin.load(CONSTRUCTIONS / "sixbar.toml")
    text = "".join(parsed(c._repr_html_()).text)
    assert "input thetaangle, 0 to 1800 deg, every 16 deg, 360 deg/s" in text
    assert "lengths inmm" in text and "tracedM" in text
    assert "9  M   = ray_circle(Ap->C; Ap, l5)  [second]" in text
    slider = Construction("slider", units="mm")
    slider.input("s", kind="length", range=(0, 5), samples=11, speed=2)
    slider.fixed("O", 0, 0)
    slider.fixed("B", "s", 0)
    sweep_text = "".join(parsed(geokin.sweep(slider)._repr_html_()).text)
    assert "input s0 to 5 mm" in sweep_text


def polylines(page):
    """Every polyline of a page's SVG, as (colour, (M, 2) array of pixels)."""
    found = re.findall(r'<polyline points="([^"]*)" fill="none" stroke="(#\w+)"', page)
    return [(colour, np.array([[float(v) for v in xy.split(",")] for xy in points.split()]))
            for points, colour in found]


def svg_size(page):
    width, height = re.search(r'<svg [^>]*width="(\d+)" height="(\d+)"', page).groups()
    return int(width), int(height)


def test_the_picture_draws_a_path_where_it_is_with_y_upwards():
    c = crank()
    c.trace("A")
    page = geokin.sweep(c, np.linspace(0, np.pi / 2, 91))._repr_html_()
    width, height = svg_size(page)
    assert width == height  # a quarter circle fills a square: x and y at one scale
    [(grey, crank_bar), (colour, path)] = polylines(page)
    assert colour == display.PATH_COLORS[0] and grey != colour
    assert len(path) == 91 and ((path >= 0) & (path <= [width, height])).all()
    # A goes from (10, 0) on the right to (0, 10) at the top: pixels' y grows downwards
    assert path[0, 0] > path[-1, 0] and path[0, 1] > path[-1, 1]
    centre = np.array([path[-1, 0], path[0, 1]])
    radius = np.hypot(*(path - centre).T)
    assert np.ptp(radius) < 0.2 and radius.mean() > 0.8 * (width - 16)
    np.testing.assert_allclose(crank_bar, [centre, path[0]], atol=0.1)  # at sample 0


def test_a_path_breaks_where_samples_between_the_drawn_ones_cannot_be_assembled():
    c = Construction("nearly stretched")
    c.input("theta")
    c.fixed("O2", 0, 0)
    c.fixed("O4", 40, 0)
    c.polar("A", "O2", 10, "theta")
    # the links reach 49.9999 of the 50 between A and O4 at 180 degrees: a gap of 0.6 deg
    c.circle_circle("B", ("A", "O4"), (35, 14.9999), branch="left")
    c.trace("B")
    s = geokin.sweep(c, np.linspace(0, 2 * np.pi, 100_001))
    kept = display.decimate(len(s))
    assert s.valid[kept].all() and not s.valid.all()  # no drawn sample falls in the gap
    paths = [line for colour, line in polylines(s._repr_html_()) if colour != "#9a9a9a"]
    assert len(paths) == 2 and sum(len(line) for line in paths) == len(kept)
    assert "cannot be assembled" in s._repr_html_()


def test_a_million_samples_display_at_once_and_in_a_few_kilobytes():
    c = geokin.load(CONSTRUCTIONS / "sixbar.toml")
    s = geokin.sweep(c, np.linspace(0, 10 * np.pi, 1_000_000))
    start = time.process_time()
    page = s._repr_html_()
    took = time.process_time() - start
    assert took < 0.5 and len(page) < 20_000
    assert all(len(line) <= display.POLYLINE_POINTS for _, line in polylines(page))


def test_a_motion_shows_its_flagged_samples_and_largest_rates():
    rocker = geokin.load(CONSTRUCTIONS / "triple_rocker_crank.toml")
    m = geokin.motion(geokin.circuit(rocker))
    text = "".join(parsed(m._repr_html_()).text)
    flagged = int(m.flagged.sum())
    assert flagged and f"{len(m.time)}: {len(m.time)} valid, {flagged} flagged (the first " \
                      f"at sample {int(np.argmax(m.flagged))})" in text
    good = ~m.flagged
    omega = np.degrees(np.abs(m.angular_velocity["follower"][good]).max())
    assert f"link followerangular velocity up to {omega:.6g} deg/s" in text
    assert "link ground" not in text  # the frame does not turn
    assert f"input theta2{np.degrees(abs(m.speed[0])):.6g} deg/s" in text


def test_a_construction_renamed_after_compiling_shows_its_new_name_and_units():
    c = crank()
    c.compile()
    c.name, c.units = "renamed", "mm"
    assert (c.compile().name, c.compile().units) == ("renamed", "mm")
    assert "Construction &#x27;renamed&#x27;" in c._repr_html_()


def test_showing_results_imports_neither_matplotlib_nor_ipython():
    shown = subprocess.run([sys.executable, "-c", """if True:
        import sys
        import geokin
        c = geokin.load(sys.argv[1])
        s = geokin.sweep(c)
        pages = [c._repr_html_(), s._repr_html_(), geokin.motion(s)._repr_html_()]
        assert all("<table" in page for page in pages)
        print(sorted({m.split(".")[0] for m in sys.modules} & {"matplotlib", "IPython"}))
        """, str(CONSTRUCTIONS / "sixbar.toml")], capture_output=True, text=True, timeout=120)
    assert shown.returncode == 0, shown.stderr
    assert shown.stdout.strip() == "[]"


def test_a_sweep_of_fixed_points_shows_them_without_paths():
    c = Construction("frame")
    c.fixed("O", 0, 0)
    c.fixed("Q", 3, 4)
    page = geokin.sweep(c)._repr_html_()
    assert page.count("<rect") == 2 and "<polyline" not in page and "path of" not in page
