"""The built-in strain energies, registered by name when the package is imported (their
registration check runs in the test suite: :func:`._registry.register_builtin`)."""

from __future__ import annotations

import math

import numpy as np

from vhfit.hyperelastic._ogden import ogden_sums
from vhfit.hyperelastic._registry import register_builtin as register

_POS = (0.0, math.inf)
_FREE = (-math.inf, math.inf)


def _same(smaller: str, *names: str) -> tuple[str, dict]:
    """``contains=`` entry of a law that holds ``smaller``'s constants under their own
    names (the others 0)."""
    return smaller, {n: n for n in names}


#: neo-Hooke inside any law with a C10 (I1 − 3) term
_NEO = (_same("neo_hooke", "C10"),)


def _mr_dW(I1, I2, C10, C01):
    return C10, C01


@register("mooney_rivlin", bounds=(_FREE, _FREE), derivatives=_mr_dW, linear=True,
          example=(0.1, 0.05), contains=_NEO)
def mooney_rivlin(I1, I2, C10, C01):
    """Mooney–Rivlin (paper Eq. 5, m = l = 1): W = C10 (I1 − 3) + C01 (I2 − 3)."""
    return C10 * (I1 - 3) + C01 * (I2 - 3)


@register("neo_hooke", bounds=(_POS,), derivatives=lambda I1, I2, C10: (C10, 0.0 * C10),
          linear=True, example=(0.1,))
def neo_hooke(I1, I2, C10):
    """neo-Hookean: W = C10 (I1 − 3)."""
    return C10 * (I1 - 3)


def _yeoh_dW(I1, I2, C10, C20, C30):
    x = I1 - 3
    return C10 + 2 * C20 * x + 3 * C30 * x**2, 0.0 * x


@register("yeoh", bounds=(_POS, _FREE, _FREE), derivatives=_yeoh_dW, linear=True,
          example=(0.1, -0.01, 0.001), contains=_NEO)
def yeoh(I1, I2, C10, C20, C30):
    """Yeoh: W = C10 (I1 − 3) + C20 (I1 − 3)² + C30 (I1 − 3)³."""
    return C10 * (I1 - 3) + C20 * (I1 - 3) ** 2 + C30 * (I1 - 3) ** 3


@register("polynomial2", linear=True, example=(0.1, 0.05, 0.01, 0.0, 0.0),
          contains=(_same("mooney_rivlin", "C10", "C01"),))
def polynomial2(I1, I2, C10, C01, C20, C11, C02):
    """Generalised polynomial of order 2: W = Σ_{i+j≤2} Cij (I1 − 3)^i (I2 − 3)^j."""
    x, y = I1 - 3, I2 - 3
    return C10 * x + C01 * y + C20 * x**2 + C11 * x * y + C02 * y**2


@register("polynomial3", linear=True,
          example=(0.1, 0.05, 0.01, 0.0, 0.0, 0.001, 0.0, 0.0, 0.0),
          contains=(_same("polynomial2", "C10", "C01", "C20", "C11", "C02"),))
def polynomial3(I1, I2, C10, C01, C20, C11, C02, C30, C21, C12, C03):
    """Generalised polynomial of order 3: W = Σ_{i+j≤3} Cij (I1 − 3)^i (I2 − 3)^j."""
    x, y = I1 - 3, I2 - 3
    return (C10 * x + C01 * y + C20 * x**2 + C11 * x * y + C02 * y**2
            + C30 * x**3 + C21 * x**2 * y + C12 * x * y**2 + C03 * y**3)


def _ogden_term(l1, l2, l3, mu, alpha):
    return 2 * mu / alpha**2 * (l1**alpha + l2**alpha + l3**alpha - 3)


def _ogden_dW(l1, l2, l3, *pairs):
    """λa ∂W/∂λa = Σ_p (2μp/αp) λa^αp for a = 1, 2, 3 (closed form: no complex powers).

    One compiled pass over the parameter sets and samples (:mod:`._ogden`): λ1^α is
    exp(α ln λ1) and the other powers follow from it where the test's kinematics tie the
    stretches together; a stretch passed twice gets the same array twice.
    """
    return ogden_sums(l1, l2, l3, pairs[::2], pairs[1::2])


_OG = dict(units=("MPa", "1"), bounds=(_FREE, _FREE))
# typical terms: a neo-Hooke-like main term, then small softening and stiffening ones
# (μp > 0: each term is stable, docs/theory.md §2)
_OGDEN_EXAMPLE = (0.1, 2.0, 0.01, -2.0, 0.001, 5.0, 0.0005, -4.0, 1e-4, 8.0, 5e-5, 1.0)


def _ogden_less(n: int) -> tuple[tuple[str, dict]]:
    """``contains=`` of the n-term Ogden law: the (n − 1)-term law, its last term idle
    (μn = 0) at the example's αn, a value inside αn's search range (its stress is 0
    whatever αn)."""
    smaller = "ogden" if n == 2 else f"ogden{n - 1}"
    names = [f"{c}{p}" for p in range(1, n) for c in ("mu", "alpha")]
    return ((smaller, {**{n_: n_ for n_ in names}, f"alpha{n}": _OGDEN_EXAMPLE[2 * n - 1]}),)


# every Ogden law uses the closed form on every test, several times faster than the
# complex step (the one-term law is the contained law of every Ogden-2 fit: its fit
# is part of theirs, calibration/_nesting.py)


@register("ogden", units=_OG["units"], bounds=_OG["bounds"], example=(0.1, 2.0),
          mu0=lambda mu1, a1: mu1, linear_params=("mu1",), derivatives=_ogden_dW,
          contains=(("neo_hooke", {"mu1": lambda c: 2.0 * c["C10"], "alpha1": 2.0}),))
def ogden(l1, l2, l3, mu1, alpha1):
    """Ogden, one term (2μ/α² form): W = 2μ1/α1² (λ1^α1 + λ2^α1 + λ3^α1 − 3); μ0 = μ1."""
    return _ogden_term(l1, l2, l3, mu1, alpha1)


@register("ogden2", units=_OG["units"] * 2, bounds=_OG["bounds"] * 2,
          example=(0.1, 2.0, 0.01, -2.0), mu0=lambda m1, a1, m2, a2: m1 + m2,
          derivatives=_ogden_dW,
          linear_params=("mu1", "mu2"), fewer="ogden", term=2, contains=_ogden_less(2))
def ogden2(l1, l2, l3, mu1, alpha1, mu2, alpha2):
    """Ogden, two terms: W = Σ_p 2μp/αp² (λ1^αp + λ2^αp + λ3^αp − 3)."""
    return _ogden_term(l1, l2, l3, mu1, alpha1) + _ogden_term(l1, l2, l3, mu2, alpha2)


@register("ogden3", units=_OG["units"] * 3, bounds=_OG["bounds"] * 3,
          example=(0.1, 2.0, 0.01, -2.0, 0.001, 5.0),
          mu0=lambda m1, a1, m2, a2, m3, a3: m1 + m2 + m3,
          derivatives=_ogden_dW,
          linear_params=("mu1", "mu2", "mu3"), fewer="ogden2", term=2,
          contains=_ogden_less(3))
def ogden3(l1, l2, l3, mu1, alpha1, mu2, alpha2, mu3, alpha3):
    """Ogden, three terms: W = Σ_p 2μp/αp² (λ1^αp + λ2^αp + λ3^αp − 3)."""
    return (_ogden_term(l1, l2, l3, mu1, alpha1) + _ogden_term(l1, l2, l3, mu2, alpha2)
            + _ogden_term(l1, l2, l3, mu3, alpha3))


def _ogden_sum(l1, l2, l3, *pairs):
    """Σ_p 2μp/αp² (λ1^αp + λ2^αp + λ3^αp − 3) over pairs = (μ1, α1, μ2, α2, ...)."""
    return sum(_ogden_term(l1, l2, l3, mu, alpha) for mu, alpha in zip(pairs[::2], pairs[1::2]))


def _ogden(n: int) -> dict:
    """Registration options of the n-term Ogden law (μp linear, μ0 = Σ μp)."""
    return dict(units=_OG["units"] * n, bounds=_OG["bounds"] * n, derivatives=_ogden_dW,
                example=_OGDEN_EXAMPLE[: 2 * n], mu0=lambda *c: sum(c[0::2]),
                linear_params=tuple(f"mu{p}" for p in range(1, n + 1)),
                fewer=f"ogden{n - 1}", term=2, contains=_ogden_less(n))



@register("ogden4", **_ogden(4))
def ogden4(l1, l2, l3, mu1, alpha1, mu2, alpha2, mu3, alpha3, mu4, alpha4):
    """Ogden, four terms: W = Σ_p 2μp/αp² (λ1^αp + λ2^αp + λ3^αp − 3)."""
    return _ogden_sum(l1, l2, l3, mu1, alpha1, mu2, alpha2, mu3, alpha3, mu4, alpha4)


@register("ogden5", **_ogden(5))
def ogden5(l1, l2, l3, mu1, alpha1, mu2, alpha2, mu3, alpha3, mu4, alpha4, mu5, alpha5):
    """Ogden, five terms: W = Σ_p 2μp/αp² (λ1^αp + λ2^αp + λ3^αp − 3)."""
    return _ogden_sum(l1, l2, l3, mu1, alpha1, mu2, alpha2, mu3, alpha3, mu4, alpha4,
                      mu5, alpha5)


@register("ogden6", **_ogden(6))
def ogden6(l1, l2, l3, mu1, alpha1, mu2, alpha2, mu3, alpha3, mu4, alpha4, mu5, alpha5,
           mu6, alpha6):
    """Ogden, six terms (the solvers' maximum): W = Σ_p 2μp/αp² (λ1^αp + λ2^αp + λ3^αp − 3)."""
    return _ogden_sum(l1, l2, l3, mu1, alpha1, mu2, alpha2, mu3, alpha3, mu4, alpha4,
                      mu5, alpha5, mu6, alpha6)


# ----------------------------------------------------------- reduced polynomial
def _rpoly_dW(I1, I2, *C):
    """∂W/∂I1 = Σ_i i Ci0 (I1 − 3)^(i−1), ∂W/∂I2 = 0."""
    x = I1 - 3
    return sum(i * c * x ** (i - 1) for i, c in enumerate(C, start=1)), 0.0 * x


def _rpoly(n: int) -> dict:
    """Registration options of the reduced polynomial of order n (N = n)."""
    return dict(bounds=(_POS,) + (_FREE,) * (n - 1), derivatives=_rpoly_dW, linear=True,
                example=(0.1, 0.005, 5e-4, 5e-5, 5e-6, 5e-7)[:n],
                fewer=f"reduced_polynomial{n - 1}" if n > 1 else None,
                contains=_NEO if n == 1 else (
                    _same(f"reduced_polynomial{n - 1}", *(f"C{i}0" for i in range(1, n))),))


@register("reduced_polynomial1", **_rpoly(1))
def reduced_polynomial1(I1, I2, C10):
    """Reduced polynomial, N = 1 (= neo-Hooke): W = C10 (I1 − 3)."""
    return C10 * (I1 - 3)


@register("reduced_polynomial2", **_rpoly(2))
def reduced_polynomial2(I1, I2, C10, C20):
    """Reduced polynomial, N = 2: W = C10 (I1 − 3) + C20 (I1 − 3)²."""
    return C10 * (I1 - 3) + C20 * (I1 - 3) ** 2


@register("reduced_polynomial3", **_rpoly(3))
def reduced_polynomial3(I1, I2, C10, C20, C30):
    """Reduced polynomial, N = 3 (= Yeoh): W = Σ_{i=1..3} Ci0 (I1 − 3)^i."""
    return C10 * (I1 - 3) + C20 * (I1 - 3) ** 2 + C30 * (I1 - 3) ** 3


@register("reduced_polynomial4", **_rpoly(4))
def reduced_polynomial4(I1, I2, C10, C20, C30, C40):
    """Reduced polynomial, N = 4: W = Σ_{i=1..4} Ci0 (I1 − 3)^i."""
    x = I1 - 3
    return C10 * x + C20 * x**2 + C30 * x**3 + C40 * x**4


@register("reduced_polynomial5", **_rpoly(5))
def reduced_polynomial5(I1, I2, C10, C20, C30, C40, C50):
    """Reduced polynomial, N = 5: W = Σ_{i=1..5} Ci0 (I1 − 3)^i."""
    x = I1 - 3
    return C10 * x + C20 * x**2 + C30 * x**3 + C40 * x**4 + C50 * x**5


@register("reduced_polynomial6", **_rpoly(6))
def reduced_polynomial6(I1, I2, C10, C20, C30, C40, C50, C60):
    """Reduced polynomial, N = 6 (the solvers' maximum): W = Σ_{i=1..6} Ci0 (I1 − 3)^i."""
    x = I1 - 3
    return C10 * x + C20 * x**2 + C30 * x**3 + C40 * x**4 + C50 * x**5 + C60 * x**6


# -------------------------------------------------------------- Arruda–Boyce
#: The five coefficients of the inverse-Langevin series (the solvers' form, docs/theory.md §2)
_AB_C = (1 / 2, 1 / 20, 11 / 1050, 19 / 7000, 519 / 673750)


def _ab_dW(I1, I2, mu, lambda_m):
    """∂W/∂I1 = μ Σ_i i C_i I1^(i−1) / λm^(2i−2), ∂W/∂I2 = 0."""
    w1 = sum(i * c * I1 ** (i - 1) / lambda_m ** (2 * i - 2) for i, c in enumerate(_AB_C, 1))
    return mu * w1, 0.0 * I1


def _ab_mu0(mu, lambda_m):
    """μ0 = μ (1 + 3/(5λm²) + 99/(175λm⁴) + 513/(875λm⁶) + 42039/(67375λm⁸))."""
    b = 1.0 / lambda_m**2
    return mu * (1 + 3 / 5 * b + 99 / 175 * b**2 + 513 / 875 * b**3 + 42039 / 67375 * b**4)


@register("arruda_boyce", units=("MPa", "1"), bounds=(_POS, (1.0, math.inf)),
          derivatives=_ab_dW, mu0=_ab_mu0, example=(0.1, 3.0), linear_params=("mu",))
def arruda_boyce(I1, I2, mu, lambda_m):
    """Arruda–Boyce (the solvers' 5-term form): W = μ Σ_{i=1..5} C_i/λm^(2i−2) (I1^i − 3^i).

    C = 1/2, 1/20, 11/1050, 19/7000, 519/673750; λm is the locking stretch (λm → ∞
    gives neo-Hooke with C10 = μ/2); μ0 = μ (1 + 3/(5λm²) + 99/(175λm⁴) + ...).
    """
    return mu * sum(c / lambda_m ** (2 * i - 2) * (I1**i - 3**i) for i, c in enumerate(_AB_C, 1))


# ---------------------------------------------------------------------- Gent
def _gent_dW(I1, I2, mu, Jm):
    """∂W/∂I1 = μ / (2 (1 − (I1 − 3)/Jm)); NaN at and past the locking limit I1 − 3 = Jm."""
    d = 1 - (I1 - 3) / Jm
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(d > 0, mu / (2 * d), np.nan), 0.0 * I1


@register("gent", units=("MPa", "1"), bounds=(_POS, _POS), derivatives=_gent_dW,
          mu0=lambda mu, Jm: mu, example=(0.1, 10.0), linear_params=("mu",))
def gent(I1, I2, mu, Jm):
    """Gent: W = −μ Jm/2 ln(1 − (I1 − 3)/Jm); μ0 = μ, locking at I1 − 3 = Jm."""
    return -mu * Jm / 2 * np.log(1 - (I1 - 3) / Jm)


# ------------------------------------------------------------ Van der Waals
def _vdw_dW(I1, I2, mu, lambda_m, a, beta):
    """dW/dĨ = μ (1/(2(1 − η)) − a/2 √((Ĩ − 3)/2)); ∂W/∂I1 = (1 − β) dW/dĨ, ∂W/∂I2 = β dW/dĨ."""
    x = np.maximum((1 - beta) * (I1 - 3) + beta * (I2 - 3), 0.0)  # Ĩ − 3 ≥ 0 (rounding)
    with np.errstate(divide="ignore", invalid="ignore"):
        eta = np.sqrt(x / (lambda_m**2 - 3))
        dW = np.where(eta < 1, mu * (0.5 / (1 - eta) - a / 2 * np.sqrt(x / 2)), np.nan)
    return (1 - beta) * dW, beta * dW


@register("van_der_waals", units=("MPa", "1", "1", "1"),
          bounds=(_POS, (math.sqrt(3.0), math.inf), _POS, (0.0, 1.0)), derivatives=_vdw_dW,
          mu0=lambda mu, lambda_m, a, beta: mu, example=(0.1, 4.0, 0.1, 0.3),
          linear_params=("mu",))
def van_der_waals(I1, I2, mu, lambda_m, a, beta):
    """Van der Waals (Kilian), with Ĩ = (1 − β) I1 + β I2, η = √((Ĩ − 3)/(λm² − 3)):

    W = μ [−(λm² − 3) (ln(1 − η) + η) − 2/3 a ((Ĩ − 3)/2)^(3/2)];  μ0 = μ.
    """
    x = (1 - beta) * (I1 - 3) + beta * (I2 - 3)
    eta = np.sqrt(x / (lambda_m**2 - 3))
    return mu * (-(lambda_m**2 - 3) * (np.log(1 - eta) + eta) - 2 / 3 * a * (x / 2) ** 1.5)
