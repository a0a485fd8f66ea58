"""The deformation of a curve: its name, its driving paths and the signs its data must have.

``Curve(deformation=...)`` takes a registered test (docs/modes.md): its record
(:class:`vhfit.modes.Deformation`) says whether it prescribes a second stretch, is
driven by an amount of shear, has a second loaded direction and a stress of known
sign, and what labs call it. These functions read the mode's arguments at the front
door — a stretch where an amount of
shear is meant, a missing or stray second stretch, a stress whose sign contradicts the
mode — with one-line messages that name the curve and the fix.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from vhfit._words import setting
from vhfit.data._errors import DataError, _Where
from vhfit.modes import (
    deformation_named,
    get_deformation,
    registered_deformations,
    with_second_stretch,
    with_two_directions,
)


def _deformation_name(text: Any) -> str | None:
    """The deformation a label names (``"pure shear"`` -> ``"planar"``), or None: the
    names and aliases of the records (:func:`vhfit.modes.deformation_named`)."""
    return deformation_named(text)


def _implied_deformation(*, second: bool, shear: bool) -> str:
    """The test a table's columns imply when nothing names it: the first registered one
    with a second prescribed stretch (a second stretch column) or driven by shear (an
    amount-of-shear column) as they say, uniaxial when they say neither."""
    return next(n for n in registered_deformations()
                if (get_deformation(n).second_stretch, get_deformation(n).shear)
                == (second, shear))


def _is_shear(name: str | None) -> bool:
    """Whether a (known) test is driven by an amount of shear."""
    return name is not None and get_deformation(name).shear


def _known() -> str:
    """The registered tests, quoted, for error messages."""
    return ", ".join(map(repr, registered_deformations()))


def _check_deformation(deformation: Any, where: _Where) -> str:
    """The canonical deformation name, or a DataError listing the valid ones."""
    name = _deformation_name(deformation)
    if name is None:
        raise DataError(
            f"{where()}: {setting(f'deformation={deformation!r}', f'--deformation {deformation}')}"
            " is not a test vhfit knows: use one of "
            f"{_known()}"
        )
    return name


def _driving_strain(strain: Any, stretch: Any, deformation: str, where: _Where) -> Any:
    """``strain`` (λ − 1, or γ in simple shear) from ``strain=`` or ``stretch=``."""
    if get_deformation(deformation).shear and stretch is not None:
        raise DataError(
            f"{where()}: {deformation.replace('_', ' ')} is driven by the amount of shear γ, "
            "not a stretch: "
            f"give {setting('strain=γ', 'γ')} (a column 'gamma' or 'shear_strain'), not "
            + setting("stretch=", "a stretch")
        )
    if strain is not None and stretch is not None:
        both = setting("strain= and stretch=", "a strain and a stretch")
        raise DataError(f"{where()}: both {both} given: give one of them")
    if strain is None and stretch is None:
        raise DataError(f"{where()}: no {setting('strain= or stretch=', 'strain or stretch')} "
                        "given: give the deformation of each sample")
    if strain is not None:
        return strain
    lam = where.array("stretch", stretch)
    if (lam <= 0).any():
        k = int(np.flatnonzero(lam <= 0)[0])
        raise DataError(f"{where(k)}: stretch = {lam[k]:g} is not > 0: give stretch "
                        f"λ = L/L0 (1 at rest), or {setting('strain=', 'a strain')} for λ − 1")
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
    test = get_deformation(deformation)
    if test.second_stretch:
        if strain2 is None and stretch2 is None:
            tied = [n for n in with_two_directions() if n not in with_second_stretch()]
            raise DataError(
                f"{where()}: a {deformation} curve needs its second stretch at each sample: "
                "give " + setting("stretch2= (λ2) or strain2= (λ2 − 1)",
                                  "a stretch2 (λ2) or strain2 (λ2 − 1) column")
                + "".join(f", or use {setting(f'deformation={n!r}', f'--deformation {n}')} "
                          "if λ2 = λ1" for n in tied[:1])
            )
        if strain2 is not None and stretch2 is not None:
            both = setting("strain2= and stretch2=", "a strain2 and a stretch2")
            raise DataError(f"{where()}: both {both} given: give one of them")
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
                only = " or ".join(f"deformation={n!r}" for n in with_second_stretch())
                raise DataError(
                    f"{where()}: {what}= is only for {only} (this curve is "
                    f"{deformation!r}): drop it, or say {only}"
                )
        e2 = None
    s2 = None
    if stress2 is not None:
        if test.directions < 2:
            raise DataError(
                f"{where()}: {setting('stress2=', 'a stress2 column')} is the stress in the "
                f"second loaded direction, which only "
                f"{' and '.join(map(repr, with_two_directions()))} tests have: drop it, or "
                "correct " + setting("deformation=", "--deformation")
            )
        s2 = where.array("stress2", stress2, n)
    return e2, s2


def _check_mode_signs(
    eps: np.ndarray, sig: np.ndarray, deformation: str, mode: str, keep: np.ndarray,
    where: _Where,
) -> None:
    """Tests whose record says ``signed``: the stress has the sign of the strain.

    Stretching a sheet (λ > 1) pulls on it, and a shear γ > 0 needs a shear stress > 0,
    whatever the law; a contradiction at the largest |stress| is a mistaken column
    (a thickness stretch 1/λ², a stress of the wrong sign), never silently mended.
    """
    test = get_deformation(deformation)
    if not test.signed or mode == "mixed":
        return
    k = int(np.argmax(np.abs(sig)))
    sgn = 1.0 if mode == "tension" else -1.0
    if sig[k] * sgn >= 0:
        return
    if test.shear:
        fix = "γ and the shear stress have the same sign: negate one of them"
    else:
        fix = ("a sheet stretched to λ > 1 is in tension, and at λ < 1 in compression: give "
               "the stretch of the loaded direction (not the thickness stretch), or correct "
               "the stress's sign")
    raise DataError(
        f"{where(keep[k])}: stress = {sig[k]:g} (the largest in magnitude) has the wrong "
        f"sign for {deformation} at strain {eps[k]:g}: {fix}"
    )
