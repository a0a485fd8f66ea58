"""``vhfit models``: registered hyperelastic models, τ strategies and plug-ins."""

from __future__ import annotations

import json

from vhfit import export, hyperelastic  # noqa: F401 - export registers the solvers
from vhfit.cli._common import EXIT_OK
from vhfit.cli._plugins import PLUGIN_GROUP, load_plugins, tau_strategies
from vhfit.formulations import FORMULATIONS, SOLVER_FORMULATIONS

__all__ = ["cmd_models"]


def cmd_models(args, argv=()) -> int:
    """``vhfit models``: registered models, τ strategies, plug-ins."""
    builtin = set(hyperelastic.available())
    plugins = load_plugins()
    origin = {m: f"plug-in {p['name']} ({p['value']})" for p in plugins for m in p["models"]}
    models = []
    for name in hyperelastic.available():
        hm = hyperelastic.get(name)
        models.append({
            "name": name,
            "parameters": [{"name": n, "unit": u} for n, u in zip(hm.param_names, hm.units)],
            "kind": hm.kind,
            "linear": bool(hm.linear),
            "origin": "built-in" if name in builtin and name not in origin else
                      origin.get(name, "registered"),
            "doc": (hm.doc or "").strip().splitlines()[0] if hm.doc else "",
        })
    strategies = tau_strategies()
    forms = [{"name": n, "description": f.description,
              "solvers": [s for s, g in SOLVER_FORMULATIONS.items() if g == n]}
             for n, f in FORMULATIONS.items()]
    if args.json:
        print(json.dumps({"models": models, "tau_strategies": strategies,
                          "formulations": forms, "plugins": plugins,
                          "plugin_group": PLUGIN_GROUP}, indent=2))
        return EXIT_OK
    _print_table(models, strategies, plugins, forms)
    return EXIT_OK


def _print_table(models: list[dict], strategies: list[str], plugins: list[dict],
                 forms: list[dict]) -> None:
    print("hyperelastic models (vhfit fit --model NAME):")
    w = max(len(m["name"]) for m in models)
    for m in models:
        pars = ", ".join(f"{p['name']} [{p['unit']}]" for p in m["parameters"])
        tag = "" if m["origin"] == "built-in" else f"   <- {m['origin']}"
        print(f"  {m['name']:<{w}}  {pars}{tag}")
        if m["doc"]:
            print(f"  {'':<{w}}    {m['doc']}")
    print("")
    print("Prony terms add G_i [MPa] and tau_i [s] for i = 1..N (vhfit fit --prony N|auto)")
    print("")
    print("tau strategies (vhfit fit --strategy NAME): " + ", ".join(strategies))
    print("")
    print("viscoelastic formulations (vhfit fit --formulation NAME; --for SOLVER picks the "
          "solver's own):")
    w = max(len(f["name"]) for f in forms)
    for f in forms:
        used = f"   [{', '.join(f['solvers'])}]" if f["solvers"] else ""
        print(f"  {f['name']:<{w}}  {f['description']}{used}")
    print("")
    if plugins:
        print(f"plug-ins (entry-point group '{PLUGIN_GROUP}'):")
        for p in plugins:
            state = (f"error: {p['error']}" if p["error"] else
                     "models: " + (", ".join(p["models"]) or "none new"))
            print(f"  {p['name']} = {p['value']}   {state}")
    else:
        print(f"plug-ins: none installed (a package adds models through the entry-point "
              f"group '{PLUGIN_GROUP}'; see docs/cli.md)")
