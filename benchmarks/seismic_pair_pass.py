"""What bounds the seismic model's contact pass (issue 42): pass 1 of the main model
(``dem3d.kernels.pair_forces``, Hertz-Mindlin with rolling resistance, one thread) timed
against copies of itself with one part taken out, in one process, on the same state.

The state is the default coarse case's static state (13,401 spheres, from the cache that
``wallsim validate seismic`` leaves in runs/seismic/cache), stepped 50 steps. Variants:

- ``no_rolling``: the same kernels with ``rolling=None`` (no copy);
- ``as_is``: an unedited copy of dem3d (a control: the copy itself must cost nothing);
- ``no_j_rows``: the forces and torques on the second sphere not stored (``prs.pf``);
- ``no_history``: the tangential and rolling histories not stored (``prs.ut``);
- ``distance_only``: every listed pair's distance test and nothing after it;
- ``rows_by_pair``: the rows stored by pair (``pf[k]``, in the order pass 1 visits the
  pairs) instead of by transposed position, pass 2 reading them through ``tpair``: the
  same sums in the same order (checked: equal forces and torques), timed as pass 1 alone
  and as passes 1 and 2 together, since it moves the scattered access from one pass to
  the other;
- ``direct_sums``: the engine's own ``pair_forces(..., direct=True)`` and pass 2 without a
  gather (``Simulation.direct_sums``: the forces on j added to j in pass 1, slab by slab),
  timed as passes 1 and 2.

Each variant is a copy of dem3d in a temporary folder with ``_pair_row`` (and for
``rows_by_pair`` ``gather_and_move``) edited as text, imported as its own package. The
variants run in blocks of ``--calls`` calls, all of them in turn forwards then backwards
(A B C ... C B A), ``--rounds`` times; the figures are CPU seconds (process time) per call,
medians, and each variant's ratio to the real kernels within the same round (median and
quartiles). One process, one numba thread: stop other jobs on the machine while it runs.

    NUMBA_NUM_THREADS=1 PYTHONPATH=. python benchmarks/seismic_pair_pass.py --out docs/validation/seismic_pair_pass.json
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import re
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent.parent


def _edit_pair_row(text: str, edit) -> str:
    a = text.index("def _pair_row(")
    b = text.index("@njit", a)
    new = edit(text[a:b])
    assert new != text[a:b]
    return text[:a] + new + text[b:]


def _no_j_rows(s: str) -> str:
    return re.sub(r"\n( +)pf\[kt_, \d\] (?:=|-=) [^\n]*", r"\n\1pass", s)


def _no_history(s: str) -> str:
    return re.sub(r"\n( +)ut\[k, \d\] = (?:ux|uy|uz|mx|my|mz)(?=\n)", r"\n\1pass", s)


def _distance_only(s: str) -> str:
    return s.replace("        d = math.sqrt(d2)\n", "        sfx += d2\n        continue\n        d = math.sqrt(d2)\n", 1)


def _rows_by_pair(text: str) -> str:
    text = _edit_pair_row(text, lambda s: s.replace("kt_ = tpos[k]", "kt_ = k"))
    a = text.index("def gather_and_move(")
    b = text.index("@njit", a)
    body = text[a:b]
    new = re.sub(r"\n( +)fx \+= pf\[kk, 0\]", r"\n\1kp = prs.tpair[kk]\n\1fx += pf[kp, 0]", body)
    for c, name in ((1, "fy"), (2, "fz"), (3, "tx"), (4, "ty"), (5, "tz")):
        new = new.replace(f"{name} += pf[kk, {c}]", f"{name} += pf[kp, {c}]")
    assert new.count("pf[kp,") == 6
    return text[:a] + new + text[b:]


EDITS = {"as_is": lambda t: t,
         "no_j_rows": lambda t: _edit_pair_row(t, _no_j_rows),
         "no_history": lambda t: _edit_pair_row(t, _no_history),
         "distance_only": lambda t: _edit_pair_row(t, _distance_only),
         "rows_by_pair": _rows_by_pair}


def variant_kernels(folder: Path) -> dict:
    """{name: kernels module} of edited copies of dem3d under ``folder``."""
    mods = {}
    for name, edit in EDITS.items():
        pkg = folder / f"dem3d_{name}"
        shutil.copytree(HERE / "dem3d", pkg, ignore=shutil.ignore_patterns("__pycache__"))
        k = pkg / "kernels.py"
        k.write_text(edit(k.read_text()))
    sys.path.insert(0, str(folder))
    for name in EDITS:
        mods[name] = importlib.import_module(f"dem3d_{name}.kernels")
    return mods


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=20)
    ap.add_argument("--calls", type=int, default=5)
    ap.add_argument("--cache", type=Path, default=HERE / "runs" / "seismic" / "cache")
    ap.add_argument("--out", type=Path)
    args = ap.parse_args()
    os.environ.setdefault("NUMBA_CACHE_DIR", tempfile.mkdtemp(prefix="numba_pair_pass_"))
    from dem3d import kernels
    from studies.seismic.case import SeismicCase
    from studies.seismic.run import coupled, prepare

    case = SeismicCase(direct_sums=False)        # the rows layout the variants below read
    sim, _, _, _ = coupled(case, prepare(case, args.cache))
    sim._rebuild()                 # a cached state may predate the slabs the direct sums need
    sim.step(50)
    sph, prs = sim.spheres, sim.pairs
    pax, plen = sim._periodic_args()
    mods = {"real": kernels, **variant_kernels(Path(tempfile.mkdtemp(prefix="dem3d_variants_")))}

    # rows_by_pair keeps its rows in its own array, by pair (the real one's rows moved)
    total = int(prs.start[-1])
    tpos = np.empty(total, np.int64)
    tpos[prs.tpair[:total]] = np.arange(total)
    by_pair = prs._replace(pf=prs.pf.copy())
    by_pair.pf[:total] = prs.pf[tpos]

    # the engine's direct sums (Simulation.direct_sums) write their rows by pair too
    direct_pairs = prs._replace(pf=by_pair.pf.copy())

    def pass1(mod, pairs=prs, rolling=True, direct=None):
        mod.pair_forces(sph, pairs, sim.params, sim.dt, pax, plen, sim.mtab, rolling, direct)

    def both(mod, pairs=prs, direct=None):
        pass1(mod, pairs, direct=direct)
        mod.gather_and_move(sph, pairs, sim.wall_pairs, sim.walls.panels, sim.params, sim.dt, 0.0, 0.0, 0.0,
                            0.0, 0.0, False, sim.mtab, sim.use_f_ext, sim.bonds, direct)

    # the same sums: forces and torques of passes 1 and 2 from one saved history
    # (pass 2 advances the wall contacts' histories too)
    wps = sim.wall_pairs
    history = (prs.ut, prs.active, wps.ut, wps.active, wps.out)
    saved = [a.copy() for a in history]
    results = {}
    for name, pairs in (("real", prs), ("rows_by_pair", by_pair)):
        for a, s in zip(history, saved):
            a[...] = s
        both(mods[name], pairs)
        results[name] = (sph.f.copy(), sph.t.copy())
    for a, s in zip(history, saved):
        a[...] = s
    both(mods["real"], direct_pairs, True)
    direct = (sph.f.copy(), sph.t.copy())
    same_bits = all(np.array_equal(a, b) for a, b in zip(results["real"], results["rows_by_pair"]))
    scale = [np.abs(a).max() for a in results["real"]]
    direct_diff = max(float(np.abs(a - b).max() / s) for a, b, s in zip(results["real"], direct, scale))

    runs = {"pass1 real": lambda: pass1(mods["real"]),
            "pass1 no_rolling": lambda: pass1(mods["real"], rolling=None),
            **{f"pass1 {n}": (lambda m=mods[n], pr=(by_pair if n == "rows_by_pair" else prs): pass1(m, pr))
               for n in EDITS},
            "pass1+2 real": lambda: both(mods["real"]),
            "pass1+2 rows_by_pair": lambda: both(mods["rows_by_pair"], by_pair),
            "pass1+2 direct_sums": lambda: both(mods["real"], direct_pairs, True)}

    def block(fn) -> float:
        c = time.process_time()
        for _ in range(args.calls):
            fn()
        return (time.process_time() - c) / args.calls

    for fn in runs.values():            # compile or load, warm the caches
        block(fn)
    times = {name: [] for name in runs}
    order = list(runs)
    for _ in range(args.rounds):
        for name in order + order[::-1]:
            times[name].append(block(runs[name]))
    rows = {}
    for name, ts in times.items():
        base = times["pass1+2 real" if name.startswith("pass1+2") else "pass1 real"]
        ratio = [t / b for t, b in zip(ts, base)]
        q = statistics.quantiles(ratio, n=4)
        rows[name] = {"ms_per_call": 1e3 * statistics.median(ts), "ratio_to_real": statistics.median(ratio),
                      "ratio_quartiles": [q[0], q[2]]}
        print(f"{name:24s} {rows[name]['ms_per_call']:7.3f} ms  x{rows[name]['ratio_to_real']:.3f} "
              f"({q[0]:.3f}-{q[2]:.3f})", flush=True)
    summary = {"spheres": sim.n_spheres, "pairs_listed": total, "pairs_touching": int(prs.active[:total].sum()),
               "rounds": args.rounds, "calls_per_block": args.calls, "rows_by_pair_same_bits": same_bits,
               "direct_sums_max_difference_over_max_load": direct_diff,
               "load_average_1min": os.getloadavg()[0], "variants": rows}
    print(json.dumps({k: v for k, v in summary.items() if k != "variants"}))
    if args.out:
        args.out.write_text(json.dumps(summary, indent=1) + "\n")
    os._exit(0)


if __name__ == "__main__":
    main()
