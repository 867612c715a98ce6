"""Benchmark writing a sweep's table as CSV against writing it as NPZ, in the same run.

Run with ``python tests/benchmark_export.py [SAMPLES]``. It sweeps the seed
six-bar (``constructions/sixbar.toml``) over 1,000,000 samples of its range
(or SAMPLES), makes the table ``geokin trace`` writes (every point, the
input in degrees), and prints the CPU time of writing it to a file as NPZ,
as CSV and as JSON (:func:`geokin.io.export_sweep`; minimum over rounds
taken in turn), the CSV-to-NPZ ratio, and the time of each whole command
``geokin trace constructions/sixbar.toml --samples SAMPLES -o FILE`` (CPU
time of the child process, minimum over rounds in turn). The test suite
does not run it: figures here are measured, never asserted.
"""

import gc
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import geokin
from geokin.io import columns, export_sweep

ROOT = Path(__file__).resolve().parents[1]
SIXBAR = ROOT / "constructions" / "sixbar.toml"


def interleaved(candidates, rounds):
    """Return each candidate's least CPU time, over rounds run in turn (A B A B ...)."""
    best = dict.fromkeys(candidates, float("inf"))
    for _ in range(rounds):
        for name, function in candidates.items():
            gc.collect()
            best[name] = min(best[name], function())
    return best


def cpu(function):
    """Return a function that calls ``function`` and gives the CPU seconds it took."""
    def timed():
        start = time.process_time()
        function()
        return time.process_time() - start
    return timed


def command(path, samples):
    """Return a function that runs ``geokin trace`` to ``path`` and gives its CPU seconds."""
    def timed():
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run([sys.executable, "-m", "geokin", "trace", str(SIXBAR), "--samples",
                        str(samples), "-o", str(path)], check=True, stderr=subprocess.DEVNULL)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return timed


def main():
    samples = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    construction = geokin.load(SIXBAR)
    start, stop = construction.inputs["theta"].range
    degrees = np.linspace(np.degrees(start), np.degrees(stop), samples)
    s = geokin.sweep(construction, np.radians(degrees))
    table = columns(s, inputs={"theta": degrees})
    folder = Path(tempfile.mkdtemp())
    paths = {kind: folder / f"sixbar.{kind}" for kind in ("npz", "csv", "json")}
    print(f"the seed six-bar, {samples:,} samples, {len(table)} columns "
          f"({sum(np.unique(c).size > 1 for c in table.values())} of them not constant)")
    writes = interleaved({kind: cpu(lambda p=path: export_sweep(table, p))
                          for kind, path in paths.items()}, rounds=3)
    sizes = {kind: os.path.getsize(path) / 1e6 for kind, path in paths.items()}
    print("writing the table, CPU seconds (best of 3 in turn):")
    for kind, seconds in writes.items():
        print(f"  {kind:5} {seconds:6.2f} s  {sizes[kind]:6.0f} MB")
    print(f"  CSV / NPZ = {writes['csv'] / writes['npz']:.1f}")
    whole = interleaved({kind: command(paths[kind], samples) for kind in ("npz", "csv")},
                        rounds=3)
    print(f"geokin trace constructions/sixbar.toml --samples {samples} -o FILE, CPU seconds "
          "(best of 3 in turn):")
    for kind, seconds in whole.items():
        print(f"  {kind:5} {seconds:6.2f} s")
    print(f"  CSV / NPZ = {whole['csv'] / whole['npz']:.1f}")
    for path in paths.values():
        path.unlink()
    folder.rmdir()


if __name__ == "__main__":
    main()
