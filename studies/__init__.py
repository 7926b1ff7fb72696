"""The study layer: every paper case and calibration test as a registered study over
shared configuration (``config``), run folders (``runfolder``), storage (``store``),
measurement (``measures``) and reports (``report``).

    from studies import get
    s = get("nadukuru")
    result = s.run(s.case(mode="RT", particles=3000))

``cli.py`` builds ``wallsim compare|validate|calibrate <study>`` from this registry
(docs/architecture.md, "How to add a study").
"""

from __future__ import annotations

from importlib import import_module

from analytic.errors import InvalidParameter

from .study import Command, Option, Study

#: registered studies, in the order ``wallsim --help`` lists them; each is a module
#: ``studies.<name>`` whose ``STUDY`` is a ``Study``
NAMES = ("nadukuru", "khosravi", "triaxial", "biaxial", "cantilever", "heap", "drystone", "tilt", "seismic", "gravel")


def get(name: str) -> Study:
    """The study called ``name``."""
    if name not in NAMES:
        raise InvalidParameter("study", name, " | ".join(NAMES))
    return import_module(f"{__name__}.{name}").STUDY


def all_studies() -> list[Study]:
    return [get(n) for n in NAMES]


__all__ = ["Command", "Option", "Study", "NAMES", "get", "all_studies"]
