"""Prony series in the paper's parameterisation (docs/theory.md §3) and its conversions.

The paper's Prony moduli G_i are uniaxial (Young's-type) moduli beside the long-term
uniaxial modulus E∞ = 3 μ0 of the hyperelastic law:

* G0 = E∞ + Σ G_i,  g_i = G_i / G0,  g∞ = 1 − Σ g_i = E∞ / G0;
* small-strain relaxation modulus E(t) = E∞ + Σ G_i exp(−t/τ_i), and under a
  sinusoidal strain of angular frequency ω the storage and loss moduli
  E′(ω) = E∞ + Σ G_i (ωτ_i)²/(1 + (ωτ_i)²), E″(ω) = Σ G_i ωτ_i/(1 + (ωτ_i)²)
  (the generalised Maxwell model; shear moduli are E/3 for an incompressible solid).

FE solvers expect the dimensionless (g_i, τ_i); they differ in whether the hyperelastic
constants they are given are long-term (relaxed) or instantaneous (= long-term / g∞).
These helpers convert between the two.
"""

from __future__ import annotations

import numpy as np

from vhfit._linear import loss_shape, relaxation_shape, storage_shape
from vhfit.viscous import ParamLayout

__all__ = [
    "prony_g",
    "from_dimensionless",
    "relaxation_modulus",
    "storage_modulus",
    "loss_modulus",
    "check_prony",
]


def check_prony(G, tau) -> tuple[np.ndarray, np.ndarray]:
    """Validate Prony moduli G_i ≥ 0 (MPa) and relaxation times τ_i > 0 (s).

    Examples
    --------
    >>> G, tau = check_prony([30.0, 1.0], [1e-4, 1.0])
    >>> G.tolist(), tau.tolist()
    ([30.0, 1.0], [0.0001, 1.0])
    >>> check_prony([1.0], [0.0])
    Traceback (most recent call last):
    ...
    ValueError: tau1 = 0.0: relaxation times must be > 0 s
    """
    G = np.atleast_1d(np.asarray(G, dtype=np.float64))
    tau = np.atleast_1d(np.asarray(tau, dtype=np.float64))
    if G.shape != tau.shape or G.ndim != 1:
        raise ValueError(
            f"G and tau need one value per Prony term, got shapes {G.shape} and {tau.shape}"
        )
    for i, (g, t) in enumerate(zip(G, tau)):
        if not (np.isfinite(g) and g >= 0):
            raise ValueError(f"{ParamLayout.amplitude_name(i)} = {float(g)!r}: Prony moduli "
                             "must be finite and >= 0 MPa")
        if not (t > 0) or np.isnan(t):
            raise ValueError(f"{ParamLayout.time_name(i)} = {float(t)!r}: relaxation times "
                             "must be > 0 s")
    return G, tau


def prony_g(E_inf: float, G) -> tuple[np.ndarray, float]:
    """Dimensionless Prony weights from the paper's moduli.

    Parameters
    ----------
    E_inf : float
        Long-term uniaxial modulus E∞ = 3 μ0 of the hyperelastic law, MPa (> 0).
    G : array_like
        Prony moduli G_i, MPa.

    Returns
    -------
    g : ndarray
        g_i = G_i / G0 with G0 = E∞ + Σ G_i.
    g_inf : float
        g∞ = E∞ / G0 = 1 − Σ g_i.

    Examples
    --------
    >>> g, g_inf = prony_g(1.0, [1.0, 2.0])
    >>> g, g_inf
    (array([0.25, 0.5 ]), 0.25)
    """
    G = np.asarray(G, dtype=np.float64)
    if not E_inf > 0:
        raise ValueError(
            f"E_inf = {E_inf!r}: the long-term modulus must be > 0 for g_i to exist "
            "(all hyperelastic constants zero leaves g_inf = 0, which FE solvers reject)"
        )
    G0 = E_inf + G.sum()
    return G / G0, float(E_inf / G0)


def from_dimensionless(g, *, E_inf: float | None = None, E_0: float | None = None):
    """Prony moduli G_i from dimensionless weights g_i.

    Give exactly one of the long-term modulus ``E_inf`` (then G0 = E∞ / g∞) or the
    instantaneous modulus ``E_0`` (= G0).

    Returns
    -------
    G : ndarray
        Moduli G_i = g_i G0, MPa.
    E_inf : float
        The long-term modulus E∞ = g∞ G0.

    Examples
    --------
    >>> G, E_inf = from_dimensionless([0.25, 0.5], E_inf=1.0)
    >>> G, E_inf
    (array([1., 2.]), 1.0)
    """
    g = np.asarray(g, dtype=np.float64)
    g_inf = 1.0 - g.sum()
    if (g < 0).any() or not g_inf > 0:
        raise ValueError(f"g = {g.tolist()}: weights must be >= 0 with sum(g) < 1")
    if (E_inf is None) == (E_0 is None):
        raise ValueError("give exactly one of E_inf (long-term) or E_0 (instantaneous)")
    G0 = E_inf / g_inf if E_inf is not None else float(E_0)
    return g * G0, float(g_inf * G0)


def relaxation_modulus(t, E_inf: float, G, tau) -> np.ndarray:
    """Small-strain relaxation modulus E(t) = E∞ + Σ G_i exp(−t/τ_i).

    Examples
    --------
    >>> float(relaxation_modulus(0.0, 1.0, [2.0], [1.0]))
    3.0
    """
    t = np.asarray(t, dtype=np.float64)
    G, tau = check_prony(G, tau)
    return E_inf + np.sum(G * relaxation_shape(t[..., None], tau), axis=-1)


def _omega_tau(omega, tau) -> np.ndarray:
    omega = np.asarray(omega, dtype=np.float64)
    if not np.all(omega > 0):
        bad = omega.reshape(-1)[np.flatnonzero(~(omega.reshape(-1) > 0))[0]]
        raise ValueError(f"omega = {float(bad)!r}: angular frequencies must be > 0 rad/s "
                         "(omega = 2 pi f)")
    return omega[..., None] * tau


def storage_modulus(omega, E_inf: float, G, tau) -> np.ndarray:
    """Small-strain storage modulus E′(ω) = E∞ + Σ G_i (ωτ_i)² / (1 + (ωτ_i)²).

    Parameters
    ----------
    omega : array_like
        Angular frequencies ω = 2πf, rad/s (> 0).
    E_inf : float
        Long-term modulus E∞ = 3 μ0 of the hyperelastic law, MPa.
    G, tau : array_like
        Prony moduli G_i (MPa) and relaxation times τ_i (s).

    Returns
    -------
    ndarray
        E′ at each ω, MPa (the shape of ``omega``).

    Examples
    --------
    >>> float(storage_modulus(1.0, 1.0, [2.0], [1.0]))   # 1 + 2 · 1/2
    2.0
    """
    G, tau = check_prony(G, tau)
    return E_inf + np.sum(G * storage_shape(_omega_tau(omega, tau)), axis=-1)


def loss_modulus(omega, E_inf: float, G, tau) -> np.ndarray:
    """Small-strain loss modulus E″(ω) = Σ G_i ωτ_i / (1 + (ωτ_i)²).

    ``E_inf`` (MPa) does not enter; it is an argument so that the three responses
    share one signature. Arguments as :func:`storage_modulus`.

    Examples
    --------
    >>> float(loss_modulus(1.0, 1.0, [2.0], [1.0]))   # 2 · 1/2
    1.0
    """
    G, tau = check_prony(G, tau)
    return np.sum(G * loss_shape(_omega_tau(omega, tau)), axis=-1)
