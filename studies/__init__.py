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

from .registry import NAMES, all_studies, get
from .study import Command, Option, Study

__all__ = ["Command", "Option", "Study", "NAMES", "get", "all_studies"]
