"""The front door of :func:`vhfit.calibrate`: every argument checked before any computation."""

from __future__ import annotations

import math
import numbers
import os
from typing import Any

from vhfit.formulations import get_formulation

__all__ = ["check_arguments", "DEFAULT_TOL"]

DEFAULT_TOL = 1e-6


def _fail(name: str, value: Any, fix: str) -> None:
    raise ValueError(f"{name} = {value!r}: {fix}")


def _is_int(v: Any) -> bool:
    return isinstance(v, numbers.Integral) and not isinstance(v, bool)


def _is_real(v: Any) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)


def _int(a: dict, name: str, low: int, *, optional: bool = False) -> None:
    v = a[name]
    if optional and v is None:
        return
    if not _is_int(v) or v < low:
        _fail(name, v, f"give a whole number >= {low}" + (" or None" if optional else ""))


def _real(a: dict, name: str, low: float, high: float = math.inf, *, open_low=False,
          open_high=False, optional: bool = False) -> None:
    v = a[name]
    if optional and v is None:
        return
    ok = _is_real(v) and (v > low if open_low else v >= low) and (
        v < high if open_high else v <= high)
    if not ok:
        lo = f"> {low:g}" if open_low else f">= {low:g}"
        hi = "" if high == math.inf else (f" and < {high:g}" if open_high else f" and <= {high:g}")
        _fail(name, v, f"give a finite number {lo}{hi}" + (" or None" if optional else ""))


def _flag(a: dict, name: str) -> None:
    if not isinstance(a[name], (bool, int)) or a[name] not in (0, 1):
        _fail(name, a[name], "give True or False")


def _choices(a: dict) -> None:
    from vhfit.calibration._space import SPACES
    from vhfit.optimize import tau_strategies

    get_formulation(a["formulation"])  # its own one-line error
    if a["method"] not in SPACES:
        _fail("method", a["method"], "choose 'separable' or 'full'")
    n = a["n_prony"]
    if not (n is None or (n == "auto" if isinstance(n, str) else _is_int(n) and n >= 0)):
        _fail("n_prony", n, "give a whole number >= 0, 'auto', or None (the default)")
    ts = a["tau_strategy"]
    if not callable(ts) and ts not in tau_strategies():
        _fail("tau_strategy", ts, f"choose one of {sorted(tau_strategies())} or give a callable")
    if not (a["bounds"] == "auto" if isinstance(a["bounds"], str) else
            isinstance(a["bounds"], dict)):
        _fail("bounds", a["bounds"], "give 'auto' or a dict name -> (low, high)")
    w = a["workers"]
    if not (callable(w) or (_is_int(w) and (w >= 1 or w == -1))):
        _fail("workers", w, "give -1, a whole number >= 1, or a map-like callable")
    if a["callback"] is not None and not callable(a["callback"]):
        _fail("callback", a["callback"], "give a callable f(state_dict) or None")
    if a["de_options"] is not None and not isinstance(a["de_options"], dict):
        _fail("de_options", a["de_options"], "give a dict of solver keywords or None")
    ck = a["checkpoint"]
    if ck is not None and not isinstance(ck, (str, os.PathLike)):
        _fail("checkpoint", ck, "give a file path or None")
    if a["resume"] and ck is None:
        _fail("resume", a["resume"], "resuming needs checkpoint=PATH (the file to resume from)")


def _pairs(a: dict) -> None:
    stall = a["stall"]
    if not (isinstance(stall, (tuple, list)) and len(stall) == 2 and _is_real(stall[0])
            and stall[0] >= 0 and _is_int(stall[1]) and stall[1] >= 1):
        _fail("stall", stall, "give (fraction >= 0, generations >= 1), e.g. (0.02, 2000)")
    sr = a["stability_range"]
    if sr is not None and not (isinstance(sr, (tuple, list)) and len(sr) == 2
                               and all(_is_real(v) for v in sr) and 0 < sr[0] < 1 < sr[1]):
        _fail("stability_range", sr,
              "give (low, high) stretches with 0 < low < 1 < high, or None (the data's range)")
    t = a["target"]
    if isinstance(t, bool) or not isinstance(t, numbers.Real) or math.isnan(t):
        _fail("target", t, "give a number (the objective value that ends the search)")


def _shift(a: dict) -> None:
    """``shift_factors`` (a law, a dict {T: log10 a_T} or a pair) and ``T_ref``."""
    T_ref, sf = a["T_ref"], a["shift_factors"]
    if T_ref is not None and not _is_real(T_ref):
        _fail("T_ref", T_ref, "give the reference temperature as a finite number, or None")
    if sf is None:
        return
    fix = ("give a law (vhfit.tts.WLF(C1, C2, T_ref), ...), a dict {temperature: log10 a_T} "
           "or a pair (temperatures, log10 a_T)")
    if hasattr(sf, "log_aT"):
        law_T = getattr(sf, "T_ref", None)
        if T_ref is not None and law_T is not None and abs(float(law_T) - T_ref) > 1e-12:
            _fail("T_ref", T_ref, f"the shift law is referred to T_ref = {law_T!r}: drop "
                  "T_ref or give a law at it")
        return
    if isinstance(sf, dict):
        pairs = list(sf.items())
    elif isinstance(sf, (tuple, list)) and len(sf) == 2:
        try:
            tt, ll = (list(map(float, v)) for v in sf)
        except (TypeError, ValueError):
            _fail("shift_factors", sf, fix)
        if len(tt) != len(ll):
            _fail("shift_factors", sf, f"{len(tt)} temperatures and {len(ll)} log10 a_T: "
                  "give one log10 a_T per temperature")
        pairs = list(zip(tt, ll))
    else:
        _fail("shift_factors", sf, fix)
    if not pairs or not all(_is_real(T) and _is_real(L) for T, L in pairs):
        _fail("shift_factors", sf, "give at least one temperature, each with a finite "
              "log10 a_T")


def check_arguments(a: dict) -> None:
    """Raise a one-line ValueError naming the first bad argument of ``calibrate`` and the fix."""
    _choices(a)
    _pairs(a)
    _shift(a)
    _int(a, "max_prony", 1)
    _int(a, "popsize", 5, optional=True)
    _int(a, "maxiter", 1, optional=True)
    _real(a, "tol", 0.0)
    _real(a, "g_inf_min", 0.0, 1.0, open_high=True)
    _real(a, "max_time", 0.0, optional=True)
    _real(a, "order_tol", 0.0)
    _real(a, "prune_tol", 0.0)
    _real(a, "decades_below", 0.0)
    _real(a, "decades_above", 0.0)
    _real(a, "rtol", 0.0, 1.0, open_low=True, open_high=True)
    _real(a, "checkpoint_every", 0.0)
    for name in ("polish", "uncertainty", "resume", "check_rates"):
        _flag(a, name)
