"""Error reporting for test data: :class:`DataError`, :class:`DataWarning` and the places
they name.

``_Where`` formats "curve 'x' (file.csv, line 17, column 'stress')" for messages and checks
arrays; ``_Subset`` and ``_Labels`` are lazy row labels; ``_norm_measure`` and ``_norm_mode``
read the stress measure and loading mode. The bottom of the data package: every other
module of it may import this one, and it imports none of them. The public names are
re-exported by :mod:`vhfit.data`.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np

from vhfit._words import Worded, setting

_MEASURES = {
    "engineering": "engineering",
    "eng": "engineering",
    "nominal": "engineering",
    "nom": "engineering",
    "piola": "engineering",
    "first_piola": "engineering",
    "pk1": "engineering",
    "true": "true",
    "cauchy": "true",
}
_MODES = {
    "compression": "compression",
    "c": "compression",
    "tension": "tension",
    "t": "tension",
    "mixed": "mixed",
    "tension_compression": "mixed",
    "cyclic": "mixed",
}


class DataError(Worded, ValueError):
    """Unusable test data; the message names the file, curve, row or column, and the fix."""


class DataWarning(Worded, UserWarning):
    """Something about the data was inferred rather than declared; the message says what."""


class _Where:
    """Formats "curve 'x' (file.csv, line 17, column 'stress')" for messages."""

    def __init__(self, name: str, source: str | None, rows: Sequence[Any] | None):
        self.name = name
        self.source = source
        self.rows = rows

    def label(self, k: int) -> str:
        if self.rows is None:
            return f"row {k}"
        r = self.rows[k]
        return r if isinstance(r, str) else f"row {r}"

    def __call__(self, k: int | None = None, column: str | None = None) -> str:
        parts = [self.source] if self.source else []
        if k is not None:
            parts.append(self.label(int(k)))
        if column:
            parts.append(f"column {column!r}")
        loc = ", ".join(parts)
        return f"curve {self.name!r}" + (f" ({loc})" if loc else "")

    def array(self, what: str, values: Any, n: int | None = None) -> np.ndarray:
        try:
            complex_ = np.iscomplexobj(values)
        except (TypeError, ValueError):
            complex_ = False
        if complex_:  # numpy would drop the imaginary part with only a warning
            raise DataError(f"{self()}: {what} holds complex numbers: give real values")
        try:
            arr = np.asarray(values, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise DataError(
                f"{self()}: {what} must be numbers ({exc}): fix the {what} data"
            ) from None
        if arr.ndim == 0:
            arr = arr.reshape(1)
        if arr.ndim != 1:
            raise DataError(
                f"{self()}: {what} must be 1-D, got shape {arr.shape}: pass one value per sample"
            )
        if n is not None and arr.size != n:
            raise DataError(
                f"{self()}: {what} has {arr.size} values but strain has {n}: give one per sample"
            )
        bad = ~np.isfinite(arr)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise DataError(
                f"{self(k)}: {what} = {arr[k]:g} is not finite: repair or delete that row"
            )
        return arr


class _Subset:
    """The labels ``rows[keep[k]]``, without building a list of them."""

    def __init__(self, rows: Sequence[Any], keep: np.ndarray):
        self.rows, self.keep = rows, keep

    def __len__(self) -> int:
        return len(self.keep)

    def __getitem__(self, k: int) -> Any:
        return self.rows[int(self.keep[k])]


class _Labels:
    """Lazy row labels ``"line 17"`` (files) or ``"row 3"`` (arrays)."""

    def __init__(self, numbers: Any, word: str):
        self.numbers = np.asarray(numbers, dtype=np.int64)
        self.word = word

    def __len__(self) -> int:
        return int(self.numbers.size)

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, (slice, np.ndarray, list)):
            return _Labels(self.numbers[i], self.word)
        return f"{self.word} {int(self.numbers[i])}"


def _warn(msg: str, stacklevel: int = 4) -> None:
    """Issue a DataWarning; ``stacklevel`` as for :func:`warnings.warn` called here."""
    warnings.warn(msg, DataWarning, stacklevel=stacklevel)


def _norm_key(s: Any) -> str:
    return re.sub(r"[\s\-]+", "_", str(s).strip().lower())


def _norm_measure(measure: Any, where: _Where) -> str:
    m = _MEASURES.get(_norm_key(measure))
    if m is None:
        raise DataError(
            f"{where()}: {setting(f'measure={measure!r}', f'--measure {measure}')} is not "
            "understood: use 'engineering' (nominal) or 'true' (Cauchy)"
        )
    return m


def _norm_mode(mode: Any, where: _Where) -> str:
    m = _MODES.get(_norm_key(mode))
    if m is None:
        raise DataError(
            f"{where()}: {setting(f'mode={mode!r}', f'the loading mode {mode!r}')} is not "
            "understood: use 'compression', 'tension' or 'mixed'"
        )
    return m


def _short(name: str, width: int = 40) -> str:
    """repr of a column name for a message, cut to ``width`` characters."""
    r = repr(name)
    return r if len(r) <= width else r[: width - 4] + "...'"
