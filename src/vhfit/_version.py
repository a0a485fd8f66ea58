"""The package version, in one place (read by the package and by the results file), and
the versions of the packages it runs with."""

import sys

__version__ = "0.1.0"


def package_version(name: str) -> str:
    """The version of an installed package, without importing it when it is not loaded.

    A results file and a report record the versions of numpy, scipy, numba and
    matplotlib; a fit that did not need numba or matplotlib should not pay their import
    (a few tenths of a second) to write a version string. A loaded package answers with
    its ``__version__``; another with its installed distribution's metadata.

    Parameters
    ----------
    name : str
        The package's import name, which is also its distribution's name here
        (``"numba"``, ``"matplotlib"``, ``"scipy"``).

    Returns
    -------
    str
        Its version.

    Raises
    ------
    importlib.metadata.PackageNotFoundError
        The package is not installed.

    Examples
    --------
    >>> import numpy
    >>> package_version("numpy") == numpy.__version__
    True
    """
    module = sys.modules.get(name)
    version = getattr(module, "__version__", None)
    if isinstance(version, str):
        return version
    from importlib.metadata import version as installed_version

    return installed_version(name)
