"""The run envelope and the case schema every command shares (issue 38): lists and whole
numbers parse one way everywhere, every key says its unit, range and meaning, a run
folder is written with the user's umask and its result.json once, and an error or an
interrupt names only what exists."""

import json
import os
import re
import stat
import subprocess
import sys
from pathlib import Path

import pytest

import cli
import studies
import studies.runner as runner
from analytic.errors import InvalidParameter
from analytic.schema import undeclared_fields
from studies.config import describe_keys

ROOT = Path(__file__).resolve().parents[2]


def _commands():
    return [(s.name, c) for s in studies.all_studies() for c in s.commands]


@pytest.mark.parametrize("name,cmd", _commands(), ids=[f"{n}-{c.verb}" for n, c in _commands()])
def test_every_key_has_a_unit_a_range_and_a_whole_meaning(name, cmd):
    """`wallsim keys STUDY` reads every field's declaration: no field undeclared, every
    meaning one complete line (it used to be cut mid-sentence from docstrings)."""
    case = cmd.default_case()
    assert undeclared_fields(type(case)) == []
    for row in describe_keys(case):
        assert row.unit != "?" and row.valid, row
        assert len(row.meaning) >= 10 and "\n" not in row.meaning, row
        assert not row.meaning.rstrip().endswith((",", "(", "...", " and", " or", " the")), row
        assert row.meaning.count("(") == row.meaning.count(")"), row


def test_keys_prints_unit_range_and_meaning_for_each_key(capsys):
    assert cli.main(["keys", "nadukuru"]) == 0
    out = capsys.readouterr().out
    assert re.search(r"^wall\.height \[m\] = 3\.1 +valid: a number in \(0, 100\] m$", out, re.M)
    assert re.search(r"^movement\.mode = T +valid: T \| RB \| RT \| mixed$", out, re.M)
    assert out.count("\n    ") == len(describe_keys(studies.get("nadukuru").command().default_case()))


def test_a_list_key_takes_a_list_from_set_and_refuses_an_empty_item():
    """`--set frictions_deg=30` was split into the characters '3', '0'."""
    cmd = studies.get("tilt").command()
    assert cmd.resolve(sets=["frictions_deg=30"]).frictions_deg == (30.0,)
    assert cmd.resolve(sets=["frictions_deg=36,28"]).frictions_deg == (36.0, 28.0)
    with pytest.raises(InvalidParameter, match="an empty item"):
        cmd.resolve(sets=["frictions_deg=36,,28"])


def test_a_whole_number_is_never_cut():
    """`--set specimen.particles=3000.5` ran 3000; a float that is whole is a whole number."""
    nad = studies.get("nadukuru")
    with pytest.raises(InvalidParameter, match="whole number"):
        nad.case(particles=3000.5)
    assert nad.case(particles=3000.0).specimen.particles == 3000
    assert type(nad.case(particles=3000.0).specimen.particles) is int
    with pytest.raises(InvalidParameter, match=r"\[50, 1000000\]"):
        nad.command().resolve(sets=["specimen.particles=1e9"])


def test_no_module_level_run_state():
    """The command in progress lives in a context variable of the envelope."""
    assert not hasattr(runner, "current_folder")


def test_an_error_inside_a_command_leaves_no_empty_folder(tmp_path):
    case = studies.get("tilt").command().default_case()
    with pytest.raises(InvalidParameter):
        with runner.command_envelope():
            folder = runner.open_run_folder("tilt", case, tmp_path)
            assert folder.path.is_dir()
            raise InvalidParameter("x", 1, "(0, 1)")
    assert list((tmp_path / "tilt").iterdir()) == []


def test_an_interrupt_names_the_folder_only_if_it_exists(tmp_path):
    case = studies.get("tilt").command().default_case()
    with pytest.raises(runner.RunInterrupted) as stop:
        with runner.command_envelope():
            folder = runner.open_run_folder("tilt", case, tmp_path)
            folder.write_json("partial.json", {})
            raise KeyboardInterrupt
    assert stop.value.folder == folder.path
    assert str(folder.path) in runner.interrupted_line(None, stop.value.folder)
    assert "nothing was written" in runner.interrupted_line(None, None)
    assert "nothing was written" in runner.interrupted_line("wallsim compare heap", tmp_path / "gone")


def test_a_run_folder_has_the_users_umask_and_one_result_write(tmp_path, monkeypatch, capsys):
    """config/CSV/JSON were 0600 (mkstemp) beside 0644 PNGs; result.json was written by
    finish and again by the closing line."""
    from studies.runfolder import RunFolder

    writes = []
    real = RunFolder.write_json
    monkeypatch.setattr(RunFolder, "write_json", lambda self, name, obj: writes.append(name) or real(self, name, obj))
    old = os.umask(0o022)
    try:
        assert cli.main(["calibrate", "tilt", "--friction", "30", "--set", "slender_widths_m=0.1", "--quiet",
                         "--out", str(tmp_path)]) == 0
    finally:
        os.umask(old)
    folder = next((tmp_path / "tilt").iterdir())
    modes = {p.name: stat.S_IMODE(p.stat().st_mode) for p in folder.iterdir() if p.is_file()}
    assert set(modes.values()) == {0o644}, modes
    assert writes.count("result.json") == 1
    result = json.loads((folder / "result.json").read_text())
    assert set(result["resources"]) == {"wall_time_s", "cpu_time_s", "peak_memory_MB", "sessions"}
    assert result["resources"]["sessions"] == 1
    config = (folder / "config.toml").read_text()
    assert "#   frictions_deg: flag --friction" in config and "#   slender_widths_m: --set" in config


def test_a_resumed_manifest_keeps_every_session(tmp_path):
    from studies.runfolder import RunFolder

    first = RunFolder("tilt", None, root=tmp_path)
    first.write_config(studies.get("tilt").command().default_case(), sources={"dt": "--set"})
    first.write_manifest()
    again = RunFolder.existing(first.path)
    again.note_used(["time step 0.0005 s"])
    man = json.loads(again.write_manifest().read_text())
    assert len(man["sessions"]) == 2 and man["command"] == man["sessions"][0]["command"]
    assert man["wall_time_s"] == pytest.approx(sum(s["wall_time_s"] for s in man["sessions"]))
    config = (first.path / "config.toml").read_text()
    assert "#   dt: --set" in config and "# what the run used:\n#   time step 0.0005 s" in config


def test_a_resumed_run_counts_the_time_its_stopped_session_checkpointed(tmp_path):
    """A session stopped by a kill writes no manifest: its times up to its last checkpoint
    are what the checkpoint recorded beside it, and the run's resources add them."""
    import time

    from studies.runfolder import SESSIONS, RunFolder

    first = RunFolder("tilt", None, root=tmp_path)
    first.write_config(studies.get("tilt").command().default_case())
    start = time.process_time()
    while time.process_time() - start < 0.05:       # some CPU before the checkpoint
        pass
    first.save_checkpoint("checkpoints/state.bin", b"state")
    stopped = json.loads((first.path / SESSIONS).read_text())["sessions"]
    assert len(stopped) == 1 and stopped[0]["cpu_time_s"] >= 0.05

    again = RunFolder.existing(first.path)
    total = again.resources()
    assert total["sessions"] == 2
    assert total["cpu_time_s"] >= stopped[0]["cpu_time_s"]
    (first.path / "checkpoints" / "state.bin").unlink()      # finished: the study drops its checkpoint
    man = json.loads(again.write_manifest().read_text())
    assert [s["cpu_time_s"] for s in man["sessions"]][0] == stopped[0]["cpu_time_s"]
    assert man["cpu_time_s"] == pytest.approx(sum(s["cpu_time_s"] for s in man["sessions"]))
    assert not (first.path / "checkpoints").exists()          # the manifest holds the sessions now


def test_an_interrupted_sweep_claims_only_what_exists(tmp_path):
    """Ctrl-C said 'the finished points and sweep.csv are in sweeps' when nothing was."""
    import time
    started = time.time()
    assert cli._finished_since(str(tmp_path), "tilt", started, "points") == "nothing was written"
    done = tmp_path / "tilt" / "p1"
    done.mkdir(parents=True)
    (done / "result.json").write_text("{}")
    said = cli._finished_since(str(tmp_path), "tilt", started, "points")
    assert said.startswith("1 finished points") and "sweep.csv" not in said


def test_wallsim_alone_prints_the_usage():
    run = subprocess.run([sys.executable, str(ROOT / "cli.py")], capture_output=True, text=True, cwd=ROOT,
                         env=os.environ | {"WALLSIM_REPRODUCIBILITY": "native"})
    assert run.returncode == 2 and run.stderr.startswith("usage: wallsim") and "compare" in run.stderr


def test_every_tracked_file_compiles_on_the_declared_floor():
    """pyproject says requires-python >= 3.11; seeds.py once held 3.12-only syntax."""
    run = subprocess.run(["bash", str(ROOT / "scripts" / "check_python_floor.sh")], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


@pytest.mark.parametrize("argv,key", [(["compare", "nadukuru", "--particles", "1000000"], "particles"),
                                      (["calibrate", "triaxial", "--particles", "600000"], "particles"),
                                      (["compare", "khosravi", "--particles-scale", "0.5"], "particles_scale")])
def test_a_run_larger_than_the_machine_is_refused_with_its_estimate(argv, key, tmp_path, monkeypatch, capsys):
    """Within the fields' bounds a run may still not fit a small machine: refused before
    anything is allocated, naming the size key and the estimate (4 KB a sphere, 4.2 KB a
    disk, as measured for dem3d and pymunk)."""
    monkeypatch.setattr(runner, "machine_memory", lambda: 1e9)
    monkeypatch.setattr(runner, "command_envelope", lambda *a: pytest.fail("the run started"))
    assert cli.main(argv + ["--out", str(tmp_path), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert re.search(rf"{key} = .* this machine can hold \(needs ~[\d.]+ GB; this machine has 1 GB\)$", err), err
    assert list(tmp_path.iterdir()) == []


def test_one_place_writes_result_json():
    """result.json was written by finish, rewritten by the closing line, and written by
    hand in the biaxial calibration; now runner.finish alone writes it."""
    import ast
    writers = []
    for path in sorted((ROOT / "studies").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Call) and any(isinstance(a, ast.Constant) and a.value == "result.json"
                                                  for a in node.args) and \
                    getattr(node.func, "attr", getattr(node.func, "id", "")) in ("write_json", "atomic_write"):
                writers.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    assert [w.split(":")[0] for w in writers] == ["studies/runner.py"], writers
