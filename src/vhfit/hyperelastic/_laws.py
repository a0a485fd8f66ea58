"""The built-in strain energies, registered by name when the package is imported."""

from __future__ import annotations

import math

from vhfit.hyperelastic._registry import register

_POS = (0.0, math.inf)
_FREE = (-math.inf, math.inf)


def _mr_dW(I1, I2, C10, C01):
    return C10, C01


@register("mooney_rivlin", bounds=(_FREE, _FREE), derivatives=_mr_dW, linear=True,
          example=(0.1, 0.05))
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
          example=(0.1, -0.01, 0.001))
def yeoh(I1, I2, C10, C20, C30):
    """Yeoh: W = C10 (I1 − 3) + C20 (I1 − 3)² + C30 (I1 − 3)³."""
    return C10 * (I1 - 3) + C20 * (I1 - 3) ** 2 + C30 * (I1 - 3) ** 3


@register("polynomial2", linear=True, example=(0.1, 0.05, 0.01, 0.0, 0.0))
def polynomial2(I1, I2, C10, C01, C20, C11, C02):
    """Generalised polynomial of order 2: W = Σ_{i+j≤2} Cij (I1 − 3)^i (I2 − 3)^j."""
    x, y = I1 - 3, I2 - 3
    return C10 * x + C01 * y + C20 * x**2 + C11 * x * y + C02 * y**2


@register("polynomial3", linear=True,
          example=(0.1, 0.05, 0.01, 0.0, 0.0, 0.001, 0.0, 0.0, 0.0))
def polynomial3(I1, I2, C10, C01, C20, C11, C02, C30, C21, C12, C03):
    """Generalised polynomial of order 3: W = Σ_{i+j≤3} Cij (I1 − 3)^i (I2 − 3)^j."""
    x, y = I1 - 3, I2 - 3
    return (C10 * x + C01 * y + C20 * x**2 + C11 * x * y + C02 * y**2
            + C30 * x**3 + C21 * x**2 * y + C12 * x * y**2 + C03 * y**3)


def _ogden_term(l1, l2, l3, mu, alpha):
    return 2 * mu / alpha**2 * (l1**alpha + l2**alpha + l3**alpha - 3)


_OG = dict(units=("MPa", "1"), bounds=(_FREE, _FREE))


@register("ogden", units=_OG["units"], bounds=_OG["bounds"], example=(0.1, 2.0),
          mu0=lambda mu1, a1: mu1)
def ogden(l1, l2, l3, mu1, alpha1):
    """Ogden, one term (Abaqus form): W = 2μ1/α1² (λ1^α1 + λ2^α1 + λ3^α1 − 3); μ0 = μ1."""
    return _ogden_term(l1, l2, l3, mu1, alpha1)


@register("ogden2", units=_OG["units"] * 2, bounds=_OG["bounds"] * 2,
          example=(0.1, 2.0, 0.01, -2.0), mu0=lambda m1, a1, m2, a2: m1 + m2)
def ogden2(l1, l2, l3, mu1, alpha1, mu2, alpha2):
    """Ogden, two terms: W = Σ_p 2μp/αp² (λ1^αp + λ2^αp + λ3^αp − 3)."""
    return _ogden_term(l1, l2, l3, mu1, alpha1) + _ogden_term(l1, l2, l3, mu2, alpha2)


@register("ogden3", units=_OG["units"] * 3, bounds=_OG["bounds"] * 3,
          example=(0.1, 2.0, 0.01, -2.0, 0.001, 5.0),
          mu0=lambda m1, a1, m2, a2, m3, a3: m1 + m2 + m3)
def ogden3(l1, l2, l3, mu1, alpha1, mu2, alpha2, mu3, alpha3):
    """Ogden, three terms: W = Σ_p 2μp/αp² (λ1^αp + λ2^αp + λ3^αp − 3)."""
    return (_ogden_term(l1, l2, l3, mu1, alpha1) + _ogden_term(l1, l2, l3, mu2, alpha2)
            + _ogden_term(l1, l2, l3, mu3, alpha3))
