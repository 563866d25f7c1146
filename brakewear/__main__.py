"""``python -m brakewear``: the ``brakewear`` command line (:mod:`brakewear.cli`)."""
import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())
