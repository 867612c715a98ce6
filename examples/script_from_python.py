"""Write a construction built in Python as a construction script, and read it back.

The Python API works in radians; a script works in degrees. geokin.dump
writes the equivalent script (angle inputs and angle fields in degrees),
and geokin.loads reads it back to a construction that moves the same way.

Run: python examples/script_from_python.py
"""

import numpy as np

import geokin

c = geokin.Construction("crank-rocker", units="mm")
c.parameter("r2", 10)
c.input("theta", range=(0, 2 * np.pi), samples=73)
c.fixed("O2", 0, 0)
c.fixed("O4", 40, 0)
c.polar("A", "O2", "r2", "theta")
c.circle_circle("B", ("A", "O4"), (35, 30), branch="left")
c.polar("P", "A", 20, np.radians(30), reference=("A", "B"))
c.link("crank", "O2", "A")
c.link("coupler", "A", "B", "P")
c.link("rocker", "O4", "B")
c.trace("P")

text = geokin.dump(c)
print(text)
again = geokin.loads(text)
difference = np.nanmax(np.abs(geokin.sweep(again)["P"] - geokin.sweep(c)["P"]))
print(f"largest difference of P between the two: {difference:.1e} mm")
