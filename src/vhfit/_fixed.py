"""What a law derives from stretch arrays that cannot change, remembered by identity.

A calibration evaluates its law on the same stretch arrays for every population (a
batch's samples, the stability grid); what depends on the stretches alone (the lateral
stretches of uniaxial tension, the Ogden kernel's logarithms and plan) is computed once
for them. Only arrays that cannot change qualify: read-only, owning their data or views
of read-only data; any other array gets a fresh computation every time.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["cannot_change", "remembered"]

#: (kind, ids of the arrays) -> (the arrays, the value); the arrays are held so that
#: their ids stay theirs
_MEMO: dict = {}
#: Entries kept before the memo starts over (a few per calibration)
_MAX = 128


def cannot_change(a: np.ndarray) -> bool:
    """Whether ``a`` is read-only and so is the data it views."""
    return not a.flags.writeable and (a.base is None or not a.base.flags.writeable)


def remembered(kind: str, arrays: tuple, compute: Callable[[], Any]) -> Any:
    """``compute()``, remembered for ``arrays`` by identity when none of them can change.

    Examples
    --------
    >>> x = np.array([1.0, 1.5, 2.0])
    >>> x.flags.writeable = False
    >>> calls = []
    >>> f = lambda: calls.append(1) or float(x.sum())
    >>> remembered("sum", (x,), f), remembered("sum", (x,), f), len(calls)
    (4.5, 4.5, 1)
    """
    if not all(cannot_change(a) for a in arrays):
        return compute()
    key = (kind, *map(id, arrays))
    hit = _MEMO.get(key)
    if hit is not None and all(a is b for a, b in zip(hit[0], arrays)):
        return hit[1]
    value = compute()
    if len(_MEMO) >= _MAX:
        _MEMO.clear()
    _MEMO[key] = (tuple(arrays), value)
    return value
