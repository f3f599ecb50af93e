"""python -m gi: the same as the `gi` command."""
import sys

from .cli import main

sys.exit(main())
