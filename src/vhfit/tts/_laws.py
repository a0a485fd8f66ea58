"""Shift-factor laws of time–temperature superposition and their least-squares fits.

Every law gives log10 a_T(T), zero at its reference temperature T_ref, with
τ_i(T) = a_T τ_i(T_ref): a_T < 1 above T_ref (faster relaxation), > 1 below.

* WLF: log10 a_T = −C1 (T − T_ref) / (C2 + T − T_ref), valid where C2 + T − T_ref > 0;
* Arrhenius: log10 a_T = E_a / (R ln 10) · (1/(T − T_0) − 1/(T_ref − T_0)), with T_0 the
  absolute zero of the temperature scale (−273.15 for °C, 0 for K);
* polynomial: log10 a_T = Σ_{k=1..n} c_k (T − T_ref)^k.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Universal gas constant, J/(mol K).
GAS_CONSTANT = 8.314462618
LN10 = math.log(10.0)


def _temps(T) -> np.ndarray:
    T = np.asarray(T, dtype=np.float64)
    if not np.isfinite(T).all():
        raise ValueError("temperature: every temperature must be finite")
    return T


@dataclass(frozen=True)
class WLF:
    """Williams–Landel–Ferry shift: log10 a_T = −C1 (T − T_ref) / (C2 + T − T_ref).

    Parameters
    ----------
    C1 : float
        Dimensionless constant (> 0 for the usual slowing down on cooling).
    C2 : float
        Constant in the temperature unit (> 0).
    T_ref : float
        Reference temperature, where a_T = 1.

    Examples
    --------
    >>> law = WLF(C1=17.44, C2=51.6, T_ref=0.0)
    >>> round(float(law.log_aT(10.0)), 6)      # −17.44·10/61.6
    -2.831169
    """

    C1: float
    C2: float
    T_ref: float
    name = "wlf"

    def __post_init__(self) -> None:
        for key in ("C1", "C2", "T_ref"):
            if not math.isfinite(getattr(self, key)):
                raise ValueError(f"WLF {key} = {getattr(self, key)!r}: give a finite number")
        if not self.C2 > 0:
            raise ValueError(f"WLF C2 = {self.C2!r}: C2 must be > 0 (temperature units)")

    def log_aT(self, T) -> np.ndarray:
        """log10 a_T at temperature(s) ``T``; an error below the pole T = T_ref − C2."""
        x = _temps(T) - self.T_ref
        den = self.C2 + x
        if (den <= 0).any():
            bad = float(np.min(np.asarray(T, dtype=np.float64)[den <= 0]))
            raise ValueError(
                f"temperature {bad:g} is at or below the WLF pole T_ref - C2 = "
                f"{self.T_ref - self.C2:g}: the law is undefined there")
        return -self.C1 * x / den

    def aT(self, T) -> np.ndarray:
        """The shift factor a_T itself."""
        return 10.0 ** self.log_aT(T)

    def constants(self) -> dict[str, float]:
        return {"T_ref": float(self.T_ref), "C1": float(self.C1), "C2": float(self.C2)}


@dataclass(frozen=True)
class Arrhenius:
    """Arrhenius shift: log10 a_T = E_a/(R ln 10) · (1/(T − T_0) − 1/(T_ref − T_0)).

    Parameters
    ----------
    E_a : float
        Activation energy, J/mol.
    T_ref : float
        Reference temperature.
    absolute_zero : float, default −273.15
        T_0, the absolute zero of the temperature scale used (0 for kelvin).

    Examples
    --------
    >>> law = Arrhenius(E_a=1e5, T_ref=25.0)
    >>> round(float(law.log_aT(35.0)), 6)
    -0.56853
    """

    E_a: float
    T_ref: float
    absolute_zero: float = -273.15
    name = "arrhenius"

    def __post_init__(self) -> None:
        if not (math.isfinite(self.E_a) and math.isfinite(self.T_ref)):
            raise ValueError("Arrhenius E_a and T_ref must be finite numbers")
        if not self.T_ref > self.absolute_zero:
            raise ValueError(f"Arrhenius T_ref = {self.T_ref!r} is not above absolute zero "
                             f"{self.absolute_zero!r}: check the temperature unit")

    def _h(self, T) -> np.ndarray:
        T = _temps(T)
        if (T <= self.absolute_zero).any():
            raise ValueError(f"temperature {float(T.min()):g} is not above absolute zero "
                             f"{self.absolute_zero:g}: check the temperature unit")
        return 1.0 / (T - self.absolute_zero) - 1.0 / (self.T_ref - self.absolute_zero)

    def log_aT(self, T) -> np.ndarray:
        return self.E_a / (GAS_CONSTANT * LN10) * self._h(T)

    def aT(self, T) -> np.ndarray:
        return 10.0 ** self.log_aT(T)

    def constants(self) -> dict[str, float]:
        return {"T_ref": float(self.T_ref), "E_a": float(self.E_a),
                "absolute_zero": float(self.absolute_zero)}


@dataclass(frozen=True)
class PolynomialShift:
    """Polynomial shift: log10 a_T = Σ_k c_k (T − T_ref)^k, k = 1..len(coefficients).

    Examples
    --------
    >>> law = PolynomialShift(coefficients=(-0.1, 0.001), T_ref=20.0)
    >>> float(law.log_aT(30.0))
    -0.9
    """

    coefficients: tuple[float, ...]
    T_ref: float
    name = "polynomial"

    def __post_init__(self) -> None:
        c = tuple(float(v) for v in self.coefficients)
        if not c or not all(math.isfinite(v) for v in c) or not math.isfinite(self.T_ref):
            raise ValueError("polynomial shift: give at least one finite coefficient and a "
                             "finite T_ref")
        object.__setattr__(self, "coefficients", c)

    def log_aT(self, T) -> np.ndarray:
        x = _temps(T) - self.T_ref
        return sum(c * x ** (k + 1) for k, c in enumerate(self.coefficients)) * np.ones_like(x)

    def aT(self, T) -> np.ndarray:
        return 10.0 ** self.log_aT(T)

    def constants(self) -> dict[str, float]:
        out = {"T_ref": float(self.T_ref)}
        out.update({f"c{k + 1}": c for k, c in enumerate(self.coefficients)})
        return out


LAWS = ("wlf", "arrhenius", "polynomial")


def _check_pairs(temperature, log_aT) -> tuple[np.ndarray, np.ndarray]:
    T = np.asarray(temperature, dtype=np.float64).ravel()
    y = np.asarray(log_aT, dtype=np.float64).ravel()
    if T.shape != y.shape:
        raise ValueError(f"temperature and log_aT need one value each: got {T.size} "
                         f"temperatures and {y.size} shift factors")
    if not (np.isfinite(T).all() and np.isfinite(y).all()):
        raise ValueError("temperature/log_aT: every value must be finite")
    if np.unique(T).size < 2:
        raise ValueError("shift factors at fewer than 2 temperatures cannot define a law")
    return T, y


def fit_shift_law(temperature, log_aT, law: str = "wlf", *, T_ref: float | None = None,
                  degree: int = 2, absolute_zero: float = -273.15):
    """Least-squares fit of a shift law to shift factors log10 a_T(T).

    Parameters
    ----------
    temperature, log_aT : array_like
        Temperatures and their log10 shift factors (same length, ≥ 2 temperatures).
    law : {"wlf", "arrhenius", "polynomial"}
        The law fitted (in log10 a_T, unweighted).
    T_ref : float, optional
        Reference temperature of the law; default the temperature with the smallest
        |log10 a_T| (the data's own reference).
    degree : int
        Degree of the polynomial law.
    absolute_zero : float
        T_0 of the Arrhenius law (−273.15 for °C).

    Returns
    -------
    WLF, Arrhenius or PolynomialShift

    Notes
    -----
    WLF is fitted by variable projection: for a fixed C2, C1 enters linearly and has a
    closed form, so the sum of squares is minimised over C2 alone (bounded so that
    C2 + T − T_ref > 0 at every data temperature): a scan of log(C2 − C2_min), then
    Brent's method on the best bracket.

    Examples
    --------
    >>> import numpy as np
    >>> T = np.linspace(-20.0, 60.0, 9)
    >>> law = fit_shift_law(T, WLF(8.86, 101.6, 0.0).log_aT(T))
    >>> round(law.C1, 6), round(law.C2, 4)
    (8.86, 101.6)
    """
    T, y = _check_pairs(temperature, log_aT)
    if T_ref is None:
        T_ref = float(T[np.argmin(np.abs(y))])
    key = str(law).strip().lower()
    if key == "wlf":
        return _fit_wlf(T - T_ref, y, float(T_ref))
    if key == "arrhenius":
        h = Arrhenius(1.0, T_ref, absolute_zero)._h(T)
        slope = float(h @ y / (h @ h))
        return Arrhenius(slope * GAS_CONSTANT * LN10, float(T_ref), absolute_zero)
    if key == "polynomial":
        if not (isinstance(degree, (int, np.integer)) and 1 <= degree < np.unique(T).size):
            raise ValueError(f"degree = {degree!r}: give an integer from 1 to the number of "
                             "temperatures - 1")
        x = T - T_ref
        A = np.stack([x ** (k + 1) for k in range(int(degree))], axis=1)
        c, *_ = np.linalg.lstsq(A, y, rcond=None)
        return PolynomialShift(tuple(c), float(T_ref))
    raise ValueError(f"law = {law!r}: choose one of {', '.join(LAWS)}")


def _wlf_c1(x, y, c2):
    g = x / (c2 + x)
    gg = g @ g
    c1 = -(g @ y) / gg if gg > 0 else 0.0
    r = y + c1 * g
    return c1, float(r @ r)


def _fit_wlf(x: np.ndarray, y: np.ndarray, T_ref: float) -> WLF:
    from scipy.optimize import minimize_scalar

    span = float(np.ptp(x)) or 1.0
    floor = max(0.0, -float(x.min()))  # C2 + x > 0 at every data point
    # C2 = floor + span·e^u: scan u coarsely, then refine the best bracket
    us = np.linspace(-12.0, 8.0, 201)
    sse = [_wlf_c1(x, y, floor + span * math.exp(u))[1] for u in us]
    k = int(np.argmin(sse))
    lo, hi = us[max(k - 1, 0)], us[min(k + 1, us.size - 1)]
    best = minimize_scalar(lambda u: _wlf_c1(x, y, floor + span * math.exp(u))[1],
                           bounds=(lo, hi), method="bounded", options={"xatol": 1e-12})
    c2 = floor + span * math.exp(best.x)
    c1, _ = _wlf_c1(x, y, c2)
    return WLF(float(c1), float(c2), T_ref)


#: A WLF fit whose C2 is at least this many times the data's largest |T − T_ref| is a
#: straight line in T to within 1 % over the data (its curvature term (T − T_ref)/C2):
#: C1 and C2 have grown together without bound, the law has no meaning beyond the line
WLF_DEGENERATE = 100.0


def wlf_degenerate(law, temperatures) -> str | None:
    """Why a WLF law fitted to shift factors at ``temperatures`` is degenerate, or None.

    Parameters
    ----------
    law : WLF (any other law: None)
    temperatures : array_like
        The temperatures of the shift factors it was fitted to.

    Returns
    -------
    str or None
        One line: C1 and C2 growing together, i.e. log10 a_T a straight line in T.

    Examples
    --------
    >>> import numpy as np
    >>> wlf_degenerate(WLF(8.86, 101.6, 0.0), np.linspace(-20, 60, 9)) is None
    True
    >>> T = np.linspace(0.0, 100.0, 11)
    >>> wlf_degenerate(fit_shift_law(T, -0.2 * (T - 50.0), "wlf"), T)[:36]
    'the WLF fit of the shift factors deg'
    """
    if not isinstance(law, WLF):
        return None
    T = np.asarray(temperatures, dtype=np.float64).ravel()
    reach = float(np.max(np.abs(T - law.T_ref))) if T.size else 0.0
    if not reach > 0 or law.C2 < WLF_DEGENERATE * reach:
        return None
    return (f"the WLF fit of the shift factors degenerates: C1 = {law.C1:.3g} and C2 = "
            f"{law.C2:.3g} grow together (C2 is {law.C2 / reach:.3g} times the largest "
            f"|T - T_ref| of the data), i.e. log10 a_T is a straight line in T "
            f"({-law.C1 / law.C2:.4g} per degree over T = {T.min():g}..{T.max():g}), as "
            "across a glass transition: C1 and C2 mean nothing one by one, and the law "
            "holds only between those temperatures")


def choose_shift_law(temperature, log_aT, T_ref: float | None = None):
    """The shift law fitted to shift factors: WLF, unless its fit degenerates.

    A degenerate WLF fit (:func:`wlf_degenerate`) is replaced by the law the data choose
    among Arrhenius and the polynomials of degree 1 and 2 (2 only from 4 temperatures):
    the one with the fewest constants whose RMS residual (in decades) is within 10 % of
    the best of them.

    Parameters
    ----------
    temperature, log_aT : array_like
        Temperatures and log10 shift factors.
    T_ref : float, optional
        Reference temperature (default as :func:`fit_shift_law`).

    Returns
    -------
    (law, message)
        The law, and None or the one-line report of the degenerate WLF fit and the law
        chosen instead.

    Examples
    --------
    >>> import numpy as np
    >>> T = np.linspace(0.0, 100.0, 11)
    >>> law, msg = choose_shift_law(T, -0.2 * (T - 50.0), T_ref=50.0)
    >>> law.name, round(law.coefficients[0], 9)
    ('polynomial', -0.2)
    """
    T, y = _check_pairs(temperature, log_aT)
    wlf = fit_shift_law(T, y, "wlf", T_ref=T_ref)
    why = wlf_degenerate(wlf, T)
    if why is None:
        return wlf, None
    T_ref = wlf.T_ref
    cands = [fit_shift_law(T, y, "polynomial", T_ref=T_ref, degree=1)]
    if min(T.min(), T_ref) > -273.15:  # above absolute zero in °C: Arrhenius defined
        cands.insert(0, fit_shift_law(T, y, "arrhenius", T_ref=T_ref))
    if np.unique(T).size >= 4:
        cands.append(fit_shift_law(T, y, "polynomial", T_ref=T_ref, degree=2))
    rms = [float(np.sqrt(np.mean((law.log_aT(T) - y) ** 2))) for law in cands]
    best = min(rms)
    k = next(i for i, r in enumerate(rms) if r <= 1.1 * best + 1e-12)
    law = cands[k]
    names = ", ".join(_label(c) + f" {r:.3g}" for c, r in zip(cands, rms))
    return law, (f"{why}; the tests at those temperatures keep their measured shift "
                 f"factors, and the law is the one the data choose instead: {_label(law)} "
                 f"(RMS residual in decades: {names})")


def _label(law) -> str:
    if law.name == "polynomial":
        return f"polynomial of degree {len(law.coefficients)}"
    return str(law.name)
