"""The registry of studies: their names, in the order ``wallsim --help`` lists them, and
the lookup by name. Each is a module ``studies.<name>`` whose ``STUDY`` is a ``Study``;
a new study is one package plus one name here."""

from __future__ import annotations

from importlib import import_module

from analytic.errors import InvalidParameter

NAMES = ("nadukuru", "khosravi", "triaxial", "biaxial", "cantilever", "heap", "drystone", "tilt", "seismic", "gravel", "wall")


def get(name: str):
    """The ``Study`` called ``name``."""
    if name not in NAMES:
        raise InvalidParameter("study", name, " | ".join(NAMES))
    return import_module(f"studies.{name}").STUDY


def all_studies() -> list:
    return [get(n) for n in NAMES]
