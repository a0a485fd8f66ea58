"""Small-strain (linear viscoelastic) loads and their evaluation plan in a batch.

In the small-strain limit the model of docs/theory.md §4 is the generalised Maxwell
model E(t) = E∞ + Σ G_i exp(−t/τ_i) (docs/theory.md §3, §10), so a frequency sweep and a
relaxation test are linear in (E∞, G_i) for fixed τ:

* storage modulus E′(ω) = E∞ + Σ G_i (ωτ_i)² / (1 + (ωτ_i)²),
* loss modulus E″(ω) = Σ G_i ωτ_i / (1 + (ωτ_i)²),
* relaxation modulus E(t) = E∞ + Σ G_i exp(−t/τ_i).

:class:`LinearLoad` is what such a test asks of the model (the angular frequencies of a
sweep, whose outputs are its storage then its loss moduli, or the times of a relaxation
test); :class:`LinearPlan` lays the loads of a :class:`vhfit.model.Batch` out and writes
their moduli, or their columns per unit modulus, at the batch's positions.
"""

from __future__ import annotations

import numpy as np

__all__ = ["LinearLoad", "LinearPlan", "storage_shape", "loss_shape", "relaxation_shape"]


def storage_shape(x: np.ndarray) -> np.ndarray:
    """x² / (1 + x²) for x = ωτ > 0: a unit Maxwell branch's storage modulus.

    Written 1 / (1 + x⁻²) so that neither x → 0 nor x → ∞ overflows.
    """
    with np.errstate(divide="ignore", over="ignore"):
        return 1.0 / (1.0 + 1.0 / (x * x))


def loss_shape(x: np.ndarray) -> np.ndarray:
    """x / (1 + x²) for x = ωτ > 0: a unit Maxwell branch's loss modulus.

    Written 1 / (x + 1/x), symmetric in x ↔ 1/x and free of overflow.
    """
    with np.errstate(divide="ignore", over="ignore"):
        return 1.0 / (x + 1.0 / x)


def relaxation_shape(t: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """exp(−t/τ): a unit Maxwell branch's relaxation modulus."""
    with np.errstate(divide="ignore", over="ignore", under="ignore"):
        return np.exp(-t / tau)


class LinearLoad:
    """A small-strain test: a frequency sweep or a relaxation test (E-type moduli, MPa).

    Parameters
    ----------
    kind : {"frequency", "relaxation"}
        A sweep's outputs are its storage moduli at ``x`` (angular frequencies, rad/s)
        followed by its loss moduli there; a relaxation test's are E(t) at ``x`` (s).
    x : array_like
        Angular frequencies (> 0) or times (≥ 0).

    Attributes
    ----------
    out_time : ndarray
        A time scale per output (1/ω of a sweep, t of a relaxation test), for the
        checks that compare relaxation times with the data's time window.
    duration : float
        The longest of them.

    Examples
    --------
    >>> load = LinearLoad("frequency", [1.0, 10.0])
    >>> load.out_time.tolist(), load.n_outputs
    ([1.0, 0.1, 1.0, 0.1], 4)
    """

    deformation = "uniaxial"  # E-type moduli: the small-strain limit of uniaxial tests
    is_equilibrium = False
    is_linear = True

    def __init__(self, kind: str, x) -> None:
        if kind not in ("frequency", "relaxation"):
            raise ValueError(f"kind = {kind!r}: choose 'frequency' or 'relaxation'")
        self.kind = kind
        self.x = np.array(x, dtype=np.float64).reshape(-1)
        if kind == "frequency":
            self.out_time = np.tile(1.0 / self.x, 2)
        else:
            self.out_time = self.x.copy()
        self.n_outputs = int(self.out_time.size)
        self.duration = float(np.max(self.out_time)) if self.n_outputs else 0.0
        self.out_loaded_stretch = np.ones(self.n_outputs)

    def columns(self, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Outputs per unit E∞ (n_out,) and per unit G_i (..., N, n_out) for τ (..., N)."""
        tau = np.asarray(tau, dtype=np.float64)[..., None]
        if self.kind == "frequency":
            n = self.x.size
            base = np.concatenate([np.ones(n), np.zeros(n)])
            x = self.x * tau
            h = np.concatenate([storage_shape(x), loss_shape(x)], axis=-1)
        else:
            base = np.ones(self.x.size)
            h = relaxation_shape(self.x, tau)
        return base, h


class LinearPlan:
    """The linear loads among a batch's histories and where their outputs go."""

    def __init__(self, histories, slices) -> None:
        self.loads = [(h, sl) for h, sl in zip(histories, slices)
                      if h.is_linear]

    def shape_columns(self, tau: np.ndarray, base: np.ndarray, h: np.ndarray) -> None:
        """Write each load's columns per unit modulus into ``base`` (P, n) and ``h`` (P, N, n)."""
        for load, sl in self.loads:
            b, c = load.columns(tau)
            base[:, sl] = b
            h[:, :, sl] = c

    def stress(self, E_inf: np.ndarray, G: np.ndarray, tau: np.ndarray, sig: np.ndarray) -> None:
        """Write the moduli E∞ b + Σ G_i h_i of parameter sets (P,), (P, N) into ``sig``."""
        with np.errstate(all="ignore"):  # invalid sets become +inf in the batch
            for load, sl in self.loads:
                b, c = load.columns(tau)
                sig[:, sl] = E_inf[:, None] * b + np.einsum("pn,pnk->pk", G, c)
