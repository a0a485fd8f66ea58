"""Readers: test curves from CSV files and in-memory tables, and loading histories.

:func:`read_csv` (one file per curve, or one long file with a rate or test column),
:func:`curves_from_arrays` (numpy arrays, anything with ``__array__``, DataFrame-like
objects with ``.to_numpy()`` and ``.columns``, or a mapping of column name to values),
and :func:`read_history` (a ``(time, strain)`` loading history to simulate). They build
on the table layer and the curve; nothing in the package imports them.
"""

from __future__ import annotations

import csv
import os
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from vhfit._words import setting
from vhfit.data._ambiguous import ROUNDINGS, _cells
from vhfit.data._columns import _classify, _unit_factor
from vhfit.data._curve import Curve, _curves_from_table
from vhfit.data._errors import DataError
from vhfit.data._moduli import FrequencySweep, Relaxation
from vhfit.data._moduli_table import _moduli_items, _moduli_plan
from vhfit.data._points import DEFAULT_N_POINTS
from vhfit.data._table import _read_table, _table_from_data
from vhfit.history import from_rest

__all__ = ["curves_from_arrays", "read_csv", "read_history"]


def read_csv(
    path_or_paths: Any,
    *,
    rate: float | Sequence[float | None] | None = None,
    measure: str | None = None,
    mode: str | None = None,
    compression_positive: bool | None = None,
    columns: Mapping[str, Any] | None = None,
    units: Mapping[str, str] | None = None,
    names: Sequence[str] | None = None,
    group_by: str | Sequence[str] | None = None,
    select: Mapping[str, Any] | None = None,
    sort: bool = False,
    n_points: int | str | None = DEFAULT_N_POINTS,
    by: str | None = None,
    encoding: str | None = None,
    deformation: str | Sequence[str | None] | None = None,
) -> list[Curve | FrequencySweep | Relaxation]:
    """Read test curves from CSV files.

    One file per curve (columns such as ``strain``, ``stress_MPa``, optional ``time_s``
    and ``strain_rate``), or one long file with a rate column (one curve per distinct
    rate), a ``test``/``curve``/``specimen``/``name`` column or a deformation column
    (one curve per test named in it). A file with neither a rate nor a time gives
    equilibrium curves (the long-term response, samples in any order).

    Parameters
    ----------
    path_or_paths : path, file-like, or a sequence of them
        The file(s). Curves come back in file order, then in order of appearance.
    rate : float or sequence of float, optional
        Engineering strain rate in 1/s (one for all files, or one per file). Beats the
        file's rate column and its ``# strain_rate:`` line.
    measure : {"engineering", "true"}, optional
        Stress measure of the file when the header does not say (``true_stress``,
        ``nominal_stress``, ``cauchy_stress`` do); default engineering. When both an
        engineering and a true stress column exist, picks that column.
    mode : {"compression", "tension", "mixed"}, optional
        Declared loading mode (a contradiction by the data's signs is an error).
    compression_positive : bool, optional
        The file gives compression as positive numbers: negate strain and stress.
    columns : mapping, optional
        Role -> header name (or 0-based index) for ``"strain"``, ``"stretch"``,
        ``"stress"``, ``"time"``, ``"rate"``, overriding recognition; ``None`` ignores a
        role (e.g. ``{"time": None}`` to treat a test as constant-rate);
        ``"ignore"`` -> a header or a list of them ignores those columns. Several columns
        that could hold one role are compared by value: agreeing within twice their
        written rounding, the finest is read; disagreeing, an error says to choose here.
    units : mapping, optional
        Role -> unit, where the header has none or a wrong one, e.g. ``{"stress": "kPa"}``;
        an unknown role is an error.
    names : sequence of str, optional
        Column names for files without a header row (or to replace the header).
    group_by : str or sequence of str, optional
        Column(s) whose values tell the curves of a long file apart. A text column that
        varies inside one curve without it (nor ``select=``, nor ``"ignore"``) is an error.
    select : mapping, optional
        Keep only rows whose column equals a value (or one of a list; text is compared
        case-insensitively, numbers by value), e.g.
        ``{"mode": "uniaxial_tension_compression"}``; a value that is not there is an
        error listing those present.
    sort : bool, default False
        Sort each curve's rows by time (or by |strain| without time) instead of
        rejecting rows out of order.
    n_points, by
        Objective points of each curve, as in :class:`Curve`.
    encoding : str, optional
        Text encoding; default: UTF-8 (with or without BOM), UTF-16 with BOM, else
        Latin-1.
    deformation : str or sequence of str, optional
        The test of the file's curves (one for all files, or one per file), as in
        :class:`Curve`; beats the file's ``# deformation:`` line. A deformation column
        (``deformation``, ``test_type``, ``mode`` holding test names) names each row's
        test instead. Undeclared: biaxial for a file with a second stretch column,
        simple shear for an amount-of-shear column (``gamma``, ``shear_strain``),
        uniaxial otherwise.

    Returns
    -------
    list of Curve, FrequencySweep and Relaxation
        A file of moduli (a frequency column with storage and loss moduli, or |E*| and
        tan δ; or a time column with a relaxation modulus) gives a
        :class:`FrequencySweep` or :class:`Relaxation` per temperature of its temperature
        column (one without; per value of ``group_by=`` too); ``columns=``, ``units=``,
        ``names=``, ``group_by=`` and ``select=`` apply to it, the options of
        stress–strain curves do not (docs/data.md).

    Raises
    ------
    DataError
        With the file, the line or column, and the fix.

    Notes
    -----
    *Headers* are matched case-insensitively, with units in brackets or as a suffix:
    ``stress_kPa``, ``stress [MPa]``, ``Stress (Pa)``, ``nominal_stress_MPa``,
    ``true_stress_MPa``, ``strain``, ``strain_%``, ``engineering_strain``,
    ``true_strain`` (logarithmic: converted), ``stretch``/``lambda``, ``time_s``,
    ``time_ms``, ``strain_rate``, ``rate_1/s``, ``nominal_strain_rate_per_s``; for other
    tests ``stretch2``/``lambda2``/``strain2`` (λ2 of a biaxial test), ``stress2`` or
    ``nominal_stress_2`` (the second stress), ``gamma``/``shear_strain`` (amount of shear),
    ``stretch_or_shear_amount`` (γ on simple-shear rows), and a deformation column. Other
    columns (force, displacement, text) are ignored. Stress units: Pa, kPa, MPa, GPa,
    N/mm², psi, ksi, kgf/cm², bar; no unit means MPa.

    *Format.* Separators ``,``, ``;``, tab, ``|`` or spaces (taken from the header
    line); a decimal comma is understood with ``;`` or tab separators; UTF-8/UTF-16
    BOMs are skipped; blank lines are skipped. Lines ``# key: value`` before the
    header set ``strain_rate`` (``-100`` or ``-100 1/s``), ``measure``, ``mode``,
    ``deformation``, ``name``, ``weight``, ``compression_positive`` and ``<role>_unit``;
    other ``#``
    lines are comments.

    *Curves.* A file with a time column gives a time-history curve; without one, a
    constant-rate curve if it has a rate (column, ``#`` line or ``rate=``), else an
    equilibrium curve (fully relaxed states; docs/modes.md). Rows
    at the same rate and strain with different stresses are an error (two tests
    mixed up). Separate files at the same rate are separate curves (replicates).

    Examples
    --------
    >>> import io
    >>> text = "# strain_rate: -100\\nstrain,stress_kPa\\n0,0\\n-0.1,-50\\n-0.2,-120\\n"
    >>> [c] = read_csv(io.StringIO(text), n_points=2)
    >>> c.strain_rate, c.target_stress
    (-100.0, array([-0.05, -0.12]))
    >>> long = "strain_rate,strain,stress\\n-1,-0.1,-1\\n-1,-0.2,-2\\n-10,-0.1,-3\\n-10,-0.2,-5\\n"
    >>> [c.name for c in read_csv(io.StringIO(long))]
    ['<stream> [rate -1/s]', '<stream> [rate -10/s]']
    """
    if isinstance(path_or_paths, (str, os.PathLike)) or hasattr(path_or_paths, "read"):
        paths = [path_or_paths]
    else:
        paths = list(path_or_paths)
        if not paths:
            raise DataError("read_csv: no files given")
    _check_unit_roles(units)
    rates = _per_file(rate, "rates", len(paths), np.ndim(rate) == 0)
    tests = _per_file(deformation, "deformations", len(paths), isinstance(deformation, str))
    out: list[Curve | FrequencySweep | Relaxation] = []
    for p, r, dfm in zip(paths, rates, tests):
        table = _read_table(p, names, encoding)
        plan = _moduli_plan(table.names, columns, table.source)
        if plan is not None:
            out.extend(_moduli_items(table, plan, units, None, group_by, select))
            continue
        out.extend(_curves_from_table(
            table, rate=None if r is None else float(r), measure=measure, mode=mode,
            compression_positive=compression_positive, columns=columns, units=units,
            group_by=group_by, select=select, sort=sort, n_points=n_points, by=by, name=None,
            deformation=dfm,
        ))
    return out


#: The roles ``units=`` may name: of stress–strain curves, then of moduli tables.
_UNIT_ROLES = ("strain", "stretch", "stress", "time", "rate", "strain_rate", "strain2",
               "stretch2", "stress2", "frequency", "omega", "storage", "loss", "modulus",
               "relaxation")


def _check_unit_roles(units: Mapping[str, str] | None) -> None:
    """A ``units=`` role that no column can have is refused, not ignored."""
    for role in units or {}:
        if role not in _UNIT_ROLES:
            raise DataError(f"{setting(f'units={{{role!r}: ...}}', f'--units {role}=UNIT')}: "
                            f"unknown role; use {', '.join(_UNIT_ROLES)}")


def _per_file(value: Any, what: str, n: int, single: bool) -> list[Any]:
    """One value for all ``n`` files, or one per file."""
    if value is None or single:
        return [value] * n
    values = list(value)
    if len(values) != n:
        raise DataError(f"read_csv: {len(values)} {what} for {n} files: give one "
                        f"{what[:-1]}, or one per file")
    return values


def curves_from_arrays(
    data: Any,
    *,
    names: Sequence[str] | None = None,
    rate: float | None = None,
    measure: str | None = None,
    mode: str | None = None,
    compression_positive: bool | None = None,
    columns: Mapping[str, Any] | None = None,
    units: Mapping[str, str] | None = None,
    group_by: str | Sequence[str] | None = None,
    select: Mapping[str, Any] | None = None,
    sort: bool = False,
    n_points: int | str | None = DEFAULT_N_POINTS,
    by: str | None = None,
    name: str | None = None,
    source: str | None = None,
    deformation: str | None = None,
) -> list[Curve | FrequencySweep | Relaxation]:
    """Curves from a table in memory: the array counterpart of :func:`read_csv`.

    A table of moduli (named columns as in :func:`read_csv`) gives frequency sweeps or
    relaxation tests.

    Parameters
    ----------
    data : array_like, DataFrame-like or mapping
        A 2-D array (rows = samples; anything with ``__array__``), a structured array,
        an object with ``.to_numpy()`` and ``.columns`` (a pandas or polars DataFrame;
        pandas is not needed), or a mapping ``{column name: values}``.
    names : sequence of str, optional
        Column names (headers with units, as in a CSV file). An unnamed 2-column array
        is taken as ``["strain", "stress"]`` (MPa).
    name : str, optional
        Curve name (with the group appended when there are several).
    source : str, optional
        What to call the data in messages.
    rate, measure, mode, compression_positive, columns, units, group_by, select, sort, n_points, by
        As in :func:`read_csv`.
    deformation : str, optional
        The test of the curves, as in :func:`read_csv` (one for all).

    Examples
    --------
    >>> import numpy as np
    >>> eps = np.linspace(0, -0.3, 4)
    >>> table = np.column_stack([np.r_[eps, eps], np.r_[eps, 2 * eps],
    ...                          np.r_[[-1.0] * 4, [-100.0] * 4]])
    >>> cs = curves_from_arrays(table, names=["strain", "stress_MPa", "rate_1/s"], n_points=3)
    >>> [(c.strain_rate, float(c.target_stress[-1])) for c in cs]
    [(-1.0, -0.3), (-100.0, -0.6)]
    """
    _check_unit_roles(units)
    table = _table_from_data(data, names, source)
    plan = _moduli_plan(table.names, columns, table.source)
    if plan is not None:  # moduli: frequency sweeps or relaxation tests
        return _moduli_items(table, plan, units, name, group_by, select)
    return _curves_from_table(
        table, rate=rate, measure=measure, mode=mode,
        compression_positive=compression_positive, columns=columns, units=units,
        group_by=group_by, select=select, sort=sort, n_points=n_points, by=by, name=name,
        deformation=deformation,
    )


def read_history(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """Read a loading history: the (time, strain) columns of a CSV file, started from rest.

    The columns are the first whose header starts with ``time`` (or is ``t`` or ``t_s``)
    and the first whose header starts with ``strain`` (and is not a strain rate); a file
    whose first row is numbers has no header, and its first two columns are time and
    strain. Lines starting with ``#`` and blank lines are skipped; the file is read as
    UTF-8 (with or without BOM). Time is in s, strain is engineering strain (negative in
    compression), unless the header gives a unit (``time_ms``, ``t [min]``, ``strain_%``);
    another column that could be the time or the strain must agree with the one read to
    within twice their written rounding. The material is at rest before t = 0: a first
    sample at t > 0 is reached by a linear ramp from (0, 0)
    (:func:`vhfit.history.from_rest`).

    Parameters
    ----------
    path : str or path-like
        The CSV file.

    Returns
    -------
    time, strain : ndarray
        The history's samples, ready for :meth:`vhfit.History.piecewise_linear`.

    Raises
    ------
    DataError
        The file cannot be read, is empty, has no time and strain columns, has a row
        that is not two numbers, or fewer than 2 rows.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "ramp_hold.csv"
    >>> _ = p.write_text("time_s,strain\\n1,-0.2\\n5,-0.2\\n")
    >>> read_history(p)
    (array([0., 1., 5.]), array([ 0. , -0.2, -0.2]))
    """
    rows = _history_rows(path)
    it, ie, data = _history_columns(path, rows)
    try:
        arr = np.array([[float(r[it]), float(r[ie])] for r in data])
    except (ValueError, IndexError):
        for k, r in enumerate(data):
            try:
                float(r[it]), float(r[ie])
            except (ValueError, IndexError):
                line = k + (2 if data is not rows else 1)
                raise DataError(f"{path}: data row {line} {r} is not two numbers "
                                "(time, strain); fix or remove it") from None
        raise
    if arr.shape[0] < 2:
        raise DataError(f"{path}: needs at least 2 (time, strain) rows")
    if data is not rows:  # a header: its units, and no second time or strain column
        t_conv, e_conv = (_history_unit(path, rows[0], j, role)
                          for j, role in ((it, "time"), (ie, "strain")))
        _history_rivals(path, rows, it, "time", t_conv)
        _history_rivals(path, rows, ie, "strain", e_conv)
        arr[:, 0], arr[:, 1] = t_conv(arr[:, 0])[0], e_conv(arr[:, 1])[0]
    return from_rest(arr[:, 0], arr[:, 1])


def _history_unit(path: Any, head: list[str], j: int, role: str) -> Any:
    """Values of a history column -> s or engineering strain, from its header's unit."""
    col = _classify(j, head[j])
    unit = col.unit if col is not None else ""
    factor = _unit_factor(role, unit)
    if factor is None or (col is not None and col.ambiguous):
        raise DataError(f"{path}, column {head[j]!r}: unit {unit!r} is not understood for "
                        f"{role}: use {'s, ms, min or h' if role == 'time' else 'none or %'} "
                        f"(e.g. '{role}_{'s' if role == 'time' else '%'}')")
    if col is not None and col.kind == "log":
        return lambda v: (np.expm1(v * factor), np.exp(v * factor) * factor)
    return lambda v: (v * factor, np.full_like(v, factor))


def _history_rivals(path: Any, rows: list[list[str]], j: int, role: str, conv: Any) -> None:
    """Another column that could be the history's time (or strain) must agree with the one
    read to within twice their written rounding, or the file is refused."""
    head = rows[0]
    for k, h in enumerate(head):
        col = _classify(k, h)
        if k == j or col is None or col.role != role or col.rank >= 2.0:
            continue
        a, ra = _cells([r[j] if j < len(r) else "" for r in rows[1:]])
        b, rb = _cells([r[k] if k < len(r) else "" for r in rows[1:]])
        with np.errstate(over="ignore", invalid="ignore"):
            xa, da = conv(a)
            xb, db = _history_unit(path, head, k, role)(b)
        tol = ROUNDINGS * (np.abs(da) * ra + np.abs(db) * rb)
        bad = np.flatnonzero(np.abs(xa - xb) > tol + 1e-12 * np.nanmax(np.abs(xa)))
        if bad.size:
            i = int(bad[0])
            raise DataError(
                f"{path}, data row {i + 2}: columns {h!r} and {head[j]!r} could both be the "
                f"{role} but differ ({xb[i]:.6g} vs {xa[i]:.6g}{' s' if role == 'time' else ''})"
                f": the history reads {head[j]!r}; delete or rename the other"
            )


def _history_rows(path: str | os.PathLike[str]) -> list[list[str]]:
    """The non-blank, non-comment rows of a CSV file, as lists of cells."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            rows = [r for r in csv.reader(line for line in f if not line.lstrip().startswith("#"))
                    if any(c.strip() for c in r)]
    except OSError as exc:
        raise DataError(f"{path}: cannot read ({exc.strerror}); check the path") from None
    except UnicodeDecodeError as exc:
        raise DataError(f"{path}: is not UTF-8 text ({exc.reason}); save it as a UTF-8 CSV "
                        "file") from None
    if not rows:
        raise DataError(f"{path}: empty; give a CSV with time and strain columns")
    return rows


def _history_columns(
    path: str | os.PathLike[str], rows: list[list[str]]
) -> tuple[int, int, list[list[str]]]:
    """(time column, strain column, data rows): named ``time*``/``strain*``, else the first
    two columns of a file without a header."""
    try:
        [float(c) for c in rows[0]]
        return 0, 1, rows
    except ValueError:
        pass
    head = [c.strip().lower() for c in rows[0]]
    t_cols = [j for j, h in enumerate(head) if h.startswith("time") or h in ("t", "t_s")]
    e_cols = [j for j, h in enumerate(head) if h.startswith("strain") and "rate" not in h]
    if not t_cols or not e_cols:
        raise DataError(f"{path}: header {rows[0]} has no 'time' and 'strain' columns; "
                        "name them so (time in s, engineering strain)")
    return t_cols[0], e_cols[0], rows[1:]
