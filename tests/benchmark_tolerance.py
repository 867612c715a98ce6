"""Time a tolerance study of seed 004's four-bar, here and on a local cluster, and its memory.

Run ``python tests/benchmark_tolerance.py`` (not collected by pytest):

* ``time``: 100,000 variants x 361 samples (+-3 on every length, normal),
  wall and CPU time in process, then wall time with a local
  ``dask.distributed`` cluster of 2 worker processes (the cluster's start
  given apart), and whether both give the same figures;
* ``memory``: 1,000,000 variants x 360 samples in process, the peak of
  memory the study allocates (tracemalloc, which numpy reports to) and the
  process's peak resident size, against what the sweep of all variants at
  once would hold (about 90 bytes a sample).

``python tests/benchmark_tolerance.py time`` or ``memory`` runs one of them.
"""

import pathlib
import resource
import sys
import time
import tracemalloc

import numpy as np

import geokin

SCRIPT = pathlib.Path(__file__).resolve().parent.parent / "constructions" / "fourbar_open.toml"
TOLERANCES = dict.fromkeys("abcd", 3.0)


def timed(run):
    wall, cpu = time.perf_counter(), time.process_time()
    result = run()
    return result, time.perf_counter() - wall, time.process_time() - cpu


def bench_time(n: int = 100_000) -> None:
    c = geokin.load(SCRIPT).compile()
    geokin.tolerance(c, TOLERANCES, n=2000, seed=1)  # imports and plans made once
    here, wall, cpu = timed(lambda: geokin.tolerance(c, TOLERANCES, n=n, seed=4))
    print(f"in process: {n:,} variants x 361 samples: {wall:.2f} s wall, {cpu:.2f} s CPU; "
          f"{100 * here.assemblable_fraction:.2f}% assemble")
    from geokin.analysis.tolerance import local_cluster

    start = time.perf_counter()
    with local_cluster(2) as client:
        started = time.perf_counter() - start
        geokin.tolerance(c, TOLERANCES, n=2000, seed=1, client=client)  # workers warmed
        there, wall, _ = timed(lambda: geokin.tolerance(c, TOLERANCES, n=n, seed=4,
                                                        client=client))
    same = there.to_dict() == here.to_dict()
    print(f"2 workers: {wall:.2f} s wall (the cluster started in {started:.1f} s); "
          f"the same figures: {same}")


def bench_memory(n: int = 1_000_000, samples: int = 360) -> None:
    c = geokin.load(SCRIPT).compile()
    values = np.linspace(0, 2 * np.pi, samples)
    tracemalloc.start()
    result, wall, cpu = timed(lambda: geokin.tolerance(c, TOLERANCES, n=n, seed=4,
                                                       values=values))
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # KiB on Linux
    print(f"{n:,} variants x {samples} samples: {wall:.1f} s wall, {cpu:.1f} s CPU; "
          f"peak allocated {peak / 2**20:.0f} MiB (tracemalloc), peak resident {rss:.0f} MiB; "
          f"all at once would hold about {90 * n * samples / 2**30:.0f} GiB; "
          f"{100 * result.assemblable_fraction:.2f}% assemble")


if __name__ == "__main__":
    chosen = sys.argv[1:] or ["time", "memory"]
    if "time" in chosen:
        bench_time()
    if "memory" in chosen:
        bench_memory()
