"""Sweeps on Dask (studies/sweep.py): the points and their statistics against hand
values, and on a 2-worker LocalCluster a tiny Khosravi box (H 0.1 m, grains x8, to
Dis/H 0.001) over 2 seeds x 2 wall speeds (+ one refused speed): the same numbers, bit for
bit, as the same points run one by one through ``Study.run``; a rerun skips every point;
a killed worker's point is run again."""

import json
import math
import os
import re
import signal
import threading
import time
from pathlib import Path

import pytest

import cli
from analytic.errors import InvalidParameter
from studies import get
from studies.sweep import (Point, build_points, expand, group_rows, lead_indices, parse_vary, result_outputs,
                           run_point, run_sweep, stats)

ROOT = Path(__file__).resolve().parents[2]
TINY = ["H=0.1", "particles_scale=8", "wall_disp_over_H_max=0.001"]
VARY = ["seed=1..2", "wall_speed=0.004,0.008,-0.004"]      # -0.004: refused by the case


# ----------------------------------------------------------------------------- fast
def test_vary_values_ranges_and_product():
    varied = parse_vary(["seed=1..3", "mode = T, RB"])
    assert varied == [("seed", ["1", "2", "3"]), ("mode", ["T", "RB"])]
    points = expand(varied)
    assert len(points) == 6
    assert points[0] == Point((("seed", "1"), ("mode", "T")), (0, 0))
    assert points[5].sets == ["seed=3", "mode=RB"]
    assert [p.index for p in expand(parse_vary(["a=-1..0", "b=x"]))] == [(0, 0), (1, 0)]


@pytest.mark.parametrize("bad", ["seed", "seed=", "=1,2", "seed=1..x", "seed=3..1", "seed=1,,2", "seed=1,1"])
def test_vary_syntax_is_refused(bad):
    with pytest.raises(InvalidParameter) as err:
        parse_vary([bad])
    assert "--vary" in str(err.value) and "\n" not in str(err.value)


def test_a_key_varied_twice_is_refused():
    with pytest.raises(InvalidParameter, match="varied twice"):
        parse_vary(["seed=1", "seed=2"])


def test_leads_keep_the_seed_and_reset_one_key_each():
    # seed x speed: each seed's first speed prepares the specimen, the second waits for it
    assert lead_indices(expand(parse_vary(["seed=1,2", "v=a,b"])), seed_at=0) == [[], [0], [], [2]]
    # two keys that may or may not shape the specimen: (b, y) waits for (a, y) and (b, x)
    assert lead_indices(expand(parse_vary(["k=a,b", "m=x,y"])), seed_at=None) == [[], [0], [0], [1, 2]]


def test_statistics_against_hand_values():
    s = stats([1.0, 2.0, 4.0])
    assert s["n"] == 3 and s["mean"] == pytest.approx(7 / 3, rel=1e-15)
    assert s["sd"] == pytest.approx(math.sqrt(7 / 3), rel=1e-15)   # ((16 + 1 + 25) / 9) / 2 = 7/3
    assert (s["min"], s["max"]) == (1.0, 4.0)
    assert stats([5.0])["sd"] is None and stats([])["mean"] is None


def test_groups_are_the_points_that_differ_only_in_seed():
    rows = [{"seed": 1, "v": 1, "status": "done", "K": 0.30},
            {"seed": 2, "v": 1, "status": "skipped", "K": 0.34},
            {"seed": 3, "v": 1, "status": "failed", "K": None},
            {"seed": 1, "v": 2, "status": "done", "K": 0.50},
            {"seed": 2, "v": 2, "status": "done", "K": float("nan")}]
    g1, g2 = group_rows(rows, ["v"], ["K"])
    assert (g1["v"], g1["points"], g1["finished"]) == (1, 3, 2)
    assert g1["K_mean"] == pytest.approx(0.32, rel=1e-14)
    assert g1["K_sd"] == pytest.approx(math.sqrt(0.0008), rel=1e-12)   # (0.02^2 + 0.02^2) / 1
    assert (g1["K_min"], g1["K_max"]) == (0.30, 0.34)
    assert (g2["K_mean"], g2["K_sd"]) == (0.50, None)                  # NaN left out


def test_cases_are_built_before_anything_runs():
    study = get("khosravi")
    built = build_points(study, parse_vary(VARY), sets=TINY)
    assert [b["error"] is None for b in built] == [True, True, False, True, True, False]
    assert re.match(r"wall_speed = '?-0\.004'? is not valid; expected a number >= ", built[2]["error"])
    assert built[0]["inputs"] == {"seed": 1, "wall_speed": 0.004}
    assert built[0]["case"] == study.case(H=0.1, particles_scale=8, wall_disp_over_H_max=0.001, seed=1)
    names = [b["name"] for b in built if b["name"]]
    assert len(set(names)) == 4 and names[0].startswith("seed1_wall_speed0.004-")
    with pytest.raises(InvalidParameter, match="unknown key"):
        build_points(study, parse_vary(["no_such_key=1,2"]))


def test_a_point_that_raises_is_one_line(tmp_path):
    row = run_point("khosravi", None, "not a case", "bad-point", str(tmp_path))
    assert row["status"] == "failed" and "\n" not in row["error"] and row["error"].startswith("AttributeError")


@pytest.mark.parametrize("argv", [["--vary", "seed=1..x"], ["--vary", "nope=1,2"], ["--vary", "seed=1", "--set", "x"]])
def test_cli_refuses_bad_input_in_one_line(argv, capsys, tmp_path):
    assert cli.main(["sweep", "khosravi", *argv, "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("wallsim")


# ----------------------------------------------------------------------------- on Dask
def _same(a, b) -> bool:
    return a == b or (isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b))


def _serial(tmp_path_factory) -> list[dict]:
    """The four good points run one by one in this process, in the sweep's order (their
    results as result.json holds them)."""
    from studies.store import to_plain
    study, out = get("khosravi"), tmp_path_factory.mktemp("serial")
    return [to_plain(study.run(b["case"], out=str(out), quiet=True))
            for b in build_points(study, parse_vary(VARY), sets=TINY) if b["case"] is not None]


def _leaves(obj, prefix=""):
    """Every value of a result by path, but for where and how long (paths, wall times)."""
    if isinstance(obj, dict):
        for k, v in obj.items():
            # resources: the run's wall time, CPU time and peak memory
            if k not in ("timings_s", "specimen", "run_folder", "wall_time_s", "resources"):
                yield from _leaves(v, f"{prefix}.{k}")
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from _leaves(v, f"{prefix}[{i}]")
    else:
        yield prefix, obj


@pytest.fixture(scope="module")
def swept(client, tmp_path_factory):
    out = tmp_path_factory.mktemp("sweep")
    return out, run_sweep("khosravi", parse_vary(VARY), sets=TINY, out=out, client=client)


@pytest.mark.slow
def test_sweep_gives_the_serial_numbers_bit_for_bit(swept, client, tmp_path_factory):
    assert set(client.run(lambda: __import__("studies").__file__).values()) == {str(ROOT / "studies" / "__init__.py")}
    out, table = swept
    done = [p for p in table["points"] if p["status"] == "done"]
    assert len(done) == 4
    serial = _serial(tmp_path_factory)
    names = list(result_outputs(serial[0]))
    assert "K_active_total" in names and "resultant_height_over_H_active" in names
    differ = [(p["point"], n) for p, s in zip(done, serial) for n in names if not _same(p[n], result_outputs(s)[n])]
    assert differ == []
    for p, s in zip(done, serial):          # the whole result (readings, profiles, theories), not only the table
        swept_result = json.loads((Path(p["run_folder"]) / "result.json").read_text())
        want, have = dict(_leaves(s)), dict(_leaves(swept_result))
        assert len(want) > 50 and want.keys() == have.keys()
        assert [k for k in want if not _same(want[k], have[k])] == []
    assert len({p["K_active_total"] for p in done}) == 4          # four different answers, not one copied
    for p in done:
        assert Path(p["run_folder"]).name == p["point"] and (Path(p["run_folder"]) / "result.json").is_file()


@pytest.mark.slow
def test_an_invalid_point_is_reported_and_the_others_finish(swept):
    out, table = swept
    failed = [p for p in table["points"] if p["status"] == "failed"]
    assert [p["seed"] for p in failed] == ["1", "2"]
    assert all(re.match(r"wall_speed = '?-0\.004'? is not valid; expected a number >= ", p["error"]) for p in failed)
    on_disk = json.loads((out / "sweep.json").read_text())
    assert on_disk["points"] == table["points"]
    assert (out / "sweep.csv").read_text().count("\n") == 7 and (out / "sweep.png").is_file()
    g = {row["wall_speed"]: row for row in table["groups"]}
    ks = [p["K_active_total"] for p in table["points"] if p["wall_speed"] == 0.004]
    assert g[0.004]["finished"] == 2 and g[0.004]["K_active_total_mean"] == stats(ks)["mean"]
    assert g["-0.004"]["finished"] == 0 and g["-0.004"]["K_active_total_mean"] is None


@pytest.mark.slow
def test_a_rerun_skips_every_finished_point(swept, client, capsys):
    out, first = swept
    argv = ["sweep", "khosravi", *sum((["--vary", v] for v in VARY), []), *sum((["--set", s] for s in TINY), []),
            "--out", str(out), "--scheduler", client.scheduler.address, "--json", "--quiet"]
    assert cli.main(argv) == 1                      # 1: some points failed
    again = json.loads(capsys.readouterr().out)
    assert [p["status"] for p in again["points"]] == ["skipped", "skipped", "failed"] * 2
    keep = [k for k in first["points"][0] if k not in ("status", "wall_time_s")]
    assert [{k: p[k] for k in keep} for p in again["points"]] == [{k: p[k] for k in keep} for p in first["points"]]
    assert {"wall_speed", "points", "finished", "K_active_total_mean", "K_active_total_sd"} <= set(again["groups"][0])


@pytest.mark.slow
def test_ctrl_c_stops_with_one_line_and_writes_the_table(client, tmp_path, monkeypatch, capsys):
    import dask.distributed

    def interrupted(futures):
        raise KeyboardInterrupt
    monkeypatch.setattr(dask.distributed, "as_completed", interrupted)
    argv = ["sweep", "khosravi", "--vary", "wall_speed=-1,-2", "--out", str(tmp_path), "--scheduler",
            client.scheduler.address, "--quiet"]
    assert cli.main(argv) == 130
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("wallsim: interrupted")
    assert len(json.loads((tmp_path / "sweep.json").read_text())["points"]) == 2


@pytest.mark.slow
def test_killing_a_worker_mid_sweep_still_finishes_every_point(client, tmp_path):
    killed = {}

    def kill_one_busy_worker():
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and not killed:
            busy = {w: keys for w, keys in client.processing().items() if keys}
            started = list(tmp_path.glob("khosravi/seed*"))
            if busy and started:
                worker = next(iter(busy))
                pid = client.run(os.getpid, workers=[worker])[worker]
                time.sleep(1.0)                      # well inside the point (pluviation takes seconds)
                os.kill(pid, signal.SIGKILL)
                killed[worker] = list(busy[worker])
            time.sleep(0.2)

    killer = threading.Thread(target=kill_one_busy_worker)
    killer.start()
    # two points, one per worker: one is killed mid-run and must be run again
    table = run_sweep("khosravi", parse_vary(["seed=1..2"]), sets=TINY, out=tmp_path, client=client)
    killer.join()
    assert killed, "no worker was killed"
    assert all(str(k).startswith("point-") for keys in killed.values() for k in keys)
    assert [p["status"] for p in table["points"]] == ["done"] * 2
    assert all((Path(p["run_folder"]) / "result.json").is_file() for p in table["points"])


@pytest.mark.slow
def test_each_point_logs_its_progress_and_keeps_its_run_options(swept):
    out, table = swept
    for p in (p for p in table["points"] if p["status"] == "done"):
        folder = Path(p["run_folder"])
        log = (folder / "run.log").read_text().splitlines()
        assert f"point {p['point']}: khosravi compare, started on" in log[0] and "point finished in" in log[-1]
        assert any("pluviation" in line or "translation" in line for line in log[1:-1])   # the run's own progress
        assert json.loads((folder / "run_options.json").read_text()) == {"rrd": None, "no_cache": None,
                                                                         "resume": None, "vtk": None,
                                                                         "out": str(out.resolve()), "quiet": True}


def test_run_options_for_every_point_are_parsed_as_their_flags():
    from studies.sweep import parse_options
    cmd = get("nadukuru").command()
    assert parse_options(cmd, ["no-rrd", "every=10", "rrd=x.rrd"]) == {"no_rrd": True, "every": 10, "rrd": "x.rrd"}
    assert parse_options(cmd, ["rrd"]) == {"rrd": True}           # --rrd alone: recording.rrd in the run folder
    for bad, why in (["particles=3"], "not a run option"), (["resume=x"], "not a run option"), \
            (["every=0"], ">= 1"), (["no-rrd=1"], "a switch"), (["every"], "every=VALUE"):
        with pytest.raises(InvalidParameter, match=why):
            parse_options(cmd, bad)


def _interrupt_when_a_point_finishes(argv, out: Path, before: set) -> tuple[int, str, float, int]:
    """Run ``wallsim sweep`` in its own session (as a terminal's foreground group), send
    SIGINT to the whole group, as Ctrl-C at a terminal does, once a point has finished;
    return (exit code, stderr, seconds from SIGINT to exit, process group)."""
    import subprocess
    import sys
    from tests.conftest import interruptible

    with interruptible([sys.executable, str(ROOT / "cli.py"), "sweep", "khosravi", *argv, "--out", str(out),
                        "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                       start_new_session=True, env=dict(os.environ, PYTHONPATH=str(ROOT))) as proc:
        deadline = time.monotonic() + 900  # a bound for a hung sweep, not a pace: a busy machine is slow
        while not set(out.glob("khosravi/*/result.json")) - before and time.monotonic() < deadline:
            assert proc.poll() is None, proc.communicate()[1][-300:]
            time.sleep(0.1)
        t0 = time.monotonic()
        os.killpg(proc.pid, signal.SIGINT)
        _, err = proc.communicate(timeout=60)
        return proc.returncode, err, time.monotonic() - t0, proc.pid


def _group_is_gone(pgid: int, wait_s: float = 5.0) -> bool:
    deadline = time.monotonic() + wait_s
    while time.monotonic() < deadline:
        try:
            os.killpg(pgid, 0)
        except ProcessLookupError:
            return True
        time.sleep(0.1)
    return False


def _speed_folders(out: Path, speeds: list[str]) -> list[Path]:
    return [f for f in out.glob("khosravi/seed1_wall_speed*")
            if f.name.split("-")[0].removeprefix("seed1_wall_speed") in speeds]


def _check_interrupted(out: Path, code: int, err: str, speeds: list[str]) -> list[dict]:
    """Exit 130, one line; sweep.json says which points finished (their folders hold a
    result) and which were stopped."""
    assert code == 130 and err.count("\n") == 1 and err.startswith("wallsim: interrupted"), err
    points = [p for p in json.loads((out / "sweep.json").read_text())["points"]
              if str(p["wall_speed"]) in speeds]
    assert {p["status"] for p in points} <= {"done", "interrupted"} and "done" in {p["status"] for p in points}
    for p in points:
        if p["status"] == "done":
            assert json.loads((Path(p["run_folder"]) / "result.json").read_text())["dem"]["K_active_total"] > 0
    return points


@pytest.mark.slow
def test_ctrl_c_with_a_scheduler_keeps_the_finished_points(swept, client):
    """A real Ctrl-C (SIGINT to the command's process group) during a sweep sent to an
    existing cluster: exit 130, one line, the finished points intact. The points already
    running finish on their workers (Dask cannot stop a running task): their folders
    are whole too, so a rerun skips them."""
    out, _ = swept                   # seed 1's specimen is stored there: each point takes ~1 s
    speeds = ["0.005", "0.006", "0.007", "0.009"]
    before = set(out.glob("khosravi/*/result.json"))
    argv = ["--vary", "seed=1", "--vary", "wall_speed=" + ",".join(speeds), *sum((["--set", s] for s in TINY), []),
            "--scheduler", client.scheduler.address]
    _check_interrupted(out, *_interrupt_when_a_point_finishes(argv, out, before)[:2], speeds)
    deadline = time.monotonic() + 60        # what was running finishes on the cluster, whole
    while any(not (f / "result.json").is_file() for f in _speed_folders(out, speeds)) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert all(json.loads((f / "result.json").read_text())["seed"] == 1 for f in _speed_folders(out, speeds))


@pytest.mark.slow
def test_ctrl_c_with_the_local_cluster_stops_its_workers_at_once(swept, tmp_path):
    """Ctrl-C at the terminal reaches the command and its LocalCluster's worker
    processes: the workers keep SIGINT blocked (no traceback from each), the command
    closes them at once (a point still running is stopped, not waited for), exit 130
    and one line; no process of the command is left."""
    out, _ = swept
    speeds = ["0.011", "0.012", "0.013", "0.014"]
    before = set(out.glob("khosravi/*/result.json"))
    argv = ["--vary", "seed=1", "--vary", "wall_speed=" + ",".join(speeds), *sum((["--set", s] for s in TINY), []),
            "--workers", "2"]
    code, err, stop_s, group = _interrupt_when_a_point_finishes(argv, out, before)
    points = _check_interrupted(out, code, err, speeds)
    assert "interrupted" in {p["status"] for p in points}
    assert stop_s < 10                      # not the minutes a running point could take
    assert _group_is_gone(group)            # the workers went with it
