"""``python -m brakewear.bench``: the benchmarks' command line (and their child processes)."""
import sys

from .core import main

sys.exit(main())
