"""examples/notebook.ipynb runs as Jupyter runs it, and shows what it says it shows.

nbclient executes every cell in an IPython kernel of the Python running these
tests (a kernel spec of its own, so a user's kernels or IPython profile play no
part), in the notebook's folder, and the outputs are checked: the tables and
the picture of the rich display, the figures, and the inline animation.
"""

import contextlib
import json
import sys
import time
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

NOTEBOOK = Path(__file__).parents[1] / "examples" / "notebook.ipynb"


@pytest.fixture(scope="module")
def executed(tmp_path_factory):
    """The notebook after running it, and the seconds it took."""
    home = tmp_path_factory.mktemp("jupyter")
    spec = home / "kernels" / "python3"
    spec.mkdir(parents=True)
    (spec / "kernel.json").write_text(json.dumps({
        "argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
        "display_name": "Python 3 (the tests' own)", "language": "python"}))
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("JUPYTER_PATH", str(home))  # searched before the user's kernels
        patch.setenv("IPYTHONDIR", str(home / "ipython"))  # no profile, no startup files
        notebook = nbformat.read(NOTEBOOK, as_version=4)
        client = NotebookClient(notebook, timeout=120, kernel_name="python3",
                                resources={"metadata": {"path": str(NOTEBOOK.parent)}})
        start = time.monotonic()
        with contextlib.ExitStack() as stack:
            try:
                stack.enter_context(client.setup_kernel())
            except Exception as err:  # nothing of geokin has run yet
                pytest.fail(f"cannot start a Jupyter kernel for {sys.executable} "
                            f"({type(err).__name__}: {err}); the notebook was not run. It "
                            "needs ipykernel and nbclient (the test extra) and local "
                            "sockets between processes", pytrace=False)
            for index, cell in enumerate(notebook.cells):
                # a cell that fails raises CellExecutionError with its traceback
                client.execute_cell(cell, index, execution_count=client.code_cells_executed + 1)
        return notebook, time.monotonic() - start


def outputs(notebook, text):
    """Return the outputs of the one code cell whose source holds ``text``."""
    [cell] = [c for c in notebook.cells if c.cell_type == "code" and text in c.source]
    return cell.outputs


def shown(notebook, text, kind="text/html"):
    """Return what the cell holding ``text`` shows as ``kind``, all outputs joined."""
    return "".join(o.get("data", {}).get(kind, "") for o in outputs(notebook, text))


def test_every_cell_runs_without_an_error(executed):
    notebook, seconds = executed
    code = [c for c in notebook.cells if c.cell_type == "code"]
    assert code and all(c.execution_count for c in code)
    errors = [o for c in code for o in c.outputs if o.output_type == "error"]
    assert not errors
    assert seconds < 60  # about 10 s on the project's machine


def test_the_construction_and_the_sweep_show_as_tables_with_a_picture(executed):
    notebook, _ = executed
    construction = shown(notebook, "sixbar = geokin.load")
    assert '<table class="geokin">' in construction
    assert "angle, 0 to 1800 deg, every 16 deg, 360 deg/s" in construction
    sweep = shown(notebook, "s = geokin.sweep(sixbar)")
    assert "Sweep of &#x27;six-bar&#x27;" in sweep and "113, all valid" in sweep
    assert "0 to 1792 deg" in sweep
    assert sweep.count("<svg") == 1 and "<title>path of M</title>" in sweep
    assert shown(notebook, "s = geokin.sweep(sixbar)", "text/plain") == \
        "<Sweep of 'six-bar': 113 samples, 113 valid, 0 branch changes>"
    circuit = shown(notebook, "rocker = geokin.circuit")
    assert "branch changes</th><td style=\"text-align:left\">2: C:" in circuit
    assert "<polyline" in circuit


def test_the_motion_shows_its_rates_in_the_units_of_the_script(executed):
    notebook, _ = executed
    motion = shown(notebook, "m = geokin.motion(s)")
    assert "Motion of &#x27;six-bar&#x27; driven by theta" in motion
    assert "113: 113 valid, 0 flagged" in motion and "mm/s²" in motion
    assert "link crank</th><td style=\"text-align:left\">angular velocity up to 360 deg/s" \
        in motion


def test_the_figures_are_drawn_inline(executed):
    notebook, _ = executed
    for cell in ("gp.figure_mechanism(s, 20)", "gp.figure_kinematics(m)"):
        images = [o for o in outputs(notebook, cell) if "image/png" in o.get("data", {})]
        assert len(images) == 1, cell


def test_the_animation_plays_inline(executed):
    notebook, _ = executed
    movie = shown(notebook, "gp.animation_html(s, frames=30)")
    assert movie.count("data:image/png;base64,") == 31  # 30 frames and the still picture
    assert "<script>" in movie and 'class="geokin-player"' in movie
    assert shown(notebook, "gp.animation_html(s, frames=30)", "text/plain").startswith(
        "<AnimationHTML of 'six-bar': 30 frames at 25 fps, ")


def test_no_output_prints_arrays_at_length(executed):
    notebook, _ = executed
    plain = [o["data"]["text/plain"] for c in notebook.cells if c.cell_type == "code"
             for o in c.outputs if "text/plain" in o.get("data", {})]
    assert plain and all(len(text) < 500 for text in plain)
    report = shown(notebook, "geokin.analyze(sixbar, degrees=True)")
    assert report.startswith("<pre>six-bar\n") and "crank-rocker (GCRR)" in report
