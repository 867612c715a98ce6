"""The README's Python example runs as written, and its quick start names real things."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def test_the_python_example_runs(monkeypatch):
    blocks = re.findall(r"```python\n(.*?)```", README, flags=re.S)
    assert blocks
    monkeypatch.chdir(ROOT)
    for block in blocks:
        exec(compile(block, "README.md", "exec"), {})


def test_the_annotated_script_is_the_one_shipped_and_it_loads():
    import geokin

    block = re.search(r"```toml\n(# Header comments.*?)```", README, flags=re.S).group(1)
    assert block == (ROOT / "examples" / "annotated.toml").read_text(encoding="utf-8")
    s = geokin.sweep(geokin.loads(block, source="README.md"))
    assert s.valid.all() and set(s.points) == {"O2", "O4", "A", "B", "P", "Q"}


def test_every_file_the_readme_names_exists():
    for name in set(re.findall(r"(?:constructions|examples|tests|geokin)/[\w./-]+\.\w+", README)):
        assert (ROOT / name).exists(), name


def test_the_quick_start_has_two_commands_one_for_the_tests():
    quick = README.split("## Quick start", 1)[1].split("##", 1)[0]
    commands = [line for line in re.findall(r"```sh\n(.*?)```", quick, flags=re.S)[0].splitlines()
                if line and not line.startswith("#")]
    assert len(commands) == 2
    assert commands[1].endswith("pytest") and "geokin plot" in commands[0]
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert "pip install -e '.[test]' && pytest" in ci


def test_the_example_error_is_what_geokin_check_prints(tmp_path, capsys):
    """The README's example error, from the six-bar with the typo it describes."""
    from geokin.cli import main

    section = README.split("A script that cannot be read", 1)[1]
    typo = re.search(r'with `l3` mistyped `l33` in\s+B\'s radii \(`(radii = \[".*?\])`\)',
                     section).group(1)
    right = typo.replace('"l33"', '"l3"')
    example = re.search(r"```\n(.*?)\n```", section, flags=re.S).group(1)
    script = (ROOT / "constructions" / "sixbar.toml").read_text(encoding="utf-8")
    assert right in script
    (tmp_path / "sixbar.toml").write_text(script.replace(right, typo), encoding="utf-8")
    assert main(["check", str(tmp_path / "sixbar.toml")]) == 2
    err = capsys.readouterr().err
    assert err.strip().endswith(example.replace("sixbar.toml", str(tmp_path / "sixbar.toml")))


def test_the_readme_states_the_tolerances_of_limits_and_strokes_as_they_are():
    from geokin.analysis.report import MEETING_SPREAD, ROUNDING
    from geokin.circuits import ROUNDING_GAP_PROBES
    from geokin.engine import MEET_RTOL

    text = " ".join(README.split())
    assert f"where {ROUNDING_GAP_PROBES} inputs evenly spaced across it" in text
    assert f"no failure wider than 1/{ROUNDING_GAP_PROBES + 1} of the gap" in text
    assert f"to rounding ({ROUNDING:.0e}, of 1 rad for an angle)".replace("e-0", "e-") in text
    assert (f"to {MEETING_SPREAD:g} times the branch rules' meeting tolerance of that node "
            f"({MEET_RTOL:.0e} of its scale".replace("e-0", "e-")) in text
