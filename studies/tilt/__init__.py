"""Tilt calibration of the rigid-block contact (dem2d.blocks, the dry-stone study's
blocks): a block on an identical fixed block tilted until it slides (the slide angle
must equal the input friction angle, tan = mu; S-OET Table 2 friction angles are tilt-test
values), and a slender block tilted until it tips over (atan(width / height)). The
study record is ``STUDY``."""

from __future__ import annotations

import math
import time
from contextlib import contextmanager
from dataclasses import dataclass
from types import SimpleNamespace

from analytic.errors import InvalidParameter
from analytic.schema import check_fields, param

from ..options import VTK
from ..study import Command, Option, Study


@dataclass(frozen=True)
class TiltCase:
    """The slide and topple tests of the block contact (S-OET Table 2 blocks)."""

    frictions_deg: tuple[float, ...] = param(
        (36.0, 28.5, 35.0, 25.0), unit="deg", lo=0, hi=80, lo_open=True, hi_open=True,
        meaning="block-block friction angles to tilt, one slide test each (S-OET Table 2: 36, 28.5, 35, 25)")
    slender_widths_m: tuple[float, ...] = param(
        (0.10, 0.125), unit="m", lo=0, hi=5, lo_open=True,
        meaning="widths of the slender blocks tilted until they topple, each below slender_height_m")
    slender_height_m: float = param(0.30, unit="m", lo=0, hi=5, lo_open=True, hi_open=True,
                                    meaning="height of the slender blocks")
    block_length_m: float = param(0.30, unit="m", lo=0, hi=5, lo_open=True, hi_open=True,
                                  meaning="length of the sliding block (S-OET: 0.30)")
    block_height_m: float = param(0.125, unit="m", lo=0, hi=5, lo_open=True, hi_open=True,
                                  meaning="height of the sliding block (S-OET: 0.125)")
    # below 1e-5 s a tilt search needs > 10^7 steps: no run would end
    dt: float = param(5e-4, unit="s", lo=1e-5, hi=2e-3, hi_open=True,
                      meaning="time step of the block solver, as the walls'")
    iterations: int = param(20, lo=1, hi=500, meaning="contact-solver sweeps per step, as the walls'")
    # the search time grows as 1 / resolution: 5e-6 deg took 30 s of CPU a test, 1e-4 about 2 s
    resolution_deg: float = param(0.05, unit="deg", lo=1e-4, hi=1, hi_open=True,
                                  meaning="tilt increment near the slide or topple angle")

    def __post_init__(self):
        check_fields(self)
        for w in self.slender_widths_m:
            if not w < self.slender_height_m:
                raise InvalidParameter("slender_widths_m", w, f"(0, {self.slender_height_m:g}) m",
                                       "a block must be slender: width below slender_height_m")


def tilt_tests(case: TiltCase, folder=None) -> dict:
    """Every slide and topple test of ``case`` (no files; with ``folder``, a run started
    with --vtk, each test's blocks at every held angle of its fine search in
    vtk/<test>/)."""
    from dem2d.blocks import BlockSolver

    from .protocol import tilt_slide_angle, topple_angle

    solver = BlockSolver(dt=case.dt, iterations=case.iterations)
    slides = []
    for f in case.frictions_deg:
        with _recording(folder, f"slide-{f:g}deg", solver.dt) as on_step:
            slides.append({"friction_deg": f, "slide_angle_deg": tilt_slide_angle(
                f, block=(case.block_length_m, case.block_height_m), solver=solver,
                resolution_deg=case.resolution_deg, on_step=on_step)})
    topples = []
    for w in case.slender_widths_m:
        expected = math.degrees(math.atan(w / case.slender_height_m))
        with _recording(folder, f"topple-{w:g}m", solver.dt) as on_step:
            got = topple_angle(w, case.slender_height_m, friction_deg=min(expected + 30, 80), solver=solver,
                               resolution_deg=case.resolution_deg, on_step=on_step)
        topples.append({"width_m": w, "height_m": case.slender_height_m, "expected_deg": expected,
                        "topple_angle_deg": got})
    for s in slides:
        s["error_deg"] = s["slide_angle_deg"] - s["friction_deg"]
    for t in topples:
        t["error_deg"] = t["topple_angle_deg"] - t["expected_deg"]
    return {"slides": slides, "topples": topples, "collision_slop_m": solver.collision_slop}


@contextmanager
def _recording(folder, label: str, dt: float):
    """The ``on_step`` of one test that records its blocks (--vtk), or None."""
    from ..runner import test_recording
    from .protocol import outlines
    with test_recording(folder, study="tilt", label=label) as rec:
        yield (lambda space, steps: rec.log_polygons(steps, steps * dt, outlines(space), kind="blocks")) \
            if rec is not None else None


def _calibrate(case: TiltCase, opts: SimpleNamespace) -> tuple[dict, str]:
    from ..runner import finish, open_run_folder

    t0, c0 = time.perf_counter(), time.process_time()
    folder = open_run_folder("tilt", case, opts.out, seed=None)
    r = tilt_tests(case, folder)
    folder.write_csv("slides.csv", ["friction_deg", "slide_angle_deg", "error_deg"],
                     [[s["friction_deg"], s["slide_angle_deg"], s["error_deg"]] for s in r["slides"]])
    folder.write_csv("topples.csv", ["width_m", "height_m", "expected_deg", "topple_angle_deg", "error_deg"],
                     [[t["width_m"], t["height_m"], t["expected_deg"], t["topple_angle_deg"], t["error_deg"]]
                      for t in r["topples"]])
    seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
    result = {"case": "tilt", **r, "dt_s": case.dt, "iterations": case.iterations,
              "resolution_deg": case.resolution_deg,
              "wall_time_s": seconds, "cpu_time_s": cpu, "run_folder": str(folder.path)}
    finish(folder, result, particles=2, dt_s=case.dt, iterations=case.iterations, wall_time_s=seconds,
           cpu_time_s=cpu)
    return result, f"run folder: {folder.path}"


def _text(r: dict) -> str:
    lines = ["block on block (tilt test): input friction -> slide angle"]
    lines += [f"  {s['friction_deg']:6.2f} deg -> {s['slide_angle_deg']:6.2f} deg ({s['error_deg']:+.2f})"
              for s in r["slides"]]
    lines.append("slender block: atan(width / height) -> topple angle")
    lines += [f"  {t['width_m']:.3f} x {t['height_m']:.3f} m: {t['expected_deg']:6.2f} deg -> "
              f"{t['topple_angle_deg']:6.2f} deg ({t['error_deg']:+.2f})" for t in r["topples"]]
    lines.append(f"resolution {r['resolution_deg']:g} deg (the angle reported is the first step at which it moved); "
                 f"dt {r['dt_s']:g} s, {r['iterations']} sweeps")
    return "\n".join(lines)


CALIBRATE = Command(
    verb="calibrate", help="tilt tests of the rigid blocks: slide angle vs input friction, toppling angle",
    description="A 0.30 x 0.125 m block on an identical fixed block, tilted (gravity turned) until it slides; "
                "slender blocks tilted until they tip over at atan(b/h). Checks the pair friction set per contact "
                "(pymunk multiplies shape frictions). Example: wallsim calibrate tilt --friction 36,28.5",
    default_case=TiltCase, run=_calibrate, text=_text, seed_key=None,
    options=(Option("--friction", "friction angles to test [deg] (36,28.5,35,25)", key="frictions_deg"),
             Option("--dt", "time step [s] (5e-4)", key="dt"), VTK))

STUDY = Study(name="tilt", title="Tilt tests of the rigid dry-stone blocks (slide and toppling angles)",
              commands=(CALIBRATE,))
