"""Table -> curves: which rows make which curve, and with what name, rate and options.

``_curve_specs`` reads a table's ``# key: value`` lines, resolves its columns, keeps the
selected rows, splits them into curves (a group column, ``group_by=``, or one curve per
nominal rate) and yields, curve by curve, the keyword arguments of
:class:`vhfit.data.Curve` in SI units. It never builds a curve itself, so that the curve
can use it (``Curve.from_array``) and the readers can build curves from it, without a
cycle.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from vhfit._words import setting
from vhfit.data._ambiguous import (
    _Cand,
    _cells,
    _check_text_columns,
    _col_index,
    _scaled,
    _select_rows,
    _settle,
)
from vhfit.data._columns import (
    _GROUP_NAMES,
    _UNITS,
    _classify,
    _Col,
    _norm_unit,
    _Plan,
    _resolve_columns,
    _split_header,
    _unit_factor,
)
from vhfit.data._errors import _MODES, DataError, _norm_key, _norm_measure, _warn, _Where
from vhfit.data._modes import _deformation_name, _implied_deformation, _is_shear, _known
from vhfit.data._points import DEFAULT_N_POINTS
from vhfit.data._table import _Table
from vhfit.modes import deformation_mentioned

_META_KEYS = {
    "strain_rate": "rate", "rate": "rate", "nominal_strain_rate": "rate",
    "engineering_strain_rate": "rate", "measure": "measure", "stress_measure": "measure",
    "mode": "mode", "loading_mode": "mode", "name": "name", "curve": "name",
    "weight": "weight", "compression_positive": "compression_positive",
    "deformation": "deformation", "deformation_mode": "deformation", "test_type": "deformation",
}


@dataclass
class _Options:
    """What holds for every curve of a table: its columns and its declared options."""

    plan: _Plan
    measure: str
    mode: str | None
    compression_positive: bool
    weight: float
    meta_rate: float | None
    deformation: str | None  # deformation= or the '# deformation:' line (raw text)
    known: dict[str, str]  # the recognised '# key: value' lines, by option
    meta: dict[str, str]  # all '# key: value' lines


@dataclass
class _Groups:
    """The rows of a table split into curves."""

    rows: np.ndarray  # the selected rows
    rate_vals: np.ndarray | None  # the rate column at those rows, in 1/s
    n_named: int  # how many of key_cols come from group columns (the rest: the rate)
    key_cols: list[np.ndarray]  # the texts that tell the curves apart, one per key
    by_rate: bool  # one curve per distinct rate of the rate column
    members: list[np.ndarray]  # positions in rows of each curve, in order of appearance


def _curve_specs(
    table: _Table,
    *,
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
    deformation: str | None = None,
) -> Iterator[dict[str, Any]]:
    """Keyword arguments of :class:`~vhfit.data.Curve` for each curve of ``table``, in order.

    A generator: a curve's data are checked only when it is asked for, so the errors come
    in the order of the curves (the caller builds each curve before asking for the next).
    Options as in :func:`vhfit.data.read_csv`.
    """
    opts = _table_options(table, measure, mode, compression_positive, columns, units,
                          deformation)
    grp = _split_rows(table, opts.plan, select, group_by, rate)
    stem = Path(table.source).stem if table.source and not table.source.startswith("<") else (
        table.source or "data")
    for g in grp.members:
        yield _group_spec(table, opts, grp, g, rate, name, stem, sort, n_points, by)


def _table_options(
    table: _Table,
    measure: str | None,
    mode: str | None,
    compression_positive: bool | None,
    columns: Mapping[str, Any] | None,
    units: Mapping[str, str] | None,
    deformation: str | None = None,
) -> _Options:
    """Columns and options of a table: the arguments, else its '# key: value' lines."""
    src = table.source
    meta = dict(table.meta)
    known = {_META_KEYS[k]: v for k, v in meta.items() if k in _META_KEYS}
    if ("mode" in known and _norm_key(known["mode"]) not in _MODES
            and _deformation_name(known["mode"])):  # '# mode: <a test>' names the test
        known.setdefault("deformation", known.pop("mode"))
    units = dict(units or {})
    for k, v in meta.items():
        if k.endswith("_unit") and k[:-5] in _UNITS and k[:-5] not in units:
            units[k[:-5]] = v
    if measure is None and "measure" in known:
        measure = known["measure"]
    meas = None if measure is None else _norm_measure(measure, _Where(src, None, None))
    try:
        plan = _resolve_columns(table.names, columns, units, meas, src)
    except DataError as exc:
        if not table.note:
            raise
        raise DataError(f"{exc}{table.note}") from None
    if meas is not None and plan.measure is not None and plan.measure != meas:
        raise DataError(
            f"{src}, column {plan.stress.header!r}: the header says {plan.measure} stress but "
            f"{setting(f'measure={meas!r}', f'--measure {meas}')} was given: drop "
            + setting("measure=", "--measure") + ", or name the right column with "
            + setting("columns={'stress': ...}", "--columns stress=NAME")
        )
    if mode is None and "mode" in known:
        mode = known["mode"]
    if compression_positive is None:
        compression_positive = (_meta_bool(known["compression_positive"], src,
                                           "compression_positive")
                                if "compression_positive" in known else False)
    try:
        weight = float(known["weight"]) if "weight" in known else 1.0
    except ValueError:
        raise DataError(f"{src}: '# weight: {known['weight']}' is not a number: write e.g. "
                        "'# weight: 2'") from None
    meta_rate = _meta_rate(known["rate"], src) if "rate" in known else None
    if deformation is None:
        deformation = known.get("deformation")
    _check_deformation_column(table, plan)
    if deformation is None and plan.deformation is None:
        deformation = _mentioned_deformation(table)
    _note_units(table, plan, units)
    return _Options(plan, meas or plan.measure or "engineering", mode, compression_positive,
                    weight, meta_rate, deformation, known, meta)


def _mentioned_deformation(table: _Table) -> str | None:
    """The test a table's comment lines or headers mention when nothing names it (e.g.
    ``# CONFINED compression in a steel cup``): only the words of a record's
    ``mentions``, so a test that no law here can represent is refused, never read as
    the default uniaxial."""
    return next(filter(None, map(deformation_mentioned, (*table.comments, *table.names))),
                None)


def _check_deformation_column(table: _Table, plan: _Plan) -> None:
    """Every value of the deformation column names a test; a 'mode' column whose values
    are not all test names (e.g. tension, compression) is no deformation column and is
    left alone, as any other column."""
    col = plan.deformation
    if col is None:
        return
    texts = table.texts(col.index)
    names = [_deformation_name(v) for v in texts]
    if _norm_key(col.header) == "mode" and not all(names):
        plan.deformation = None
        return
    bad = [k for k, n in enumerate(names) if n is None]
    if bad:
        k = bad[0]
        raise DataError(
            f"{table.source}, {table.label(k)}, column {col.header!r}: {texts[k]!r} is not a "
            f"test vhfit knows: use one of {_known()}"
        )


def _meta_rate(val: str, src: str) -> float:
    m = re.fullmatch(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*",
                     val.replace(",", "."))
    f = None if m is None else _unit_factor("rate", m.group(2))
    if m is None or f is None:
        raise DataError(f"{src}: '# strain_rate: {val}' is not a rate: write e.g. "
                        "'# strain_rate: -100' (1/s) or '# strain_rate: -6000 1/min'")
    return float(m.group(1)) * f


def _meta_bool(val: str, src: str, key: str) -> bool:
    v = val.strip().lower()
    if v in ("1", "true", "yes", "y", "on"):
        return True
    if v in ("0", "false", "no", "n", "off"):
        return False
    raise DataError(f"{src}: '# {key}: {val}': write true or false")


def _split_rows(
    table: _Table,
    plan: _Plan,
    select: Mapping[str, Any] | None,
    group_by: str | Sequence[str] | None,
    rate: float | None,
) -> _Groups:
    """The selected rows, split into curves by group columns and by nominal rate."""
    src = table.source
    rows = _select_rows(table, select)
    # columns compared with the one read (and found to agree) are no unused channels
    compared = {c.index for role, alts in plan.alternates.items()
                for c in [getattr(plan, role), *alts]}
    _settle_columns(table, plan, rows)
    rate_vals = None
    if plan.rate is not None:
        rate_vals = table.floats(
            plan.rate.index, rows,
            empty="the strain rate is missing: fill it in (1/s, negative in compression), or "
                  "ignore the column with " + setting("columns={'rate': None}", "--columns rate="),
        ) * plan.factors["rate"]
    gcols = _group_columns(table, group_by, rows)
    if plan.deformation is not None and plan.deformation.index not in gcols:
        j = plan.deformation.index
        if len({_deformation_name(v) for v in table.texts(j)[rows]}) > 1:
            gcols.append(j)  # each test its own curve
    key_cols = [table.texts(j)[rows] for j in gcols]
    by_rate = (rate_vals is not None and rate is None
               and plan.rate.index not in gcols and len(np.unique(rate_vals)) > 1)
    if by_rate:
        key_cols.append(_rate_key(table, plan, rows, rate_vals))
    if key_cols:
        combo = np.array(["\x1f".join(map(str, t)) for t in zip(*key_cols)], dtype=object)
        _, first, inv = np.unique(combo, return_index=True, return_inverse=True)
        order = np.argsort(first)
        members = [np.flatnonzero(inv == g) for g in order]
    else:
        members = [np.arange(rows.size)]
    unused = _check_text_columns(table, rows, members,
                                 _used_columns(table, plan, gcols, select) | compared)
    _note_unused(table, plan, unused)
    _note_levels(table, plan, rows)
    if rate is not None and rate_vals is not None and len(np.unique(rate_vals)) > 1:
        raise DataError(
            f"{src}, column {plan.rate.header!r}: holds {len(np.unique(rate_vals))} different "
            f"rates but {setting(f'rate={rate!r}', f'--rate {rate}')} was given: drop "
            + setting("rate=", "--rate") + " to get one curve per rate"
        )
    return _Groups(rows, rate_vals, len(gcols), key_cols, by_rate, members)


def _group_columns(
    table: _Table, group_by: str | Sequence[str] | None, rows: np.ndarray
) -> list[int]:
    """Columns telling curves apart: ``group_by``, else a 'test'/'curve'/... column that varies."""
    if group_by is not None:
        return [_col_index(table, g, "group_by")
                for g in ([group_by] if isinstance(group_by, str) else group_by)]
    gcols = []
    for j, h in enumerate(table.names):
        toks, _ = _split_header(h)
        if len(toks) == 1 and toks[0] in _GROUP_NAMES:
            if len(set(table.texts(j)[rows])) > 1:
                gcols.append(j)
    return gcols


#: What each plan role holds, for messages, and its unit.
_QUANTITY = {"deform": ("strain", ""), "stress": ("stress", " MPa"), "time": ("time", " s"),
             "rate": ("strain rate", " 1/s"), "deform2": ("second strain", ""),
             "stress2": ("second stress", " MPa"), "temperature": ("temperature", "")}
#: A test is at one temperature: the readings of a curve's temperature column lie within
#: this many degrees (a measured channel drifts a little, e.g. by self-heating at high
#: rates); the curve's temperature is their mean.
CURVE_TEMPERATURE_SPREAD = 2.0


def _settle_columns(table: _Table, plan: _Plan, rows: np.ndarray) -> None:
    """Each role with several columns that could hold it: read the finest-written one if
    they agree on ``rows`` to within their rounding, else refuse (``_ambiguous._settle``)."""
    for role, alts in list(plan.alternates.items()):
        chosen = getattr(plan, role)
        cols = [chosen] + alts
        factors = [plan.factors[role]] + [plan.alt_factors[c.index] for c in alts]
        cands = [_Cand(c.index, c.header, c.role, _converter(c, f)) for c, f in zip(cols, factors)]
        what, unit = _QUANTITY[role]
        k = _settle(table, rows, cands, what, unit)
        setattr(plan, role, cols[k])
        plan.factors[role] = factors[k]
        del plan.alternates[role]


def _converter(col: _Col, factor: float):
    """Values of ``col`` -> the role's quantity (engineering strain, MPa, s, 1/s)."""
    if col.role.startswith("stretch") and col.kind != "or_shear":
        return _scaled(factor, -1.0)
    if col.kind == "log":
        return lambda v: (np.expm1(v * factor), np.exp(v * factor) * factor)
    return _scaled(factor)


def _used_columns(table: _Table, plan: _Plan, gcols: list[int],
                  select: Mapping[str, Any] | None) -> set[int]:
    """Columns a text-column check leaves alone: read, grouping, selecting or ignored."""
    used = set(gcols) | plan.ignored
    used |= {c.index for c in (plan.deform, plan.stress, plan.time, plan.rate, plan.deform2,
                               plan.stress2, plan.deformation, plan.temperature)
             if c is not None}
    used |= {_col_index(table, h, "select") for h in (select or {})}
    return used


def _note_unused(table: _Table, plan: _Plan, unused: list[int]) -> None:
    """One line naming the columns the fit does not read (a second stress measure beside
    the one fitted said as such), so that nothing is dropped unseen."""
    if not unused:
        return
    names = table.names
    stress = plan.stress
    kind = stress.kind or "engineering"  # an unqualified stress is read as nominal
    other = [j for j in unused
             if (c := _classify(j, names[j])) is not None and c.role == stress.role
             and c.rank < 2.0 and {c.kind or "engineering", kind} == {"engineering", "true"}]
    rest = [j for j in unused if j not in other]
    parts = []
    if other:
        word = "true" if kind != "true" else "nominal"
        fitted = "true" if kind == "true" else "nominal"
        flag = (setting("measure='true'", "--measure true") if fitted == "nominal" else
                setting("measure='engineering'", "--measure engineering"))
        use = setting(f"columns={{'stress': {names[other[0]]!r}}}",
                      f"--columns stress={names[other[0]]}")
        parts.append(
            f"the {fitted} stress {stress.header!r} is fitted, not the {word} stress "
            f"{', '.join(repr(names[j]) for j in other)} (to fit that one: {flag} or {use})")
    if rest:
        parts.append(f"column{'s' if len(rest) > 1 else ''} "
                     f"{', '.join(repr(names[j]) for j in rest)} read and not used by the fit")
    _warn(f"{table.source}: {'; '.join(parts)}", stacklevel=2)


#: An engineering strain beyond this, in a column with no unit, is likely in percent.
PERCENT_STRAIN = 5.0
#: A stress beyond this many MPa (10 GPa) is no soft solid's: likely a wrong unit.
SOFT_SOLID_MPA = 1e4


def _note_units(table: _Table, plan: _Plan, units: Mapping[str, str]) -> None:
    """One line each: a file's stress column with no unit (read as MPa), and a ``units=`` that
    overrides the unit a header states. Notes only: nothing read changes."""
    src = table.source
    for role, col in (("stress", plan.stress), ("stress2", plan.stress2),
                      ("deform", plan.deform), ("time", plan.time)):
        if col is None:
            continue
        base = col.role.rstrip("2")
        given = units.get(col.role, units.get(base))
        if given is not None and col.unit and _norm_unit(given) != _norm_unit(col.unit):
            override = setting(f"units={{{base!r}: {given!r}}}", f"--units {base}={given}")
            _warn(f"{src}, column {col.header!r}: {override} overrides the unit {col.unit!r} the "
                  f"header states: read as {given}", stacklevel=2)
        elif role == "stress" and given is None and not col.unit and table.labels.word == "line":
            # a file's header only: arrays and mappings are documented as MPa
            _warn(f"{src}, column {col.header!r}: no unit: read as MPa; another unit "
                  "with " + setting("units={'stress': 'kPa'}", "--units stress=kPa"),
                  stacklevel=2)


def _note_levels(table: _Table, plan: _Plan, rows: np.ndarray) -> None:
    """One line each for values implausible as read: a strain beyond
    :data:`PERCENT_STRAIN` in a column with no unit (percent?), a stress beyond
    :data:`SOFT_SOLID_MPA` MPa. Notes only: nothing read changes."""
    src = table.source
    col = plan.deform
    if col.role == "strain" and col.kind == "eng" and not col.unit \
            and plan.factors["deform"] == 1.0:
        top = _largest(table, col.index, rows)
        if top > PERCENT_STRAIN:
            _warn(f"{src}, column {col.header!r}: the strain reaches {top:g} (a stretch of "
                  f"{1 + top:g}) with no unit: is it in %? then say "
                  + setting("units={'strain': '%'}", "--units strain=%"), stacklevel=2)
    col = plan.stress
    top = _largest(table, col.index, rows) * plan.factors["stress"]
    if top >= SOFT_SOLID_MPA:
        _warn(f"{src}, column {col.header!r}: the stress reaches {top:g} MPa as read, "
              "implausible for a soft solid: check its unit ("
              + setting("units={'stress': 'Pa'} or 'kPa'", "--units stress=Pa or kPa") + ")",
              stacklevel=2)


def _largest(table: _Table, j: int, rows: np.ndarray) -> float:
    """The largest finite |value| of a column at ``rows`` (0 if none): a bad cell is
    refused later, where the column is read, with its own message."""
    v = np.abs(_cells(table.texts(j)[rows])[0])
    v = v[np.isfinite(v)]
    return float(v.max()) if v.size else 0.0


def _rate_key(table: _Table, plan: _Plan, rows: np.ndarray, rate_vals: np.ndarray) -> np.ndarray:
    """The rate of each row as a group key; each rate must have at least 2 rows."""
    uniq, first_k, counts = np.unique(rate_vals, return_index=True, return_counts=True)
    if counts.min() < 2:
        k = int(first_k[np.argmin(counts)])
        raise DataError(
            f"{table.source}, column {plan.rate.header!r}: {uniq.size} different rates in "
            f"{rows.size} rows, {table.label(int(rows[k]))} alone at {rate_vals[k]:g}: if "
            "this is a measured rate channel, not the nominal rate of each test, ignore "
            "it with " + setting("columns={'rate': None}", "--columns rate=") + " (and give "
            + setting("rate=", "--rate") + " or a time column); otherwise "
            "give each rate at least 2 rows"
        )
    return np.array([f"{v:.12g}" for v in rate_vals], dtype=object)


def rate_label(value: float, every) -> str:
    """A rate rounded for reading in a curve's name: 4 significant digits, more only
    where 4 would not tell two of the table's rates ``every`` apart.

    Examples
    --------
    >>> rate_label(0.00860002, [0.00860002, 0.1])
    '0.0086'
    >>> rate_label(0.00860002, [0.00860002, 0.0086])
    '0.00860002'
    """
    vals = {float(x) for x in np.ravel(every) if np.isfinite(x)}
    for d in (4, 5, 6):
        if len({f"{x:.{d}g}" for x in vals}) == len(vals):
            return f"{float(value):.{d}g}"
    return repr(float(value))


def _group_spec(
    table: _Table,
    opts: _Options,
    grp: _Groups,
    g: np.ndarray,
    rate: float | None,
    name: str | None,
    stem: str,
    sort: bool,
    n_points: int | str | None,
    by: str | None,
) -> dict[str, Any]:
    """Keyword arguments of the curve made of rows ``grp.rows[g]``."""
    src, plan = table.source, opts.plan
    r = grp.rows[g]
    parts = [str(kc[g[0]]) for kc in grp.key_cols[: grp.n_named]]
    crate = _group_rate(table, opts, grp, g, rate)
    if grp.by_rate:
        parts.append(f"rate {rate_label(grp.rate_vals[g][0], grp.rate_vals)}/s")
    if name is not None:
        cname = name if len(grp.members) == 1 else f"{name} [{', '.join(parts)}]"
    elif "name" in opts.known and len(grp.members) == 1:
        cname = opts.known["name"]
    else:
        cname = stem if not parts else f"{stem} [{', '.join(parts)}]"
    dfm = _group_deformation(table, opts, r, cname)
    d, s, t, labels, more = _group_samples(table, plan, r, sort, dfm, cname)
    cmeta = dict(opts.meta)
    if parts:
        cmeta["group"] = ", ".join(parts)
    if grp.n_named:  # the group_by columns' own values, in their order
        cmeta["group_values"] = parts[: grp.n_named]
    cmeta["columns"] = {
        "strain": plan.deform.header, "stress": plan.stress.header,
        "time": None if plan.time is None else plan.time.header,
        "rate": None if plan.rate is None else plan.rate.header,
    }
    for role, col in (("strain2", plan.deform2), ("stress2", plan.stress2),
                      ("deformation", plan.deformation), ("temperature", plan.temperature)):
        if col is not None:
            cmeta["columns"][role] = col.header
    if plan.temperature is not None:
        cmeta["temperature"] = _curve_temperature(table, plan.temperature, r, cname,
                                                  opts.meta.get("temperature"))
    return dict(
        strain=d, stress=s, strain_rate=crate, time=t, measure=opts.measure, mode=opts.mode,
        name=cname, weight=opts.weight, n_points=n_points, by=by,
        compression_positive=opts.compression_positive, source=src, rows=labels,
        metadata=cmeta, deformation=dfm, **more,
    )


def _curve_temperature(table: _Table, col: _Col, r: np.ndarray, cname: str,
                       line: str | None) -> float:
    """The temperature of the curve made of rows ``r``: the mean of its temperature
    column's readings, which must lie within :data:`CURVE_TEMPERATURE_SPREAD` of each
    other (and of a '# temperature:' line, if the file has one)."""
    h = col.header
    ignore = "or ignore the column with " + setting("columns={'temperature': None}",
                                                    "--columns temperature=")
    T = table.floats(col.index, r, empty=f"the temperature is missing: fill it in, {ignore}")
    where = _Where(cname, table.source, None)()
    if T.max() - T.min() > CURVE_TEMPERATURE_SPREAD:
        raise DataError(
            f"{where}, column {h!r}: the temperature goes from {T.min():g} to {T.max():g} "
            f"within one curve: a test is at one temperature; give each its own curve (a "
            f"'test' column, or {setting('group_by=COLUMN', '--group-by COLUMN')}), {ignore}")
    mean = float(np.mean(T))
    if line is not None:
        try:
            stated = float(line)
        except ValueError:
            stated = None
        if stated is not None and abs(stated - mean) > CURVE_TEMPERATURE_SPREAD:
            raise DataError(
                f"{where}: the '# temperature: {line}' line and column {h!r} ({mean:g}) "
                f"disagree: correct the line, {ignore}")
    return mean


def _group_deformation(table: _Table, opts: _Options, r: np.ndarray, cname: str) -> Any:
    """A curve's test: its rows' deformation column, else ``deformation=`` or the '#' line,
    else what the columns say (a second stretch: biaxial; an amount of shear: simple
    shear), else uniaxial. An unknown name is passed on for the curve to refuse."""
    plan = opts.plan
    if plan.deformation is not None:
        text = table.texts(plan.deformation.index)[r[0]]
        dfm = _deformation_name(text)
        given = opts.deformation
        if given is not None and _deformation_name(given) not in (None, dfm):
            raise DataError(
                f"{_Where(cname, table.source, None)()}: column {plan.deformation.header!r} "
                f"says {text!r} but "
                f"{setting(f'deformation={given!r}', f'--deformation {given}')} was given: "
                f"drop {setting('deformation=', '--deformation')} (the column names each "
                "row's test)"
            )
        return dfm
    if opts.deformation is not None:
        return opts.deformation
    return _implied_deformation(second=plan.deform2 is not None,
                                shear=plan.deform.kind == "shear")


def _group_rate(
    table: _Table, opts: _Options, grp: _Groups, g: np.ndarray, rate: float | None
) -> float | None:
    """A curve's nominal rate: ``rate=``, else its rate column (one value), else the '#' line."""
    if grp.rate_vals is not None:
        gr = grp.rate_vals[g]
        if np.ptp(gr) != 0:
            k = int(np.flatnonzero(gr != gr[0])[0])
            raise DataError(
                f"{table.source}, {table.label(int(grp.rows[g][k]))}, column "
                f"{opts.plan.rate.header!r}: the rate changes from {gr[0]:g} to {gr[k]:g} "
                "inside one curve: give each test its own rate, or a 'test' column to tell "
                "them apart"
            )
    if rate is not None:
        return rate
    return float(grp.rate_vals[g][0]) if grp.rate_vals is not None else opts.meta_rate


def _group_samples(
    table: _Table, plan: _Plan, r: np.ndarray, sort: bool, deformation: Any, cname: str
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, Any, dict[str, np.ndarray]]:
    """Engineering strain (γ in simple shear), stress (MPa), time (s), row labels of rows
    ``r``, and the second strain and stress of a biaxial test (``strain2``, ``stress2``)."""
    shear = _is_shear(_deformation_name(deformation))
    if shear and plan.deform.role == "stretch" and plan.deform.kind != "or_shear":
        raise DataError(
            f"{_Where(cname, table.source, None)()}, column {plan.deform.header!r}: holds "
            "stretches, but simple shear is driven by the amount of shear γ: give a 'gamma' "
            "(or 'shear_strain') column, or correct the deformation"
        )
    d = _deformation_values(table, plan.deform, r, plan.factors["deform"], shear)
    s = table.floats(plan.stress.index, r) * plan.factors["stress"]
    t = None
    if plan.time is not None:
        t = table.floats(plan.time.index, r) * plan.factors["time"]
    more = {}
    if plan.deform2 is not None:
        more["strain2"] = _deformation_values(table, plan.deform2, r, plan.factors["deform2"],
                                              False)
    if plan.stress2 is not None:
        more["stress2"] = table.floats(plan.stress2.index, r) * plan.factors["stress2"]
    labels = table.labels[r]
    if sort:
        key = t if t is not None else np.abs(d)
        o = np.argsort(key, kind="stable")
        d, s, labels = d[o], s[o], labels[o]
        t = None if t is None else t[o]
        more = {k: v[o] for k, v in more.items()}
    return d, s, t, labels, more


def _deformation_values(table: _Table, col: Any, r: np.ndarray, factor: float,
                        shear: bool) -> np.ndarray:
    """λ − 1 of a strain or stretch column (γ itself on simple-shear rows)."""
    d = table.floats(col.index, r) * factor
    if col.kind in ("log",):
        return np.expm1(d)
    if col.role.startswith("stretch") and not (shear and col.kind == "or_shear"):
        return d - 1.0
    return d

