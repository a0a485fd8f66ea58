"""The results file as every command reads it: :meth:`Calibration.load`, one-line errors."""

from __future__ import annotations

from vhfit.calibration import Calibration
from vhfit.cli._common import UsageError, one_line
from vhfit.cli._plugins import load_plugins

__all__ = ["load_calibration"]

_HINT = "give the results.json written by 'vhfit fit' or 'vhfit demo'"


def _number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _window(v) -> bool:
    return v is None or (isinstance(v, list) and len(v) == 2
                         and all(x is None or _number(x) for x in v))


#: The entries of a results file's context that the commands read: entry -> (what it
#: must be, check). Absent or null entries are allowed (older files lack some).
_ENTRIES = {
    "card_fits": ("a mapping of card to formulation", lambda v: isinstance(v, dict) and all(
        isinstance(f, str) for f in v.values())),
    "cards": ("a mapping of card to file name", lambda v: isinstance(v, dict) and all(
        isinstance(f, str) for f in v.values())),
    "inputs": ("a list of input files", lambda v: isinstance(v, list) and all(
        isinstance(i, dict) and isinstance(i.get("path", ""), str) for i in v)),
    "shift": ("a shift law and table", lambda v: isinstance(v, dict)
              and all(isinstance(v.get(k) or [], list) and all(map(_number, v.get(k) or []))
                      for k in ("temperatures", "log_aT"))
              and (v.get("T_ref") is None or _number(v["T_ref"]))
              and isinstance(v.get("constants") or {}, dict)),
    "cli_options": ("the fit's options", lambda v: isinstance(v, dict)
                    and all(isinstance(v.get(k) or [], list) for k in (
                        "rate", "deformation", "trim_strain", "trim_time"))
                    and all(map(_number, v.get("rate") or []))
                    and all(isinstance(d, str) for d in v.get("deformation") or [])
                    and all(map(_window, (v.get("trim_strain") or []) +
                                (v.get("trim_time") or [])))
                    and (v.get("points") is None or isinstance(v["points"], int))
                    and (v.get("measure") is None or isinstance(v["measure"], str))),
}


def _check_context(path: str, cal: Calibration) -> Calibration:
    """The calibration, once every context entry the commands read has its type."""
    for key, (want, ok) in _ENTRIES.items():
        value = cal.context.get(key)
        if value is not None and not ok(value):
            raise UsageError(f"{path}: entry {key!r} is not {want}: the file is damaged or "
                             f"of another program; {_HINT}, or rerun the fit")
    return cal


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
        return _check_context(path, Calibration.load(path))
    except OSError as exc:
        raise UsageError(f"{path}: cannot read ({exc.strerror}); {_HINT}") from None
    except ValueError:
        pass
    load_plugins()  # a plug-in may register the law or the formulation the file names
    try:
        return _check_context(path, Calibration.load(path))
    except ValueError as exc:
        raise UsageError(one_line(exc)) from None
