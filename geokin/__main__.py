"""``python -m geokin``: the ``geokin`` command, for where its script is not on PATH."""

import sys

from .cli import main

if __name__ == "__main__":  # pragma: no cover - run as a program, tested in a subprocess
    sys.exit(main())
