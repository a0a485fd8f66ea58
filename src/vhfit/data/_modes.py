"""The deformation of a curve: its name, its driving paths and the signs its data must have.

``Curve(deformation=...)`` takes one of :data:`vhfit.history.DEFORMATIONS`
(docs/modes.md): the uniaxial test of the paper, equibiaxial and planar (pure shear)
tension of a sheet, a general biaxial test (λ1 and λ2 both prescribed, one or both
nominal stresses measured) and simple shear (amount of shear γ, shear stress). These
functions read the mode's arguments at the front door — a stretch where an amount of
shear is meant, a missing or stray second stretch, a stress whose sign contradicts the
mode — with one-line messages that name the curve and the fix.
"""

from __future__ import annotations

import re
from typing import Any

import numpy as np

from vhfit.data._errors import DataError, _Where
from vhfit.history import DEFORMATIONS
from vhfit.modes import TWO_DIRECTIONS

# Names labs write, as tokens: words that say nothing about the kinematics ("tension",
# "test") are dropped before the lookup, so "uniaxial_tension_compression" is uniaxial.
_ALIASES = {
    "uniaxial": "uniaxial", "ut": "uniaxial", "uc": "uniaxial",
    "equibiaxial": "equibiaxial", "equi_biaxial": "equibiaxial", "eb": "equibiaxial",
    "et": "equibiaxial", "ebt": "equibiaxial", "balanced_biaxial": "equibiaxial",
    "planar": "planar", "pure_shear": "planar", "ps": "planar", "pt": "planar",
    "biaxial": "biaxial", "general_biaxial": "biaxial",
    "simple_shear": "simple_shear", "shear": "simple_shear", "ss": "simple_shear",
}
_NOISE_WORDS = {"tension", "tensile", "compression", "compressive", "test", "tests",
                "loading", "mode"}
# modes whose measured stress has the sign of the driving strain for any sensible law
_SIGNED = ("equibiaxial", "planar", "simple_shear")


def _deformation_name(text: Any) -> str | None:
    """The deformation a label names (``"pure shear"`` -> ``"planar"``), or None."""
    if not isinstance(text, str):
        return None
    toks = [t for t in re.split(r"[\s_\-/]+", text.strip().lower()) if t]
    return _ALIASES.get("_".join(t for t in toks if t not in _NOISE_WORDS))


def _check_deformation(deformation: Any, where: _Where) -> str:
    """The canonical deformation name, or a DataError listing the valid ones."""
    name = _deformation_name(deformation)
    if name is None:
        raise DataError(
            f"{where()}: deformation={deformation!r} is not a test vhfit knows: use one of "
            f"{', '.join(map(repr, DEFORMATIONS))}"
        )
    return name


def _driving_strain(strain: Any, stretch: Any, deformation: str, where: _Where) -> Any:
    """``strain`` (λ − 1, or γ in simple shear) from ``strain=`` or ``stretch=``."""
    if deformation == "simple_shear" and stretch is not None:
        raise DataError(
            f"{where()}: simple shear is driven by the amount of shear γ, not a stretch: "
            "give strain=γ (a column 'gamma' or 'shear_strain'), not stretch="
        )
    if strain is not None and stretch is not None:
        raise DataError(f"{where()}: both strain= and stretch= given: give one of them")
    if strain is None and stretch is None:
        raise DataError(f"{where()}: no strain= or stretch= given: give the deformation "
                        "of each sample")
    if strain is not None:
        return strain
    lam = where.array("stretch", stretch)
    if (lam <= 0).any():
        k = int(np.flatnonzero(lam <= 0)[0])
        raise DataError(f"{where(k)}: stretch = {lam[k]:g} is not > 0: give stretch "
                        "λ = L/L0 (1 at rest), or strain= for λ − 1")
    return lam - 1.0


def _mode_name(deformation: str, strain_rate: Any, time: Any) -> str:
    """The name of an unnamed curve of another test than the paper's uniaxial ramp."""
    if strain_rate is None and time is None:
        return f"{deformation} (equilibrium)"
    try:
        return f"{deformation} {float(strain_rate):g} 1/s"
    except (TypeError, ValueError):
        return deformation


def _second_path(
    deformation: str, strain2: Any, stretch2: Any, stress2: Any, n: int, where: _Where
) -> tuple[np.ndarray | None, np.ndarray | None]:
    """(λ2 − 1, nominal stress in direction 2) of each sample, or None where they do not
    apply; errors for a missing, doubled or stray second path."""
    if deformation == "biaxial":
        if strain2 is None and stretch2 is None:
            raise DataError(
                f"{where()}: a biaxial curve needs its second stretch at each sample: give "
                "stretch2= (λ2) or strain2= (λ2 − 1), or use deformation='equibiaxial' if "
                "λ2 = λ1"
            )
        if strain2 is not None and stretch2 is not None:
            raise DataError(f"{where()}: both strain2= and stretch2= given: give one of them")
        if strain2 is not None:
            e2 = where.array("strain2", strain2, n)
        else:
            e2 = where.array("stretch2", stretch2, n) - 1.0
        if (e2 <= -1.0).any():
            k = int(np.flatnonzero(e2 <= -1.0)[0])
            raise DataError(f"{where(k)}: stretch2 = {e2[k] + 1:g} is not > 0: give λ2 > 0")
    else:
        for what, v in (("strain2", strain2), ("stretch2", stretch2)):
            if v is not None:
                raise DataError(
                    f"{where()}: {what}= is only for deformation='biaxial' (this curve is "
                    f"{deformation!r}): drop it, or say deformation='biaxial'"
                )
        e2 = None
    s2 = None
    if stress2 is not None:
        if deformation not in TWO_DIRECTIONS:
            raise DataError(
                f"{where()}: stress2= is the stress in the second loaded direction, which "
                f"only {' and '.join(map(repr, TWO_DIRECTIONS))} tests have: drop it, or "
                "correct deformation="
            )
        s2 = where.array("stress2", stress2, n)
    return e2, s2


def _check_mode_signs(
    eps: np.ndarray, sig: np.ndarray, deformation: str, mode: str, keep: np.ndarray,
    where: _Where,
) -> None:
    """Equibiaxial, planar and simple shear: the stress has the sign of the strain.

    Stretching a sheet (λ > 1) pulls on it, and a shear γ > 0 needs a shear stress > 0,
    whatever the law; a contradiction at the largest |stress| is a mistaken column
    (a thickness stretch 1/λ², a stress of the wrong sign), never silently mended.
    """
    if deformation not in _SIGNED or mode == "mixed":
        return
    k = int(np.argmax(np.abs(sig)))
    sgn = 1.0 if mode == "tension" else -1.0
    if sig[k] * sgn >= 0:
        return
    if deformation == "simple_shear":
        fix = "γ and the shear stress have the same sign: negate one of them"
    else:
        fix = ("a sheet stretched to λ > 1 is in tension, and at λ < 1 in compression: give "
               "the stretch of the loaded direction (not the thickness stretch), or correct "
               "the stress's sign")
    raise DataError(
        f"{where(keep[k])}: stress = {sig[k]:g} (the largest in magnitude) has the wrong "
        f"sign for {deformation} at strain {eps[k]:g}: {fix}"
    )
