"""Viscous records: the viscous part of a model (Prony terms first) and its parameter layout."""

from vhfit.viscous._layout import ParamLayout

__all__ = ["ParamLayout"]
