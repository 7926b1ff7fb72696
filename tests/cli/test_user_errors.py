"""What a new user trips over: every bad input ends in one line on stderr and exit 2,
with no traceback and nothing written; Ctrl-C ends every long command with exit 130
and one line; settings follow one precedence; a resume keeps its run's settings.

The inputs are the ones a new user tried on a fresh clone, and more of each kind."""

import json
import re
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import cli
from tests.conftest import interruptible

ROOT = Path(__file__).resolve().parents[2]

BAD = [
    # Dask scheduler addresses dask.distributed cannot parse (it raised a traceback)
    ["validate", "nadukuru", "--seeds", "1..2", "--scheduler", "notanaddress"],
    ["sweep", "nadukuru", "--vary", "seed=1,2", "--scheduler", "tcp://host:99999"],
    # counts and numbers
    ["compare", "nadukuru", "--particles", "50"],
    ["compare", "nadukuru", "--particles", "800"],           # below the 878 a 3.1 m wall needs
    ["compare", "nadukuru", "--particles", "-3"],
    ["compare", "nadukuru", "--set", "particles=inf"],
    ["compare", "nadukuru", "--set", "seed=1e400"],
    ["compare", "nadukuru", "--set", "density=-2650"],
    ["compare", "nadukuru", "--set", "particle_friction=nan"],
    ["compare", "nadukuru", "--set", "movement.record_every=0"],
    ["compare", "nadukuru", "--set", "d_max=0.01"],           # below d_min
    ["compare", "nadukuru", "--set", "d_min=0.2"],            # above d_max (named both)
    ["compare", "nadukuru", "--set", "dt=1"],                 # over the safe step (named as typed)
    ["compare", "nadukuru", "--every", "0"],
    ["compare", "nadukuru", "--mode", "sideways"],
    ["compare", "khosravi", "--particles-scale", "1000"],
    ["compare", "khosravi", "--H", "0.001", "--particles-scale", "3"],
    ["compare", "khosravi", "--H", "0.5"],
    ["compare", "khosravi", "--set", "friction=-1"],
    ["compare", "khosravi", "--set", "dis_over_H_max=nan"],   # an old spelling, still checked
    ["calibrate", "biaxial", "--friction", "0.3,abc"],
    ["calibrate", "biaxial", "--friction", "-0.1"],
    ["calibrate", "biaxial", "--target-phi", "95"],
    ["calibrate", "triaxial", "--confining", "-5"],
    ["calibrate", "triaxial", "--particles", "0"],
    ["theory", "--omega", "-60"],
    ["theory", "--phi", "95"],
    ["dsm", "--delta", "-30"],
    ["dsm", "--theta-r", "abc"],
    ["calibrate", "tilt", "--friction", "nan"],
    ["calibrate", "tilt", "--friction", "120"],
    ["calibrate", "tilt", "--set", "dt=1e-9"],              # would never end
    ["calibrate", "tilt", "--dt", "1e-9"],
    ["calibrate", "tilt", "--set", "resolution_deg=0"],     # named as typed, not "resolution"
    ["calibrate", "tilt", "--set", "slender_widths_m=5"],
    ["compare", "drystone", "--set", "dt=1e-9"],
    ["compare", "drystone", "--dt", "0"],
    ["validate", "drystone", "--walls", "V1L,V1L"],
    ["validate", "drystone", "--docs", "/proc"],             # not writable: refused before any run
    ["validate", "drystone", "--docs", "/proc/wallsim"],     # cannot be created
    # keys and abbreviations
    ["compare", "nadukuru", "--set", "no_such_key=1"],
    ["compare", "nadukuru", "--set", "novalue"],
    ["compare", "khosravi", "--particles", "3000"],            # not --particles-scale
    ["validate", "khosravi", "--out-dir", "x"],                # now --docs
    ["keys", "sandpile"],                                    # no such study
    # files
    ["theory", "--plot", "p.txt"],
    ["theory", "--plot", "missing/dir/p.png"],
    ["dsm", "--plot", "missing/p.png"],
    ["compare", "nadukuru", "--rrd", "out.txt"],
    ["compare", "nadukuru", "--rrd", "missing/r.rrd"],
    ["calibrate", "biaxial", "--card", "missing/card.json"],
    ["compare", "nadukuru", "--config", "."],                  # a folder
    ["compare", "nadukuru", "--config", "binary.toml"],
    ["compare", "nadukuru", "--config", "missing.toml"],
    ["compare", "nadukuru", "--config", "bad.toml"],
    # resume
    ["compare", "nadukuru", "--resume", ""],
    ["compare", "nadukuru", "--resume", "."],
    ["compare", "nadukuru", "--resume", "runs/khosravi/old"],  # another study's run
    ["compare", "nadukuru", "--resume", "runs/nadukuru/old", "--seed", "3"],
    ["compare", "nadukuru", "--resume", "runs/nadukuru/old", "--set", "particle_friction=0.3"],
    # a fresh clone's second round (issue 38): lists, whole numbers, sizes, paths, contradictions
    ["calibrate", "tilt", "--friction", "36,,28"],             # an empty item was dropped in silence
    ["calibrate", "tilt", "--set", "frictions_deg=30,"],
    ["calibrate", "tilt", "--set", "slender_widths_m=0.1,,0.2"],
    ["calibrate", "biaxial", "--friction", "0.3,,0.7"],
    ["compare", "nadukuru", "--set", "specimen.particles=3000.5"],   # was cut to 3000
    ["compare", "nadukuru", "--particles", "1.5"],
    ["compare", "nadukuru", "--particles", "1e9"],             # a whole number, but beyond any machine
    ["compare", "heap", "--particles", "1000000000"],
    ["calibrate", "triaxial", "--particles", "2.5"],
    ["calibrate", "cantilever", "--length", "1e6"],            # grew to 24 GB and was killed
    ["calibrate", "tilt", "--set", "iterations=20.5"],
    ["compare", "drystone", "--out", "/proc/runs"],            # a traceback from mkdir
    ["compare", "drystone", "--wall", "C2S", "--set", "backfill.seed=-5"],    # numpy's traceback
    ["compare", "drystone", "--rrd", "x.rrd", "--no-rrd"],     # wrote x.rrd
    ["compare", "nadukuru", "--seed", "-1"],
    ["compare", "nadukuru", "--seed", "2.5"],
    ["theory", "--plot", "/proc/p.png"],                       # a traceback after the table
    ["design", "wall.toml", "--plot", "/proc/w.png"],
    ["dsm", "--plot", "/proc/d.png"],
    ["sweep", "tilt", "--vary", "iterations=1..1000000"],      # a million points
    ["sweep", "tilt", "--vary", "iterations=1..100", "--vary", "resolution_deg=1..200"],
    ["sweep", "tilt", "--out", "/proc/sweeps", "--vary", "iterations=10,20"],
    ["validate", "heap", "--seeds", "0..2"],
    ["validate", "heap", "--seeds", "2.5"],
    # a fresh set of the same kinds, tried after the schema (69 inputs; these 5 ran)
    ["validate", "drystone", "--walls", "V1L,,V2L"],
    ["validate", "drystone", "--backfill-seeds", "1,,2"],
    ["calibrate", "tilt", "--set", "resolution_deg=1e-12"],      # the search time grows as 1 / resolution
    ["calibrate", "biaxial", "--pressures", "1e12"],
    ["calibrate", "biaxial", "--friction", "1e300"],
    ["calibrate", "biaxial", "--confining", "1e5"],
    ["compare", "nadukuru", "--set", "wall.segments=6.5"],
    ["compare", "nadukuru", "--set", "seed=4294967296"],
    ["compare", "nadukuru", "--every", "2.5"],
    ["compare", "nadukuru", "--out", "/dev/null/runs"],
    ["compare", "heap", "--set", "slump_time=1e5"],
    ["compare", "heap", "--rrd", "a.rrd", "--no-rrd"],
    ["compare", "seismic", "--set", "grain_scale=0.01"],
    ["compare", "khosravi", "--set", "n_panels=40.5"],
    ["compare", "drystone", "--set", "backfill.container_m=1e6"],
    ["validate", "nadukuru", "--seeds", "1..100000"],
    ["validate", "seismic", "--freqs", "5,,4"],
    ["calibrate", "gravel", "--set", "seeds=1,2.5"],
    ["calibrate", "cantilever", "--length", "5", "--thickness", "0.001"],
    ["sweep", "heap", "--vary", "particles=1..20000"],
    ["theory", "--plot", "/dev/full/p.png"],
    ["validate", "khosravi", "--report-only", "--docs", "empty"],
    ["validate", "nadukuru", "--report-only", "--docs", "empty"],
    ["validate", "heap", "--report-only", "--docs", "empty"],
]


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    """A folder with the files the bad inputs name, as the current directory."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "binary.toml").write_bytes(bytes(range(256)))
    (tmp_path / "bad.toml").write_text("seed = = 3\n")
    (tmp_path / "wall.toml").write_text((ROOT / "docs" / "examples" / "cantilever.toml").read_text())
    (tmp_path / "empty").mkdir()                      # a --docs without the report to rewrite
    for study in ("khosravi", "nadukuru"):
        old = tmp_path / "runs" / study / "old"
        old.mkdir(parents=True)
        (old / "config.toml").write_text("seed = 7\n")
    return tmp_path


def _files(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*")}


@pytest.mark.parametrize("argv", BAD, ids=[" ".join(a) for a in BAD])
def test_bad_input_is_one_line_and_exit_2(argv, workdir, capsys):
    before = _files(workdir)
    with pytest.raises(SystemExit) as stop:
        raise SystemExit(cli.main(argv))
    err = capsys.readouterr().err
    assert stop.value.code == 2
    if "--set" in argv and "--resume" not in argv:      # the message names what the user typed
        from studies.config import current_name
        typed = argv[argv.index("--set") + 1].split("=")[0].split(".")[-1]
        assert typed in err or current_name(typed) in err or "key" in err
    assert len(err.strip().splitlines()) == 1 and "error" in err and "Traceback" not in err
    assert _files(workdir) == before          # nothing written


def test_a_finished_run_is_not_rerun(workdir, capsys):
    """--resume on a folder with a result.json: exit 0, says so, runs nothing."""
    from studies import get
    from studies.runfolder import RunFolder

    folder = RunFolder("nadukuru", 4, root=workdir / "runs")
    folder.write_config(get("nadukuru").case(particles=2000, seed=4))
    folder.write_json("result.json", {"case": "nadukuru"})
    before = _files(workdir)
    assert cli.main(["compare", "nadukuru", "--resume", str(folder.path)]) == 0
    assert "finished" in capsys.readouterr().err
    assert _files(workdir) == before


def test_vtk_on_a_resume_of_a_run_without_it_is_refused(workdir, capsys):
    """A resumed run records as it started: --vtk on a run started without it is one
    line and exit 2 (it would otherwise silently write no VTK), and nothing is written."""
    from studies import get
    from studies.runfolder import RunFolder

    folder = RunFolder("heap", 4, root=workdir / "runs")
    folder.write_config(get("heap").case(seed=4))
    before = _files(workdir)
    assert cli.main(["compare", "heap", "--resume", str(folder.path), "--vtk"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "--vtk" in err and "Traceback" not in err
    assert _files(workdir) == before


def _args(argv):
    return cli.build_parser().parse_args(argv)


def _case(argv):
    from studies import get
    args = _args(argv)
    return cli.case_from_args(get(args.study).command(args.command), args)


def test_precedence_defaults_config_flags_set(tmp_path):
    """defaults < --config < typed flags < --set; a flag not typed leaves the file's value."""
    cfg = tmp_path / "c.toml"
    cfg.write_text("seed = 7\n[specimen]\nparticles = 2500\n[movement]\nmode = \"RB\"\n[wall]\nfriction = 0.0\n")
    only_file = _case(["compare", "nadukuru", "--config", str(cfg)])
    assert (only_file.seed, only_file.specimen.particles, only_file.movement.mode, only_file.wall.friction) == \
        (7, 2500, "RB", 0.0)
    typed = _case(["compare", "nadukuru", "--config", str(cfg), "--seed", "3", "--mode", "T", "--wall", "rough",
                   "--particles", "2000"])
    assert (typed.seed, typed.specimen.particles, typed.movement.mode, typed.wall.friction) == (3, 2000, "T", 0.35)
    last = _case(["compare", "nadukuru", "--config", str(cfg), "--seed", "3", "--set", "seed=5"])
    assert last.seed == 5 and last.specimen.particles == 2500
    kcfg = tmp_path / "k.toml"
    kcfg.write_text("H = 0.2\nseed = 9\n")
    k = _case(["compare", "khosravi", "--config", str(kcfg), "--H", "0.25"])
    assert (k.H, k.seed) == (0.25, 9)


def test_old_spellings_are_read(tmp_path):
    """A config or --set key of the old vocabulary maps to today's (glossary)."""
    case = _case(["compare", "khosravi", "--set", "dis_over_H_max=0.002"])
    assert case.wall_disp_over_H_max == 0.002
    case = _case(["compare", "nadukuru", "--set", "movement.disp_over_H=0.004", "--particles", "2000"])
    assert case.movement.wall_disp_over_H == 0.004


LONG = [
    (["compare", "nadukuru", "--particles", "1000", "--no-rrd"], True),
    (["compare", "khosravi", "--particles-scale", "3", "--no-cache"], False),
    (["calibrate", "biaxial", "--particles-scale", "3", "--friction", "0.3"], False),
    (["calibrate", "triaxial", "--particles", "1000"], False),
    (["validate", "nadukuru", "--particles", "3000", "--walls", "rough", "--modes", "T", "--no-triaxial",
      "--no-rate-check", "--docs", "report"], False),
    (["validate", "khosravi", "--docs", "report"], False),
]


def _cpu_seconds(pid: int) -> float:
    """CPU time used so far by process ``pid`` (Linux /proc: utime + stime)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _wait_until(proc, ready, what: str, limit_s: float = 900.0) -> None:
    """Poll until ``ready()``: how far a run has got, measured by what it has done (CPU
    time, files) rather than by the clock, so a loaded machine interrupts it at the same
    point (a fixed sleep caught some runs before their run folder existed)."""
    t0 = time.monotonic()
    while not ready():
        assert proc.poll() is None, f"finished before {what}: " + proc.communicate()[1][-300:]
        assert time.monotonic() - t0 < limit_s, f"not {what} after {limit_s:.0f} s"
        time.sleep(0.2)


@pytest.mark.slow
@pytest.mark.parametrize("argv,resumable", LONG, ids=[" ".join(a[:2]) for a, _ in LONG])
def test_ctrl_c_stops_with_one_line_and_exit_130(argv, resumable, tmp_path):
    """SIGINT a few seconds into each long command: exit 130, no traceback, one line
    that names the run folder (and the resume command where there is one). Before,
    calibrate biaxial ran on: the interrupt was swallowed in a pymunk callback."""
    env = dict(os.environ, NUMBA_NUM_THREADS="1")
    with interruptible([sys.executable, str(ROOT / "cli.py"), *argv, "--quiet", "--out", str(tmp_path)],
                       cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as proc:
        if resumable:  # into the movement: its first checkpoint exists
            _wait_until(proc, lambda: any(tmp_path.glob("*/*/checkpoints/*")), "at a checkpoint")
        else:  # as far in as 4 s of an idle machine's run: past the imports, into the work
            _wait_until(proc, lambda: _cpu_seconds(proc.pid) >= 4.0, "4 s of CPU in")
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "Exception ignored" not in err
    last = err.strip().splitlines()[-1]
    assert last.startswith("wallsim: interrupted")
    assert ("--resume" in last) == resumable
    # the line names this run's folder, which exists (or says nothing was written yet)
    named = [w for w in last.replace(")", " ").split() if w.startswith(str(tmp_path))]
    assert all(Path(w).is_dir() for w in named) and (named or "nothing was written" in last)


def _write_and_reread(argv, tmp_path):
    """The case of ``argv``, written to a run folder's config.toml and read back with --config."""
    from studies.runfolder import RunFolder

    case = _case(argv)
    folder = RunFolder("x", 1, root=tmp_path)
    folder.write_config(case)
    return case, _case(argv[:2] + ["--config", str(folder.path / "config.toml")])


def test_a_runs_config_repeats_it_whatever_the_key_order(tmp_path):
    """Checks that span fields see the final values: particles=700 is allowed once d_max
    shrinks the grains, and the run's config.toml (particles written before d_max) is read
    back to the same case (before, it was refused: 700 < 878 at the old d_max)."""
    case, again = _write_and_reread(["compare", "nadukuru", "--set", "d_max=0.05", "--set", "particles=700"],
                                    tmp_path)
    assert case.specimen.particles == 700 and again == case


def test_a_runs_config_keeps_unset_values(tmp_path):
    """None survives config.toml: reading_iterations=none (readings at the fill's sweeps)
    came back at the default 80 when None was dropped from the file."""
    case, again = _write_and_reread(["compare", "khosravi", "--set", "reading_iterations=none"], tmp_path)
    assert case.reading_iterations is None and again == case


@pytest.mark.slow
def test_the_printed_resume_command_continues_where_the_run_started(tmp_path):
    """Ctrl-C prints a resume command; run from another folder it resumes under the
    run's own root (specimen cache there, not in ./runs) with the run's own options
    (--no-rrd kept: no recording)."""
    env = dict(os.environ, NUMBA_NUM_THREADS="1")
    root = tmp_path / "first"
    with interruptible([sys.executable, str(ROOT / "cli.py"), "compare", "nadukuru", "--particles", "1000",
                        "--no-rrd", "--quiet", "--out", str(root)], cwd=tmp_path, env=env,
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as proc:
        _wait_until(proc, lambda: any(root.glob("nadukuru/*/checkpoints/movement.npz")),  # part of the movement saved
                    "at a checkpoint")
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=120)
    line = err.strip().splitlines()[-1]
    assert proc.returncode == 130 and "--resume" in line
    folder = Path(line.split("--resume ", 1)[1])
    assert folder.is_dir() and folder.parent.parent == root
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    done = subprocess.run([sys.executable, str(ROOT / "cli.py"), "compare", "nadukuru", "--resume", str(folder),
                           "--quiet", "--json"], cwd=elsewhere, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert not (elsewhere / "runs").exists() and (root / "nadukuru" / "specimens").is_dir()
    assert not any(folder.glob("*.rrd"))
    assert json.loads(done.stdout)["run_folder"] == str(folder)


def test_tilt_friction_has_one_valid_range(capsys):
    """--friction (flag) and frictions_deg (case key) refuse nan and 120 with the same
    range, (0, 80) deg, the one TiltCase checks."""
    ranges = []
    for argv in (["calibrate", "tilt", "--friction", "nan"], ["calibrate", "tilt", "--friction", "120"],
                 ["calibrate", "tilt", "--set", "frictions_deg=120"]):
        with pytest.raises(SystemExit) as stop:
            raise SystemExit(cli.main(argv))
        assert stop.value.code == 2
        ranges.append(re.split("valid range|expected", capsys.readouterr().err)[-1].strip())
    assert all("(0, 80) deg" in r for r in ranges), ranges
