"""``python -m brakewear.bench``: the benchmarks' command line (and their child processes)."""
import sys

from .cli import main

sys.exit(main())
