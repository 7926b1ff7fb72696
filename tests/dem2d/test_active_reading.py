"""Where the Khosravi case reads its active state: at Khosravi et al.'s Dis/H = 0.003, even
when the wall moves on further (so that the steadiness after it can be judged)."""

from types import SimpleNamespace

from studies.khosravi.case import KhosraviCase
from studies.khosravi.compare import active_record


def _run(wall_disp_over_H_max: float, H: float = 0.3):
    case = KhosraviCase(wall_disp_over_H_max=wall_disp_over_H_max)
    step = 0.0005 * H                       # one reading per Dis/H 0.0005
    n = int(round(wall_disp_over_H_max * H / step))
    history = [SimpleNamespace(dis=(k + 1) * step) for k in range(n)]
    return SimpleNamespace(case=case, backfill=SimpleNamespace(H=H), history=history)


def test_active_state_is_read_at_the_papers_0_003_when_the_wall_moves_on_to_0_01():
    run = _run(0.01)
    assert abs(active_record(run).dis / 0.3 - 0.003) < 1e-12
    assert run.history[-1].dis / 0.3 > 0.0099


def test_a_wall_that_stops_before_0_003_is_read_where_it_stopped():
    run = _run(0.001)
    assert active_record(run) is run.history[-1]
