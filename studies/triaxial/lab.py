"""The triaxial calibration of the Nadukuru backfill mixture: the cubical triaxial test
(``studies.elements.triaxial``) on a recipe, written to a calibration card that
``compare nadukuru`` looks phi up in (``card_path``, ``calibrate_triaxial``), and the
case of the ``calibrate triaxial`` command (``TriaxialCase``)."""

from __future__ import annotations

from dataclasses import dataclass, field

import reproducibility
from analytic.errors import InvalidParameter
from analytic.schema import check_fields, seed_param

from ..elements.triaxial import TriaxialSetup, mu_compact_of, run_triaxial
from ..granular import MOST_PARTICLE_STEPS, SpecimenRecipe, time_step
from ..store import atomic_write, content_key


@dataclass(frozen=True)
class TriaxialCase:
    """``calibrate triaxial``: the backfill recipe (Nadukuru's, its card keyed by the
    grain and contact fields; ``specimen.particles`` is the test's sphere count, the
    paper's 8,200), the test set-up and the seed."""

    specimen: SpecimenRecipe = field(default_factory=lambda: SpecimenRecipe(particles=8200))
    setup: TriaxialSetup = field(default_factory=TriaxialSetup)
    seed: int = seed_param(1)

    def __post_init__(self):
        check_fields(self)
        steps, dt = self.most_steps()
        work = self.specimen.particles * steps
        if work > MOST_PARTICLE_STEPS:
            raise InvalidParameter("particles x time steps", work, f"<= {MOST_PARTICLE_STEPS:g}",
                                   f"up to {steps:.3g} steps of {dt:.3g} s, ~{work / 4e6 / 86400:.3g} days on 2 "
                                   "cores")

    def most_steps(self) -> tuple[float, float]:
        """(time steps of the test at most, the time step [s]): the compaction at its cap
        (400,000), the re-balance (2000) and the shear (``run_triaxial``)."""
        rec, setup = self.specimen, self.setup
        dt = time_step(rec)
        return 400_000 + 2000 + setup.max_strain / setup.strain_rate / dt, dt


def card_path(root, rec: SpecimenRecipe, seed: int):
    """Where the calibration card of a recipe lives: runs/nadukuru/calibration/, keyed by
    the grain and contact fields (not the particle count: one card serves every size)."""
    from pathlib import Path
    keys = ("clump_fraction", "clump_overlap", "d_min", "d_max", "kn", "ks", "particle_friction", "density",
            "deposition_friction", "damping_ratio")
    fields = {k: getattr(rec, k) for k in keys}
    if rec.rolling_friction:        # absent at 0, so the cards made before it keep their names
        fields["rolling_friction"] = rec.rolling_friction
    key = content_key(fields, length=12)
    return Path(root) / "nadukuru" / "calibration" / f"triaxial-{key}.json"


def calibrate_triaxial(case, setup: TriaxialSetup, *, particles: int, root, progress=None, on_frame=None):
    """Run the triaxial test for the case's recipe and write its calibration card
    (JSON: phi at peak and at the end, strains, porosity, provenance) where
    ``compare nadukuru`` finds it (``on_frame``: as ``run_triaxial``). Returns (card, path)."""
    import dataclasses
    import json
    import time

    from ..runfolder import package_versions

    t0 = time.perf_counter()
    res = run_triaxial(case.specimen, setup, seed=case.seed, particles=particles, progress=progress,
                       on_frame=on_frame)
    card = {
        "test": "cubical triaxial (six rigid platens, sigma_2 = sigma_3), gravity off",
        "phi_peak_deg": res.phi_peak_deg, "strain_at_peak": res.strain_at_peak, "phi_end_deg": res.phi_end_deg,
        "porosity": res.porosity_start, "particles": res.n_spheres, "side_m": res.side,
        "confining_kPa": setup.confining / 1e3, "strain_rate_per_s": setup.strain_rate,
        "compaction_friction": mu_compact_of(setup, case.specimen), "seed": case.seed,
        "recipe": dataclasses.asdict(case.specimen), "steps": res.steps, "wall_time_s": time.perf_counter() - t0,
        "versions": package_versions(), "reproducibility": reproducibility.describe(),
        "curve": {"axial_strain": res.axial_strain[::10].tolist(), "volumetric_strain": res.volumetric_strain[::10].tolist(),
                  "sigma_1_kPa": (res.sigma_1[::10] / 1e3).tolist(), "sigma_3_kPa": (res.sigma_3[::10] / 1e3).tolist()},
        "paper": {"phi_deg": 39.0, "source": "Nadukuru & Michalowski (2012): cylinder 1.2 m, 8,200 particles, 200 kPa"},
    }
    path = atomic_write(card_path(root, case.specimen, case.seed), json.dumps(card, indent=1).encode())
    return card, path
