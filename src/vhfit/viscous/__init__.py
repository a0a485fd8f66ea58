"""Nonlinear viscoelasticity: the parallel rheological framework (PRF) of networks.

An equilibrium network carries (1 − Σ s_k) W(F) and each viscous network k carries
s_k W(F_e,k), F = F_e,k F_cr,k, W the model's hyperelastic law with its *instantaneous*
constants (``MODULI=INSTANTANEOUS``). Network k creeps by its flow rule
(:mod:`vhfit.viscous.flows`) at the equivalent rate ε̇_cr along its stress deviator:
D_cr = ε̇_cr (3/2) τ'_k / q̃_k, q̃_k the Mises equivalent of the network's deviatoric
Kirchhoff stress τ'_k (docs/theory.md, "Parallel rheological networks").

>>> from vhfit.viscous import Network, NetworkModel
>>> m = NetworkModel("neo_hooke", (0.5,), (Network("BERGSTROM", 0.5, (1.0, 1.0, 0.0, 0.01)),))
>>> m.describe()
'neo_hooke + 1 network (bergstrom_boyce)'
"""

from __future__ import annotations

from vhfit.viscous import flows
from vhfit.viscous._networks import Network, NetworkModel

__all__ = ["flows", "Network", "NetworkModel"]
