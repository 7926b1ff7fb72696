"""``wallsim bench dem3d`` takes its figures side by side: the two engines run in
alternating pairs (A B A B ...), and the report gives medians with their min-max, the
ratio as the median of the pairs' ratios (a machine whose speed drifts between pairs
moves both engines of a pair alike). Checked with stand-in engines of known speeds, so
nothing here is timed."""

from studies.bench import EngineRun, bench_dem3d


def _engine(name, rates, calls):
    def run(n, steps, threads=None, ranks=None):
        calls.append(name)
        rate = rates[sum(1 for c in calls if c == name) - 1]
        return EngineRun(n, steps, n * steps / rate, rate, 1.0, 0.1, 10, cpu_seconds=2 * n * steps / rate)
    return run


def test_engines_alternate_and_the_report_takes_medians():
    calls = []
    ours = _engine("wallsim", [10.0, 30.0, 20.0], calls)
    theirs = _engine("liggghts", [5.0, 10.0, 10.0], calls)
    r = bench_dem3d(n=100, steps=10, pairs=3, engines=(ours, theirs))
    assert calls == ["wallsim", "liggghts"] * 3
    assert r["wallsim_particle_steps_per_s"] == 20.0 and r["liggghts_particle_steps_per_s"] == 10.0
    assert r["ratio"] == 2.0                                 # pair ratios 2, 3, 2
    assert r["spread"]["ratio"] == {"median": 2.0, "min": 2.0, "max": 3.0}
    assert r["spread"]["wallsim_cpu_seconds"]["median"] == 2 * 100 * 10 / 20.0
    assert len(r["runs"]) == 3


def test_without_liggghts_only_dem3d_runs():
    calls = []
    r = bench_dem3d(n=100, steps=10, pairs=2, liggghts=False,
                    engines=(_engine("wallsim", [4.0, 6.0], calls), _engine("liggghts", [1.0], calls)))
    assert calls == ["wallsim", "wallsim"]
    assert r["wallsim_particle_steps_per_s"] == 5.0 and r["ratio"] is None and r["liggghts_ranks"] is None
