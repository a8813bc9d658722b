"""``python -m kinetic_fem``: the same as the ``kinetic-fem`` command."""

import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())
