"""Benchmark loading many names: declaring, compiling and reading scripts.

Run with ``python tests/benchmark_loading.py``; it prints the CPU time to
build 40,000 parameters and 20,000 points (compile included), in Python and
through :func:`geokin.io.loads` of a generated script, with tomllib's own
share, and the same at half and a quarter of the size: a linear load takes
twice the time for twice the names. The test suite does not run it: figures
here are measured, never asserted.
"""

import time
import tomllib

from geokin import Construction
from geokin.io import loads


def best_time(function, repeat=3):
    """Return the least CPU time of ``repeat`` calls, in seconds."""
    best = float("inf")
    for _ in range(repeat):
        start = time.process_time()
        function()
        best = min(best, time.process_time() - start)
    return best


def parameters(n):
    """Declare n parameters and one point, and compile."""
    c = Construction("parameters")
    for k in range(n):
        c.parameter(f"p{k}", k)
    c.fixed("O", 0, 0)
    c.compile()


def points(n):
    """Declare a chain of n points, each built on the one before, and compile."""
    c = Construction("points")
    c.input("t")
    c.fixed("O", 0, 0)
    for k in range(n):
        c.polar(f"P{k}", f"P{k - 1}" if k else "O", 1, "t")
    c.compile()


def parameters_script(n):
    return ("[parameters]\n" + "".join(f"p{k} = {k}\n" for k in range(n))
            + '[points]\nO = { op = "fixed", at = [0, 0] }\n')


def points_script(n):
    lines = ["[inputs.t]", "range = [0, 360]", "[points]", 'O = { op = "fixed", at = [0, 0] }']
    lines += [f'P{k} = {{ op = "polar", origin = "{f"P{k - 1}" if k else "O"}", '
              f'distance = 1, angle = "t" }}' for k in range(n)]
    return "\n".join(lines) + "\n"


def main():
    print("loading many names, CPU seconds (best of 3)")
    print(f"{'what':>30} {'n':>7} {'Python':>8} {'io.loads':>9} {'tomllib':>8}")
    for name, build, script, full in (("parameters", parameters, parameters_script, 40_000),
                                      ("points (compile included)", points, points_script,
                                       20_000)):
        for n in (full // 4, full // 2, full):
            text = script(n)
            api = best_time(lambda n=n, build=build: build(n))
            read = best_time(lambda text=text: loads(text))
            toml = best_time(lambda text=text: tomllib.loads(text))
            print(f"{name:>30} {n:>7,} {api:>8.3f} {read:>9.3f} {toml:>8.3f}")


if __name__ == "__main__":
    main()
