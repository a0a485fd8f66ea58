"""``python -m vhfit``: the same command line as the ``vhfit`` console script."""

import sys

from vhfit.cli import main

if __name__ == "__main__":
    sys.exit(main())
