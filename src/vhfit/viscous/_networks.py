"""The :class:`Network` and :class:`NetworkModel` records and their validation."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vhfit import hyperelastic
from vhfit.viscous import _integrate, flows

__all__ = ["Network", "NetworkModel"]

@dataclass(frozen=True)
class Network:
    """One viscous network: a stiffness ratio times the model's law, and its flow.

    Parameters
    ----------
    flow : str
        A registered flow (:mod:`vhfit.viscous.flows`), any accepted spelling; kept as its
        canonical name.
    ratio : float
        s_k, the card's SRATIO: the share of the instantaneous law this network carries
        (0 < s_k; Σ s_k < 1 over a model's networks).
    constants : tuple of float
        The flow's constants in :attr:`~vhfit.viscous.flows.Flow.param_names` order, in
        solver units (MPa, s).

    Examples
    --------
    >>> Network("STRAIN", 0.5, (1e-5, 1.0, -0.5)).flow
    'strain'
    >>> Network("strain", -0.5, (1e-5, 1.0, -0.5))
    Traceback (most recent call last):
    ...
    ValueError: network ratio s = -0.5 must be a positive finite number (SRATIO)
    """

    flow: str
    ratio: float
    constants: tuple[float, ...]

    def __post_init__(self) -> None:
        f = flows.get(self.flow)
        s = float(self.ratio)
        if not (math.isfinite(s) and s > 0.0):
            raise ValueError(f"network ratio s = {self.ratio!r} must be a positive finite "
                             "number (SRATIO)")
        c = f.check(np.atleast_1d(np.asarray(self.constants, dtype=np.float64)))
        object.__setattr__(self, "flow", f.name)
        object.__setattr__(self, "ratio", s)
        object.__setattr__(self, "constants", tuple(float(x) for x in c))


@dataclass(frozen=True)
class NetworkModel:
    """A hyperelastic law with its equilibrium network and K viscous networks (PRF).

    Parameters
    ----------
    law : str
        A registered hyperelastic law (:mod:`vhfit.hyperelastic`).
    law_params : tuple of float
        The law's *instantaneous* constants (``MODULI=INSTANTANEOUS``): the
        equilibrium network carries (1 − Σ s_k) W, network k carries s_k W(F_e,k).
    networks : tuple of Network
        One or more viscous networks.

    Examples
    --------
    >>> n = Network("bergstrom_boyce", 0.6, (1.0, 1.0, 0.0, 0.01))
    >>> NetworkModel("neo_hooke", (0.5,), (n, n))
    Traceback (most recent call last):
    ...
    ValueError: network ratios sum to 1.2, not < 1: the equilibrium network keeps 1 - Σ s_k > 0
    """

    law: str
    law_params: tuple[float, ...]
    networks: tuple[Network, ...]

    def __post_init__(self) -> None:
        h = hyperelastic.get(self.law)
        p = h.check(np.atleast_1d(np.asarray(self.law_params, dtype=np.float64)))
        nets = tuple(self.networks) if not isinstance(self.networks, Network) else (
            self.networks,)
        if not nets:
            raise ValueError("a network model needs at least one viscous network "
                             "(without one it is the hyperelastic law alone)")
        for n in nets:
            if not isinstance(n, Network):
                raise ValueError(f"networks must be Network records, got {type(n).__name__}")
        total = sum(n.ratio for n in nets)
        if not total < 1.0:
            raise ValueError(f"network ratios sum to {total:g}, not < 1: the equilibrium "
                             "network keeps 1 - Σ s_k > 0")
        object.__setattr__(self, "law", h.name)
        object.__setattr__(self, "law_params", tuple(float(x) for x in p))
        object.__setattr__(self, "networks", nets)

    def describe(self) -> str:
        """One line: the law and its networks' flows.

        Examples
        --------
        >>> n = Network("strain", 0.5, (1e-5, 1.0, -0.5))
        >>> NetworkModel("arruda_boyce", (20.0, 7.0), (n,)).describe()
        'arruda_boyce + 1 network (strain)'
        """
        k = len(self.networks)
        names = ", ".join(n.flow for n in self.networks)
        return f"{self.law} + {k} network{'s' if k != 1 else ''} ({names})"

    def stress(self, time, stretch, *, deformation: str = "uniaxial", stretch2=None,
               measure: str = "true") -> np.ndarray:
        """The stress in the loading direction along a stretch history (strain control).

        Parameters
        ----------
        time : array_like, shape (m,)
            Non-decreasing times (s); the stretch is linear in time between them.
        stretch : array_like, shape (m,)
            λ1 at each time (loading, unloading, holds: any shape).
        deformation : {"uniaxial", "equibiaxial", "planar", "biaxial"}
        stretch2 : array_like, shape (m,), optional
            λ2 of a general biaxial test (``deformation="biaxial"``).
        measure : {"true", "engineering"}
            Cauchy stress σ11, or nominal stress σ11 / λ1.

        Returns
        -------
        ndarray, shape (m,)
        """
        return _integrate.model_stress(self, time, stretch, deformation=deformation,
                                       stretch2=stretch2, measure=measure)

    def creep(self, stress, time, *, deformation: str = "uniaxial",
              measure: str = "true") -> np.ndarray:
        """The stretch λ1 under a load applied at once at t = 0 and then held (creep).

        At t = 0 the response is the instantaneous one (every network elastic, λ_cr = 1,
        as a static step of the solver gives it); then the load is held and the networks
        creep.

        Parameters
        ----------
        stress : float
            The held stress in the loading direction (MPa).
        time : array_like, shape (m,)
            Output times (s), non-decreasing, ≥ 0.
        deformation : {"uniaxial", "equibiaxial", "planar"}
        measure : {"true", "engineering"}
            Whether ``stress`` is a Cauchy (true) stress, held as the area shrinks, or a
            nominal (engineering) stress, force per original area.

        Returns
        -------
        ndarray, shape (m,)
        """
        return _integrate.model_creep(self, stress, time, deformation=deformation,
                                      measure=measure)
