"""The results file as every command reads it: :meth:`Calibration.load`, one-line errors."""

from __future__ import annotations

from vhfit.calibration import Calibration
from vhfit.cli._common import UsageError, one_line
from vhfit.cli._plugins import load_plugins

__all__ = ["load_calibration"]

_HINT = "give the results.json written by 'vhfit fit' or 'vhfit demo'"


def load_calibration(path: str) -> Calibration:
    """The calibration of a results file, with the model it defines (law, terms,
    formulation, accuracy, shift); a law or formulation it names that is not registered
    loads the plug-ins first. Bad files are a :class:`UsageError` (exit 2).

    Examples
    --------
    >>> load_calibration("no/such/results.json")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    vhfit.cli._common.UsageError: no/such/results.json: cannot read (No such file ...
    """
    try:
        return Calibration.load(path)
    except OSError as exc:
        raise UsageError(f"{path}: cannot read ({exc.strerror}); {_HINT}") from None
    except ValueError:
        pass
    load_plugins()  # a plug-in may register the law or the formulation the file names
    try:
        return Calibration.load(path)
    except ValueError as exc:
        raise UsageError(one_line(exc)) from None
