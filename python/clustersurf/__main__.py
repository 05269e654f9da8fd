"""`python -m clustersurf ARGS`: the command-line tool, as the `clustersurf` command."""

import sys

from ._cli import main

sys.exit(main())
