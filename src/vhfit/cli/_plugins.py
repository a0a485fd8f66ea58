"""Model plug-ins (entry points), model names and τ strategies as the commands see them."""

from __future__ import annotations

from typing import Any

from vhfit.cli._common import UsageError

__all__ = ["PLUGIN_GROUP", "load_plugins", "resolve_model_name", "tau_strategies"]

PLUGIN_GROUP = "vhfit.models"


def load_plugins(strict: bool = False) -> list[dict[str, Any]]:
    """Import the hyperelastic models that installed packages declare as plug-ins.

    A package registers models through the entry-point group ``vhfit.models``; each
    entry point names a module whose import registers models with
    :func:`vhfit.hyperelastic.register` (``gent = "mypkg.models"``), or a function
    with no required arguments that registers them when called
    (``gent = "mypkg.models:register_all"``).

    Parameters
    ----------
    strict : bool
        Raise if a plug-in fails to load (default: report it and go on).

    Returns
    -------
    list of dict
        One per entry point: ``name``, ``value``, ``distribution``, ``models`` (the
        model names it registered) and ``error`` (None, or the message).

    Examples
    --------
    >>> from vhfit.cli import load_plugins
    >>> all(set(p) >= {"name", "models", "error"} for p in load_plugins())
    True
    """
    import inspect
    from importlib.metadata import entry_points

    from vhfit import hyperelastic

    out = []
    for ep in entry_points(group=PLUGIN_GROUP):
        before = set(hyperelastic.available())
        info = {"name": ep.name, "value": ep.value, "models": [], "error": None,
                "distribution": None if ep.dist is None else ep.dist.name}
        try:
            obj = ep.load()
            if inspect.isfunction(obj) and not any(
                p.default is p.empty and p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)
                for p in inspect.signature(obj).parameters.values()
            ):
                obj()
        except Exception as exc:  # a broken plug-in must not break vhfit
            if strict:
                raise
            info["error"] = f"{type(exc).__name__}: {exc}"
        info["models"] = sorted(set(hyperelastic.available()) - before)
        out.append(info)
    return out


def resolve_model_name(name: str) -> str:
    """A registered model name, loading plug-ins if it is not (yet) known."""
    from vhfit import hyperelastic

    if name in hyperelastic.available():
        return name
    plugins = load_plugins()
    if name in hyperelastic.available():
        return name
    broken = [f"{p['name']} ({p['error']})" for p in plugins if p["error"]]
    hint = f"; plug-ins that failed to load: {', '.join(broken)}" if broken else ""
    raise UsageError(
        f"unknown model {name!r}: choose one of {', '.join(hyperelastic.available())} "
        f"(see 'vhfit models'){hint}"
    )


def tau_strategies() -> list[str]:
    """The registered τ strategies (``--strategy``)."""
    # scipy.optimize comes with vhfit.optimize (~0.3 s): only the commands that need
    # the strategies pay for it, not 'export' or 'simulate'
    from vhfit.optimize import tau_strategies as registered

    return list(registered())
