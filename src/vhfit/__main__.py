"""``python -m vhfit``: the same command line as the ``vhfit`` console script."""

from vhfit.cli import program

if __name__ == "__main__":
    program()
