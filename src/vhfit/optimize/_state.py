"""Exact conversion between solver state (numpy arrays, floats, dicts) and plain JSON types.

:func:`to_plain` turns a nested structure of dicts (string keys), lists, tuples, numpy
arrays and scalars, ints, floats, strings, bools and None into lists, dicts, ints,
finite floats, strings, bools and None only, so that ``json.dumps(..., allow_nan=False)``
works; :func:`from_plain` inverts it exactly (dtype, shape and every bit of every
finite float; non-finite floats come back as ±inf or NaN). Python's JSON writes a
float with the shortest repr that reads back to the same double, so the round trip
through text is exact too.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["to_plain", "from_plain", "plain_column"]

_ARRAY = "__ndarray__"
_FLOAT = "__float__"
_TUPLE = "__tuple__"
_NONFINITE = {"inf": math.inf, "-inf": -math.inf, "nan": math.nan}


def _float_word(v: float) -> str:
    return "nan" if v != v else ("inf" if v > 0 else "-inf")


def _array(a: np.ndarray, scalar: bool = False) -> dict:
    if a.dtype.kind not in "biuf":
        raise TypeError(f"arrays of dtype {a.dtype} cannot be stored")
    data = a.ravel().tolist()
    if a.dtype.kind == "f" and not np.isfinite(a).all():
        data = [v if math.isfinite(v) else _float_word(v) for v in data]
    out = {_ARRAY: a.dtype.name, "shape": list(a.shape), "data": data}
    if scalar:
        out["scalar"] = True
    return out


def plain_column(values: list, dtype: str) -> dict:
    """A list of Python floats or ints as :func:`to_plain` stores a 1-D array of `dtype`.

    As ``to_plain(np.asarray(values, dtype))``, without the round trip through numpy:
    long per-generation histories are stored at every checkpoint.
    """
    data = list(values)
    if dtype.startswith("float") and not math.isfinite(sum(data)):  # inf or nan somewhere
        data = [v if math.isfinite(v) else _float_word(v) for v in data]
    return {_ARRAY: dtype, "shape": [len(data)], "data": data}


def to_plain(obj: Any) -> Any:
    """`obj` as plain JSON types; TypeError for anything that cannot be stored exactly."""
    if obj is None or isinstance(obj, (bool, str)):
        return obj
    if isinstance(obj, np.ndarray):
        return _array(obj)
    if isinstance(obj, np.generic):
        return _array(np.asarray(obj), scalar=True)
    if isinstance(obj, int):
        return int(obj)
    if isinstance(obj, float):
        return float(obj) if math.isfinite(obj) else {_FLOAT: _float_word(obj)}
    if isinstance(obj, dict):
        if not all(isinstance(k, str) for k in obj):
            raise TypeError("dict keys must be strings")
        return {k: to_plain(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [to_plain(v) for v in obj]
    if isinstance(obj, tuple):
        return {_TUPLE: [to_plain(v) for v in obj]}
    raise TypeError(f"a {type(obj).__name__} cannot be stored")


def from_plain(obj: Any) -> Any:
    """Invert :func:`to_plain`."""
    if isinstance(obj, list):
        return [from_plain(v) for v in obj]
    if not isinstance(obj, dict):
        return obj
    if _ARRAY in obj:
        dtype = np.dtype(obj[_ARRAY])
        data = obj["data"]
        if dtype.kind == "f":
            data = [_NONFINITE[v] if isinstance(v, str) else v for v in data]
        a = np.array(data, dtype=dtype).reshape(obj["shape"])
        return a[()] if obj.get("scalar") else a
    if _FLOAT in obj:
        return _NONFINITE[obj[_FLOAT]]
    if _TUPLE in obj:
        return tuple(from_plain(v) for v in obj[_TUPLE])
    return {k: from_plain(v) for k, v in obj.items()}
