"""Mutated scripts end in success or a GeokinError, never anything else (tests/fuzz_scripts.py).

The suite runs every mutation on every shipped script once, then random
combinations: ``GEOKIN_FUZZ_EXAMPLES`` of them (60 by default; the hypothesis
profile fixes them in CI). ``python tests/fuzz_scripts.py --cases 10000``
runs a longer fuzz.
"""

import os
import pathlib
import random

import pytest
from fuzz_scripts import DATA_MUTATIONS, SOURCES, bytes_mutation, mutate, run_case
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

ROOT = pathlib.Path(__file__).resolve().parents[1]
RAW = {p.name: p.read_bytes() for p in SOURCES}


def check(outcome):
    assert not outcome.unexpected, (outcome.ending, outcome.where, outcome.error,
                                    outcome.details)


def test_every_shipped_script_is_fuzzed_and_passes_unmutated(tmp_path):
    shipped = {p.name for p in ROOT.glob("constructions/*.toml")} | {"annotated.toml"}
    assert set(RAW) == shipped
    for raw in RAW.values():
        assert run_case(raw, tmp_path).ending == "ok"


@pytest.mark.parametrize("mutation", DATA_MUTATIONS, ids=lambda m: m.__name__.strip("_"))
def test_each_mutation_of_each_script(tmp_path, mutation):
    import tomllib

    from fuzz_scripts import to_toml

    endings = set()
    for k, (_, raw) in enumerate(sorted(RAW.items())):
        rng = random.Random(k)
        data = tomllib.loads(raw.decode())
        mutation(data, rng)
        outcome = run_case(to_toml(data).encode("utf-8", "surrogatepass"), tmp_path)
        check(outcome)
        endings.add(outcome.ending)
    assert endings  # ran


def test_each_byte_mutation_of_each_script(tmp_path):
    endings = set()
    for k in range(8 * len(RAW)):
        rng = random.Random(k)
        name = sorted(RAW)[k % len(RAW)]
        outcome = run_case(bytes_mutation(RAW[name], rng), tmp_path)
        check(outcome)
        endings.add(outcome.ending)
    assert {"ok", "check: error"} <= endings  # some survive, some are refused


@settings(max_examples=int(os.environ.get("GEOKIN_FUZZ_EXAMPLES", "60")), deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(source=st.sampled_from(sorted(RAW)), rng=st.randoms(use_true_random=False))
def test_a_mutated_script_loads_or_fails_cleanly(tmp_path, source, rng):
    raw = mutate(RAW[source], rng)
    check(run_case(raw, tmp_path))


def test_the_harness_tells_other_exceptions_apart(tmp_path, monkeypatch):
    raw = RAW["sixbar.toml"]

    def broken(*args, **kwargs):
        raise TypeError("a fault")

    monkeypatch.setattr("geokin.sweep", broken)
    outcome = run_case(raw, tmp_path)
    assert outcome.unexpected and outcome.ending == "TypeError at sweep"
    assert outcome.where.startswith("test_fuzz.py") or outcome.where == "?"
    monkeypatch.undo()
    monkeypatch.setattr("geokin.cli._print_lines", lambda text, stream=None: print("\x1b[2J"))
    outcome = run_case(raw, tmp_path)
    assert outcome.unexpected and outcome.ending.startswith("check: status 0, ")
    assert outcome.ending.endswith("unescaped lines") and outcome.details[0] == "\x1b[2J"
