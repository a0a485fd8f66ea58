"""The ``vhfit`` argument parser: every command, flag and value check.

Values are checked here, at the front door, with one-line messages that name the flag
and the fix (argparse then reports them as :class:`UsageError`, exit code 2).
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable, Collection, Sequence
from typing import Any

from vhfit._version import __version__
from vhfit.cli._common import DEMO_PRONY, UsageError
from vhfit.cli._plugins import PLUGIN_GROUP, load_plugins

# The registries the flags name (solvers, tests, formulations) come with numpy and the
# model code: each command's flags import them when that command's parser is built
# (build_parser), so that --version, --help and the light commands never load them.

__all__ = ["build_parser", "command_in", "glue_windows"]


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit code 2)."""

    def error(self, message: str):  # noqa: D401 - argparse API
        raise UsageError(f"{message} (see '{self.prog} --help')")


def _command(name: str) -> Callable[..., int]:
    """The command ``cmd_<name>`` of ``vhfit.cli._<module>``, imported when it runs.

    Why: a command's module pulls in numpy, scipy and the fitting code; ``--help``,
    ``--version`` and the other commands must not wait for it.
    """
    module, _, func = name.partition(":")

    def run(args, argv=()) -> int:
        import importlib

        return getattr(importlib.import_module(f"vhfit.cli.{module}"), func)(args, argv)

    run.__name__ = func
    return run


# ============================================================== value checks
def _whole(text: str, least: int, not_int: str, too_small: str) -> int:
    """``text`` as an int >= ``least``; the messages say which flag and the fix."""
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(not_int) from None
    if n < least:
        raise argparse.ArgumentTypeError(too_small.format(n=n))
    return n


def _points(text: str) -> int | None:
    if text.lower() in ("all", "none"):
        return None
    return _whole(text, 2, f"--points {text!r}: give a whole number >= 2 or 'all'",
                  "--points {n}: give at least 2 (or 'all')")


def _ramp_points(text: str) -> int:
    n = _points(text)
    if n is None:
        raise argparse.ArgumentTypeError("--points: give a whole number >= 2")
    return n


def _deformation(text: str) -> str:
    from vhfit.modes import deformation_named, registered_deformations

    name = deformation_named(text)  # a registered test, by its name or an alias
    if name is None:  # perhaps a plug-in's test
        load_plugins()
        name = deformation_named(text)
    if name is None:
        raise argparse.ArgumentTypeError(
            f"--deformation {text!r}: use one of {', '.join(registered_deformations())}")
    return name


def _one_stretch_tests() -> str:
    """Help of simulate's --deformation: the tests it can drive, and their strains."""
    from vhfit.modes import get_deformation, registered_deformations

    tests = [get_deformation(n) for n in registered_deformations()]
    tests = [t for t in tests if not t.second_stretch]
    own = "".join(f"; {t.name}: {t.strain_label}" for t in tests
                  if t.strain_label != tests[0].strain_label)
    return (f"the test: {', '.join(t.name for t in tests)} (default uniaxial; strain = "
            f"{tests[0].strain_label}{own}); a test with a second stretch needs the Python API")


def _prony(text: str) -> int | str:
    if text.lower() == "auto":
        return "auto"
    return _whole(text, 0, f"--prony {text!r}: give the number of Prony terms (e.g. 3) or 'auto'",
                  "--prony {n}: give a whole number >= 0 or 'auto'")


def _window(what: str) -> Callable[[str], tuple[float | None, float | None] | None]:
    def conv(text: str) -> tuple[float | None, float | None] | None:
        lo, sep, hi = text.partition(":")
        if not sep:
            raise argparse.ArgumentTypeError(
                f"{what} {text!r}: give LOW:HIGH, either side may be empty (e.g. :120)")
        number = _float(what)
        out = tuple(number(v) if v.strip() else None for v in (lo, hi))
        if out[0] is not None and out[1] is not None and not out[0] < out[1]:
            raise argparse.ArgumentTypeError(f"{what} {text!r}: LOW must be below HIGH")
        return None if out == (None, None) else out

    return conv


def _positive(kind: type, what: str) -> Callable[[str], Any]:
    def conv(text: str):
        try:
            v = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{what} {text!r}: not a {kind.__name__}") from None
        if not v > 0:
            raise argparse.ArgumentTypeError(f"{what} {text!r}: must be > 0")
        return v

    return conv


def _float(what: str) -> Callable[[str], float]:
    def conv(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{what} {text!r}: not a number") from None
        if not math.isfinite(v):
            raise argparse.ArgumentTypeError(f"{what} {text!r}: must be finite")
        return v

    return conv


def _times(text: str) -> tuple[float, ...]:
    """``--time t1,t2,...``: output times in s, >= 0 and increasing."""
    number = _float("--time")
    times = tuple(number(t.strip()) for t in text.split(",") if t.strip())
    if not times or times[0] < 0 or any(b <= a for a, b in zip(times, times[1:])):
        raise argparse.ArgumentTypeError(
            f"--time {text!r}: give increasing times >= 0 in s, e.g. --time 0,10,100")
    return times


def _stretch_range(text: str) -> tuple[float, float]:
    """``--stability-range LO:HI``: stretches with 0 < LO < 1 < HI."""
    lo, sep, hi = text.partition(":")
    try:
        v: tuple[float, float] | None = (float(lo), float(hi))
    except ValueError:
        v = None
    if not sep or v is None or not 0 < v[0] < 1 < v[1] or not math.isfinite(v[1]):
        raise argparse.ArgumentTypeError(
            f"--stability-range {text!r}: give LO:HI stretches with 0 < LO < 1 < HI, "
            "e.g. --stability-range 0.5:2")
    return v


def _shift(text: str) -> tuple[str, tuple[float, ...]]:
    """``--shift wlf:C1,C2`` or ``arrhenius:E_A[,T0]`` as (law, constants)."""
    law, sep, rest = text.partition(":")
    law = law.strip().lower()
    sizes = {"wlf": (2,), "arrhenius": (1, 2)}
    form = ("give wlf:C1,C2 or arrhenius:E_A[,T0] (E_A in J/mol, T0 the absolute zero, "
            "-273.15 for C)")
    if not sep or law not in sizes:
        raise argparse.ArgumentTypeError(f"--shift {text!r}: {form}")
    try:
        vals = tuple(float(v) for v in rest.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--shift {text!r}: not numbers; {form}") from None
    if len(vals) not in sizes[law] or not all(math.isfinite(v) for v in vals):
        raise argparse.ArgumentTypeError(f"--shift {text!r}: {form}")
    return law, vals


def _column(flag: str) -> Callable[[str], str]:
    """A column name given to ``flag``: not empty."""
    def conv(text: str) -> str:
        if not text.strip():
            raise argparse.ArgumentTypeError(f"{flag} {text!r}: give a column name, e.g. "
                                             f"{flag} region")
        return text.strip()

    return conv


def _pair(flag: str, form: str, *, empty: bool = False) -> Callable[[str], tuple[str, str]]:
    """``KEY=VALUE`` of a repeatable flag (``--columns stress=S11``) as (KEY, VALUE); an
    empty VALUE only where it means something (``empty``: ``--columns time=`` ignores)."""
    def conv(text: str) -> tuple[str, str]:
        key, sep, value = text.partition("=")
        if not sep or not key.strip() or not (empty or value.strip()):
            raise argparse.ArgumentTypeError(f"{flag} {text!r}: give {form}")
        return key.strip(), value.strip()

    return conv


def _bound(text: str) -> tuple[str, float, float]:
    """``--bounds NAME=LO:HI`` as (NAME, LO, HI): finite numbers, LO < HI (whether NAME is
    a parameter of the law, and LO:HI inside its physical range, is checked with the law:
    ``cli/_settings.py``)."""
    form = "give NAME=LO:HI, e.g. alpha1=-40:40 (tau in s, moduli in MPa)"
    name, sep, rng = text.partition("=")
    lo, sep2, hi = rng.partition(":")
    name = name.strip()
    if not sep or not sep2 or not name or not lo.strip() or not hi.strip():
        raise argparse.ArgumentTypeError(f"--bounds {text!r}: {form}")
    try:
        low, high = float(lo), float(hi)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--bounds {text!r}: LO and HI are not numbers; "
                                         f"{form}") from None
    if not (math.isfinite(low) and math.isfinite(high)):
        raise argparse.ArgumentTypeError(f"--bounds {text!r}: give finite LO and HI "
                                         f"(e.g. {name}=-1e3:1e3 for a wide range)")
    if not low < high:
        raise argparse.ArgumentTypeError(f"--bounds {text!r}: LO must be below HI; give "
                                         f"{name}={min(low, high):g}:{max(low, high):g} "
                                         "with LO < HI")
    return name, low, high


def _add_data_choices(p: argparse.ArgumentParser, default: Any = None) -> None:
    """--columns, --units, --group-by and --select of the files' reader."""
    p.add_argument("--columns", type=_pair("--columns", "ROLE=NAME, e.g. stress=stress_kPa",
                                           empty=True),
                   action="append", metavar="ROLE=NAME", default=default,
                   help="the column holding a role (strain, stretch, stress, time, rate, "
                        "temperature, frequency, storage, ...): overrides recognition; "
                        "ROLE= (empty NAME) ignores the role; ignore=NAME ignores a column "
                        "(repeatable)")
    p.add_argument("--units", type=_pair("--units", "ROLE=UNIT, e.g. stress=kPa"),
                   action="append", metavar="ROLE=UNIT", default=default,
                   help="the unit of a role's column where its header has none or a wrong "
                        "one, e.g. stress=kPa (repeatable)")
    p.add_argument("--group-by", type=_column("--group-by"), action="append",
                   metavar="COLUMN", default=default,
                   help="split each file into one curve per value of this column, fitted "
                        "together as one material, e.g. --group-by region (repeatable; "
                        "--each COLUMN fits each value separately)")
    p.add_argument("--select", type=_pair("--select", "COLUMN=VALUE, e.g. region=cortex"),
                   action="append", metavar="COLUMN=VALUE", default=default,
                   help="keep only the rows where COLUMN holds VALUE (repeatable; the same "
                        "column twice keeps either value)")
    p.add_argument("--sort", action="store_true", default=False if default is None else default,
                   help="sort each curve's rows by time (by |strain| without a time "
                        "column) instead of refusing rows out of order")


def _solvers(text: str) -> list[str]:
    """``--for A,B`` -> ['A', 'B'] (names or aliases of the solver records, as their names)."""
    from vhfit.export import get_solver, solvers

    out = []
    for part in text.split(","):
        try:
            out.append(get_solver(part).name)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"--for {text!r}: give {' or '.join(solvers())} (repeat --for, or a comma "
                "list)") from None
    return out


def _density(text: str) -> float:
    v = _float("--density")(text)
    if not v > 0:
        raise argparse.ArgumentTypeError(
            f"--density {text}: must be > 0, in tonne/mm^3 (1e-9 for 1000 kg/m^3)")
    return v


def _poisson(text: str) -> float:
    v = _float("--poisson")(text)
    if not -1.0 < v < 0.5:
        raise argparse.ArgumentTypeError(
            f"--poisson {text}: must lie in (-1, 0.5) (0.5 is incompressible); give e.g. "
            "0.4995, or leave it out for the default bulk modulus (1000 x the instantaneous "
            "shear modulus)")
    return v


def _bulk(text: str) -> float:
    v = _float("--bulk-modulus")(text)
    if not v > 0:
        raise argparse.ArgumentTypeError(
            f"--bulk-modulus {text}: must be > 0 (MPa); leave it out for the default, 1000 x "
            "the instantaneous shear modulus")
    return v


def _add_card_options(p: argparse.ArgumentParser, *, fit: bool) -> None:
    """--density, --poisson / --bulk-modulus and the solvers' card variants
    (``--NAME-VARIANT`` for fit and demo, ``--VARIANT`` for export)."""
    from vhfit.export import get_solver, solvers

    p.add_argument("--density", type=_density, metavar="RHO",
                   help="mass density in tonne/mm^3 (1e-9 for 1000 kg/m^3), written as "
                        "*DENSITY, RO, MP,DENS (default: none, and the cards say so)")
    bulk = p.add_mutually_exclusive_group()
    bulk.add_argument("--poisson", type=_poisson, metavar="NU",
                      help="Poisson's ratio of the instantaneous response, -1 < NU < 0.5: "
                           "gives the bulk modulus of every card that takes one")
    bulk.add_argument("--bulk-modulus", type=_bulk, metavar="K",
                      help="bulk modulus in MPa instead of --poisson (default: each card's "
                           "own, docs/export.md: 1000 x the instantaneous shear modulus "
                           "where the card needs one, else incompressible)")
    for name in solvers():  # each solver record's card variants
        for variant, (what, detail) in get_solver(name).variants.items():
            if fit:
                p.add_argument(f"--{name}-{variant}".replace("_", "-"), action="store_true",
                               dest=f"{name}_{variant}",
                               help=f"also write the {what} card ({detail})")
    if not fit:
        for variant in dict.fromkeys(v for n in solvers() for v in get_solver(n).variants):
            owners = [n for n in solvers() if variant in get_solver(n).variants]
            p.add_argument(f"--{variant}".replace("_", "-"), action="store_true",
                           dest=f"variant_{variant}",
                           help=f"the {variant} variant of the card (--to "
                                f"{' or '.join(owners)})")


def glue_windows(argv: list[str]) -> list[str]:
    """``--trim-strain -0.3:`` -> ``--trim-strain=-0.3:`` (argparse takes -0.3: for a flag)."""
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        if a.startswith("--") and a.endswith("=--"):  # argparse would take [] for it
            raise UsageError(f"{a}: '--' is not a value; give {a[:-3]} a value "
                             f"(e.g. {a[:-3]}=VALUE)")
        if a in ("--trim-strain", "--trim-time") and i + 1 < len(argv):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
        else:
            out.append(a)
            i += 1
    return out


# ================================================================== commands
def build_parser(commands: Collection[str] | None = None) -> argparse.ArgumentParser:
    """The ``vhfit`` argument parser.

    Parameters
    ----------
    commands : collection of str, optional
        Build only these commands' flags (the command line's own parser, see
        :func:`command_in`): every command is still listed with its one-line help, as
        ``vhfit --help`` shows them, but the registries that the other commands' flags
        name are not imported. Default: every command's flags.

    Returns
    -------
    argparse.ArgumentParser
        The parser.

    Examples
    --------
    >>> from vhfit.cli import build_parser
    >>> args = build_parser().parse_args(["fit", "a.csv", "--prony", "auto"])
    >>> args.command, args.curves, args.prony, args.model
    ('fit', ['a.csv'], 'auto', 'mooney_rivlin')
    """
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--debug", action="store_true",
                        help="show a traceback instead of a one-line error")
    parser = _Parser(
        prog="vhfit", parents=[common],
        description="Calibrate visco-hyperelastic models (hyperelastic law + Prony series) to "
                    "stress-strain curves at several strain rates.",
        epilog="Start with 'vhfit demo'. Exit codes: 0 success, 1 fit failed or interrupted, "
               "2 bad input. Docs: docs/cli.md.",
    )
    parser.add_argument("--version", action="version", version=f"vhfit {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name, (flags, summary, description) in _COMMANDS.items():
        p = sub.add_parser(name, parents=[common], help=summary, description=description)
        if commands is None or name in commands:
            flags(p)
    return parser


def command_in(argv: Sequence[str]) -> tuple[str, ...]:
    """The command an argument list runs, as ``build_parser(commands=...)`` takes it: its
    first word that is not a flag (the top-level flags take no value), or none
    (``--help``, ``--version``, no arguments)."""
    return tuple(a for a in argv if not a.startswith("-"))[:1]


def _fit_flags(p: argparse.ArgumentParser) -> None:
    from vhfit.data import MAX_POINTS
    from vhfit.modes import registered_deformations

    p.add_argument("curves", nargs="+", metavar="CURVES",
                   help="CSV files: one curve per file, or long files with a strain_rate column")
    p.add_argument("--rate", type=_float("--rate"), action="append", metavar="R",
                   help="strain rate in 1/s for files without one (once for all, or once "
                        "per file)")
    p.add_argument("--measure", choices=("engineering", "true"),
                   help="stress measure when the file does not say (default engineering)")
    p.add_argument("--deformation", type=_deformation, action="append", metavar="MODE",
                   help="the test of files that do not say: "
                        + ", ".join(registered_deformations())
                        + " (once for all files, or once per file; default: what the "
                          "file's columns say, else uniaxial)")
    p.add_argument("--points", type=_points, default=None, metavar="N|all",
                   help="objective points per curve (default 'all': every sample, or the "
                        f"means of {MAX_POINTS} bins of consecutive samples for longer "
                        "records; 10 = the paper's scheme)")
    p.add_argument("--trim-strain", type=_window("--trim-strain"), metavar="LOW:HIGH",
                   action="append",
                   help="compare model and data only where LOW <= strain <= HIGH (signed; "
                        "either side may be empty, e.g. -0.4: ); once for all files or once "
                        "per file; the history keeps all data")
    p.add_argument("--trim-time", type=_window("--trim-time"), metavar="LOW:HIGH",
                   action="append",
                   help="compare only where LOW <= time (s) <= HIGH, e.g. :120 to leave out "
                        "a slack end of unloading; once for all files or once per file")
    p.add_argument("--tref", type=_float("--tref"), metavar="T",
                   help="reference temperature of the fitted constants, for tests at several "
                        "temperatures (a 'temperature' column or '# temperature:' line; "
                        "default: the shift law's, or the middle sweep temperature)")
    p.add_argument("--shift", type=_shift, metavar="LAW:CONSTANTS",
                   help="known time-temperature shift at --tref: wlf:C1,C2 or "
                        "arrhenius:E_A[,T0] (default: built from the sweeps' overlap and "
                        "fitted by WLF); a WLF shift goes into the cards, each in its "
                        "solver's form")
    _add_data_choices(p)
    p.add_argument("--bounds", type=_bound, action="append", metavar="NAME=LO:HI",
                   help="search limits of one parameter instead of the automatic ones, e.g. "
                        "alpha1=-40:40 or tau1=1e-3:10 (tau in s, moduli in MPa; "
                        "repeatable, each parameter once; within its physical range)")
    _add_fit_options(p, demo=False)
    p.set_defaults(func=_command("_fit:cmd_fit"))


def _demo_flags(p: argparse.ArgumentParser) -> None:
    _add_fit_options(p, demo=True)
    # one temperature: no shift; the default search limits
    p.set_defaults(func=_command("_fit:cmd_demo"), shift=None, tref=None, bounds=None)


def _add_fit_options(p: argparse.ArgumentParser, *, demo: bool) -> None:
    """The search and output flags of ``fit`` and ``demo``."""
    from vhfit.export import get_solver, solvers
    from vhfit.formulations import FORMULATIONS

    if not demo:
        p.add_argument("--model", default="mooney_rivlin",
                       help="hyperelastic model (default mooney_rivlin; see 'vhfit models'); "
                            "several, comma-separated (mooney_rivlin,yeoh,ogden2), or 'all': "
                            "each fitted side by side, ranked, the best written as the result "
                            "and the others under laws/LAW/")
        p.add_argument("--each", type=_column("--each"), metavar="COLUMN", default=None,
                       help="fit each value of this column separately (one material each): "
                            "one output folder each under --out, and each.txt / each.csv "
                            "side by side; --group-by instead fits the groups as one material")
    p.add_argument("--prony", type=_prony, default=DEMO_PRONY if demo else None,
                   metavar="N|auto",
                   help="number of Prony terms, or 'auto' to scan N = 1, 2, ... while a term "
                        "lowers the error by 5 %% or more, up to --max-prony "
                        + (f"(default {DEMO_PRONY})" if demo else
                           "(default 2, or 0 when the data cannot separate elastic from "
                           "viscous response: one monotonic rate, or only equilibrium "
                           "curves)"))
    p.add_argument("--max-prony", type=int, default=5, metavar="N",
                   help="largest N of --prony auto (default 5; sweeps and relaxation "
                        "tests alone scan one term per decade of the data instead)")
    if not demo:
        p.add_argument("--strategy", default="free",
                       help="tau strategy: free, semifree or fixed (default free; "
                            "see 'vhfit models')")
    p.add_argument("--method", choices=("separable", "full"), default="separable",
                   help="separable (DE over tau + NNLS for moduli, default) or full "
                        "(the paper's all-parameter DE)")
    p.add_argument("--seed", type=int, default=0,
                   help="random seed of the search (default 0: runs are reproducible)")
    p.add_argument("--out", metavar="DIR",
                   help="output folder (default ./vhfit-{}, or -2, -3... if taken)".format(
                       "demo" if demo else "results"))
    p.add_argument("--force", action="store_true", help="write into a non-empty --out")
    p.add_argument("--resume", action="store_true",
                   help="continue an interrupted fit from the checkpoint in --out "
                        "(same command otherwise)")
    p.add_argument("--popsize", type=_positive(int, "--popsize"),
                   help="population size (absolute; default 64 separable, 60 full)")
    p.add_argument("--maxiter", type=_positive(int, "--maxiter"),
                   help="generation cap (default 1000 separable, 100000 full)")
    p.add_argument("--max-time", type=_positive(float, "--max-time"), metavar="SECONDS",
                   help="stop the search after this many seconds with the best so far")
    p.add_argument("--target", type=_float("--target"), default=1e-4, metavar="PERCENT",
                   help="stop as soon as RMSAPE <= this (percent, default 1e-4)")
    p.add_argument("--stability-range", type=_stretch_range, metavar="LO:HI",
                   help="stretches over which the fitted law must be Drucker-stable in "
                        "the stability check's tests (uniaxial, biaxial, planar) "
                        "(default: the data's smallest and largest principal stretch, "
                        "each 10 %% further from 1)")
    p.add_argument("--g-inf-min", type=_float("--g-inf-min"), default=1e-6,
                   help="floor on g_inf (FE solvers reject 0; default 1e-6)")
    p.add_argument("--workers", type=_positive(int, "--workers"), default=1,
                   help="parallel processes for the full method (default 1)")
    p.add_argument("--scan-workers", choices=("auto", "1", "2"), default="auto",
                   help="processes for --prony auto's N: 2 side by side (a second process "
                        "fits N = 3 while the first fits N = 1 and 2; the same result), 1 "
                        "one after the other; auto (default): 2 where two CPUs are usable")
    p.add_argument("--no-polish", action="store_true",
                   help="skip the final least-squares polish")
    p.add_argument("--checkpoint-every", type=_positive(float, "--checkpoint-every"),
                   default=5.0, metavar="SECONDS",
                   help="seconds between checkpoints for --resume (default 5)")
    every = solvers()
    own = "; ".join(f"{n}: {get_solver(n).formulation}" for n in every)
    p.add_argument("--for", type=_solvers, action="append", dest="targets",
                   metavar="SOLVER[,SOLVER]",
                   help=f"fit for these solvers ({', '.join(every)}; repeatable): each "
                        "solver's card comes from a fit in the formulation it integrates "
                        f"({own}), and only their cards are written (default: every "
                        "solver, each from its own formulation's fit)")
    p.add_argument("--formulation", metavar="NAME",
                   help=f"fit in this viscoelastic formulation ({', '.join(FORMULATIONS)} "
                        "or a registered one) for every card written, instead of each "
                        "solver's own (--for); the card check shows the error each solver "
                        "will make of it")
    _add_card_options(p, fit=True)
    p.add_argument("--no-plot", action="store_true", help="do not draw plots")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")


def _simulate_flags(p: argparse.ArgumentParser) -> None:
    p.add_argument("--results", metavar="RESULTS.json", help="material from a results file")
    p.add_argument("--model", help="hyperelastic model (with --param)")
    p.add_argument("--param", action="append", metavar="NAME=VALUE[,NAME=VALUE...]",
                   help="a constant (repeatable): C10=0.1, G1=1, tau1=0.01 ...; overrides "
                        "--results")
    p.add_argument("--rate", type=_float("--rate"), action="append", metavar="R",
                   help="constant engineering strain rate in 1/s (repeatable)")
    p.add_argument("--strain-max", type=_float("--strain-max"), metavar="E",
                   help="final engineering strain of the ramps (default -0.5 or 0.5, the "
                        "rate's sign)")
    p.add_argument("--points", type=_ramp_points, default=50, metavar="N",
                   help="points per ramp, from rest (default 50)")
    p.add_argument("--history", action="append", metavar="FILE.csv",
                   help="a strain history with time (s) and strain columns (repeatable)")
    p.add_argument("--card", metavar="FILE",
                   help="material from a solver card vhfit reads (the format is read from "
                        "the file; Prony terms or nonlinear networks)")
    p.add_argument("--creep", type=_float("--creep"), metavar="S",
                   help="creep test: the stress S (MPa, in --measure) applied at once at "
                        "t = 0, then held (with --time; network cards)")
    p.add_argument("--time", type=_times, metavar="T1,T2,...",
                   help="output times of --creep in s, increasing from >= 0")
    p.add_argument("--deformation", type=_deformation, default="uniaxial", metavar="MODE",
                   help=_one_stretch_tests())
    p.add_argument("--measure", choices=("engineering", "true"), default="engineering",
                   help="stress measure (default engineering)")
    p.add_argument("--out", metavar="FILE.csv", help="output CSV (default: standard output)")
    p.set_defaults(func=_command("_simulate:cmd_simulate"))


def _export_flags(p: argparse.ArgumentParser) -> None:
    from vhfit.export import solvers

    p.add_argument("results", metavar="RESULTS.json")
    p.add_argument("--to", required=True, choices=(*solvers(), "json"),
                   help=f"{', '.join(solvers())} or json")
    p.add_argument("--name", help="material name in the card")
    _add_card_options(p, fit=False)
    p.add_argument("--out", metavar="FILE", help="output file (default: standard output)")
    p.set_defaults(func=_command("_export:cmd_export"))


def _check_flags(p: argparse.ArgumentParser) -> None:
    p.add_argument("results", metavar="RESULTS.json",
                   help="results.json of 'vhfit fit' (its cards are read from its folder)")
    p.add_argument("--data", nargs="+", metavar="FILE",
                   help="the CSV files of the fit (default: the input files the results "
                        "record)")
    p.add_argument("--card", action="append", metavar="FILE",
                   help="check this card instead of the results folder's (repeatable; "
                        "the format is read from the file)")
    # the fit's data options; not given: the results' own (cli_options)
    d = argparse.SUPPRESS
    p.add_argument("--rate", type=_float("--rate"), action="append", metavar="R", default=d,
                   help="strain rate in 1/s for files without one (as for fit)")
    p.add_argument("--measure", choices=("engineering", "true"), default=d,
                   help="stress measure when the file does not say")
    p.add_argument("--deformation", type=_deformation, action="append", metavar="MODE",
                   default=d, help="the test of files that do not say (as for fit)")
    p.add_argument("--points", type=_points, metavar="N|all", default=d,
                   help="objective points per curve (default: the fit's)")
    p.add_argument("--trim-strain", type=_window("--trim-strain"), metavar="LOW:HIGH",
                   action="append", default=d, help="as for fit (default: the fit's)")
    p.add_argument("--trim-time", type=_window("--trim-time"), metavar="LOW:HIGH",
                   action="append", default=d, help="as for fit (default: the fit's)")
    _add_data_choices(p, default=d)
    p.add_argument("--json", action="store_true", help="print the card check as JSON")
    p.set_defaults(func=_command("_check:cmd_check"))


def _models_flags(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=_command("_models:cmd_models"))


#: command -> (its flags, its line in --help, its description), in --help's order
_COMMANDS: dict[str, tuple[Callable[[argparse.ArgumentParser], None], str, str]] = {
    "fit": (_fit_flags, "calibrate a model to CSV curves",
            "Calibrate a model to stress-strain curves (CSV) and write results JSON, fitted "
            "curves, solver cards and plots."),
    "demo": (_demo_flags, "calibrate the bundled synthetic SEBS set end to end",
             "Calibrate Mooney-Rivlin + 4 Prony terms (semifree) to the bundled synthetic "
             "SEBS curves (generated from the paper's Table 5 parameters at -0.0018, -0.18, "
             "-59.5, -820 1/s) and write every output into a fresh folder."),
    "simulate": (_simulate_flags, "stress-strain curves of a material",
                 "Stress of a material along constant-rate ramps or measured histories, "
                 "or its strain under a held stress (--creep), as CSV."),
    "export": (_export_flags, "solver card of a results file",
               "Write the material card of a results file for an FE solver."),
    "check": (_check_flags, "what each solver will compute from the cards, against the data",
              "Parse the solver cards of a results folder back, re-simulate each in its "
              "solver's viscoelastic formulation on every test history, and score it against "
              "the data."),
    "models": (_models_flags, "registered hyperelastic models and tau strategies",
               f"List the hyperelastic models (built-in and plug-ins of the '{PLUGIN_GROUP}' "
               "entry-point group) and tau strategies."),
}
