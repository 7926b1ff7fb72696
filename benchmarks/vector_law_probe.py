"""Would a vectorised contact law make dem3d's contact pass twice as fast? A probe on the
LIGGGHTS benchmark problem (studies.bench, 30,000 spheres, linear law, absolute damping,
Coulomb cap on |Fn|; one numba thread).

The real pass 1 (``kernels.pair_forces``, rows) computes each touching pair's law where it
finds the pair, scalar code. The probe's pass computes the same forces in three stages per
block of spheres: the distance test, gathering the touching pairs' inputs into a small
structure-of-arrays buffer (``CAP`` pairs, 26 arrays, in L1/L2), the law over the buffer
in a loop without branches that LLVM turns into AVX2 code (checked: packed square roots
and divisions, ``vsqrtpd`` / ``vdivpd``, in ``law_buffer``'s machine code), then the sums
on each sphere in the pairs' order and the rows of the second spheres. The results are
the real pass's bit for bit (checked: forces, torques, rows, histories, flags), so only
the time differs.

LLVM vectorises ``law_buffer`` only with its limit on runtime alias checks raised (26
arrays; the default of 8 leaves it scalar), set here through llvmlite for this process
only. Timed: the real pass, the probe's, and the probe's without the law (the gather and
the scatter alone), each as the CPU time of 20 passes on one state, interleaved over
``--rounds`` rounds (A B C, then C B A).

    PYTHONPATH=. python benchmarks/vector_law_probe.py --out docs/validation/vector_law_probe.json
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import re
import statistics
import time
from pathlib import Path

import llvmlite.binding as llvm

# before anything is compiled: the law's loop reads and writes 26 arrays
llvm.set_option("", "-runtime-memory-check-threshold=400")
llvm.set_option("", "-vectorize-memory-check-threshold=400")

import numpy as np  # noqa: E402
from numba import njit, prange  # noqa: E402

from dem3d.kernels import min_image  # noqa: E402

#: pairs per buffer (26 arrays x 128 x 8 B = 26 KB); 64 and 512 were slower
CAP = 128


@njit(error_model="numpy")
def law_buffer(m, DX, DY, DZ, RI, RJ, DVX, DVY, DVZ, WIX, WIY, WIZ, WJX, WJY, WJZ, UX, UY, UZ,
               FX, FY, FZ, FN, AI, AJ, CX, CY, CZ, kn, ks, cn, ct, mu, dt):
    """kernels.contact_law (linear, absolute damping, Coulomb on |Fn|) over m buffered pairs,
    every branch a select of values computed on both sides (the same operations, the same
    bits)."""
    for q in range(m):
        dx = DX[q]
        dy = DY[q]
        dz = DZ[q]
        d2 = dx * dx + dy * dy + dz * dz
        rs = RI[q] + RJ[q]
        d = math.sqrt(d2)
        inv_d = 1.0 / d
        nx = dx * inv_d
        ny = dy * inv_d
        nz = dz * inv_d
        delta = rs - d
        h = 0.5 * delta
        ai = RI[q] - h
        aj = RJ[q] - h
        wx = ai * WIX[q] + aj * WJX[q]
        wy = ai * WIY[q] + aj * WJY[q]
        wz = ai * WIZ[q] + aj * WJZ[q]
        vrx = DVX[q] + (wy * nz - wz * ny)
        vry = DVY[q] + (wz * nx - wx * nz)
        vrz = DVZ[q] + (wx * ny - wy * nx)
        vn = vrx * nx + vry * ny + vrz * nz
        vtx = vrx - vn * nx
        vty = vry - vn * ny
        vtz = vrz - vn * nz
        fn = kn * delta + cn * vn
        ux = UX[q]
        uy = UY[q]
        uz = UZ[q]
        un = ux * nx + uy * ny + uz * nz
        px = ux - un * nx
        py = uy - un * ny
        pz = uz - un * nz
        p2 = px * px + py * py + pz * pz
        e = un * un / p2
        s_small = 1.0 + e * (0.5 - 0.125 * e)
        s_big = math.sqrt(1.0 + e)
        s = s_small if e < 1e-4 else s_big
        rot = un != 0.0
        scl = rot & (p2 > 0.0)
        qx = px * s
        qy = py * s
        qz = pz * s
        px = qx if scl else px
        py = qy if scl else py
        pz = qz if scl else pz
        ux = (px if rot else ux) + vtx * dt
        uy = (py if rot else uy) + vty * dt
        uz = (pz if rot else uz) + vtz * dt
        ftx = -ks * ux - ct * vtx
        fty = -ks * uy - ct * vty
        ftz = -ks * uz - ct * vtz
        cap = abs(fn)
        fmax0 = mu * cap
        fmax = fmax0 if cap > 0.0 else 0.0
        ft2 = ftx * ftx + fty * fty + ftz * ftz
        slide = ft2 > fmax * fmax
        scale = fmax / math.sqrt(ft2)
        gx = ftx * scale
        gy = fty * scale
        gz = ftz * scale
        ftx = gx if slide else ftx
        fty = gy if slide else fty
        ftz = gz if slide else ftz
        sx = -(ftx + ct * vtx) / ks
        sy = -(fty + ct * vty) / ks
        sz = -(ftz + ct * vtz) / ks
        UX[q] = sx if slide else ux
        UY[q] = sy if slide else uy
        UZ[q] = sz if slide else uz
        fx = -fn * nx + ftx
        fy = -fn * ny + fty
        fz = -fn * nz + ftz
        FX[q] = fx
        FY[q] = fy
        FZ[q] = fz
        FN[q] = fn
        AI[q] = ai
        AJ[q] = aj
        CX[q] = ny * fz - nz * fy
        CY[q] = nz * fx - nx * fz
        CZ[q] = nx * fy - ny * fx


@njit(parallel=True, error_model="numpy")
def pass_buffered(x, v, w, r, f, t, start, nbr, tpos, ut, active, pf, kn, ks, cn, ct, mu, dt, pax, plen,
                  n_chunks, with_law):
    """Pass 1 (rows) of kernels.pair_forces for the probe's law: per block of spheres,
    distance test and gather, ``law_buffer`` (skipped without ``with_law``), scatter."""
    n = x.shape[0]
    for c in prange(n_chunks):
        buf = np.empty((26, CAP))
        K = np.empty(CAP, np.int64)
        I = np.empty(CAP, np.int64)   # noqa: E741
        i = c * n // n_chunks
        i1 = (c + 1) * n // n_chunks
        while i < i1:
            first = i
            m = 0
            while i < i1 and m + (start[i + 1] - start[i]) <= CAP:
                m = _gather(i, m, x, v, w, r, start, nbr, tpos, ut, active, pf, pax, plen, buf, K, I)
                i += 1
            if with_law:
                law_buffer(m, buf[0], buf[1], buf[2], buf[3], buf[4], buf[5], buf[6], buf[7], buf[8], buf[9],
                           buf[10], buf[11], buf[12], buf[13], buf[14], buf[15], buf[16], buf[17], buf[18],
                           buf[19], buf[20], buf[21], buf[22], buf[23], buf[24], buf[25], kn, ks, cn, ct, mu, dt)
            _scatter(first, i, m, f, t, ut, active, pf, tpos, buf, K, I)


@njit(inline="always", error_model="numpy")
def _gather(i, m, x, v, w, r, start, nbr, tpos, ut, active, pf, pax, plen, buf, K, I):   # noqa: E741
    xi = x[i, 0]
    yi = x[i, 1]
    zi = x[i, 2]
    ri = r[i]
    for k in range(start[i], start[i + 1]):
        j = nbr[k]
        dx, dy, dz = min_image(x[j, 0] - xi, x[j, 1] - yi, x[j, 2] - zi, pax, plen)
        rs = ri + r[j]
        d2 = dx * dx + dy * dy + dz * dz
        if d2 >= rs * rs:
            if active[k]:
                active[k] = 0
                ut[k, 0] = 0.0
                ut[k, 1] = 0.0
                ut[k, 2] = 0.0
                for cc in range(8):
                    pf[tpos[k], cc] = 0.0
            continue
        K[m] = k
        I[m] = i
        buf[0, m] = dx
        buf[1, m] = dy
        buf[2, m] = dz
        buf[3, m] = ri
        buf[4, m] = r[j]
        for a in range(3):
            buf[5 + a, m] = v[i, a] - v[j, a]
            buf[8 + a, m] = w[i, a]
            buf[11 + a, m] = w[j, a]
            buf[14 + a, m] = ut[k, a]
        m += 1
    return m


@njit(inline="always", error_model="numpy")
def _scatter(first, last, m, f, t, ut, active, pf, tpos, buf, K, I):   # noqa: E741
    for s in range(first, last):
        for a in range(3):
            f[s, a] = 0.0
            t[s, a] = 0.0
    for q in range(m):
        k = K[q]
        s = I[q]
        active[k] = 1
        kt_ = tpos[k]
        ai = buf[21, q]
        aj = buf[22, q]
        for a in range(3):
            ut[k, a] = buf[14 + a, q]
            f[s, a] += buf[17 + a, q]
            t[s, a] += ai * buf[23 + a, q]
            pf[kt_, a] = -buf[17 + a, q]
            pf[kt_, 3 + a] = aj * buf[23 + a, q]
        pf[kt_, 6] = buf[20, q]


def _cpu_model() -> str:
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        return platform.machine()
    found = re.search(r"^model name\s*:\s*(.+)$", text, re.M)
    return found.group(1) if found else platform.machine()


def _vector_ops(fn) -> dict:
    asm = "".join(fn.inspect_asm().values())
    return {op: len(re.findall(op, asm)) for op in ("vsqrtpd", "vsqrtsd", "vdivpd", "vdivsd")}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=16)
    ap.add_argument("--passes", type=int, default=20, help="passes per timed block (20)")
    ap.add_argument("--out", type=Path)
    args = ap.parse_args()
    import numba

    from dem3d import kernels
    from studies.bench import build_problem
    numba.set_num_threads(1)
    sim = build_problem(30_000)
    sim.step(50)
    prm, sph, prs = sim.params, sim.spheres, sim.pairs
    assert (prm.law, prm.damping, prm.coulomb) == (kernels.LINEAR, kernels.ABSOLUTE, 1), "the probe's law only"
    pax, plen = sim._periodic_args()
    names = ("f", "t", "pf", "ut", "active")

    def state():
        return {k: getattr(sph if k in ("f", "t") else prs, k).copy() for k in names}

    def restore(s):
        for k in names:
            getattr(sph if k in ("f", "t") else prs, k)[:] = s[k]

    def real():
        kernels.pair_forces(sph, prs, prm, sim.dt, pax, plen, None, None, None)

    def buffered(with_law=True):
        pass_buffered(sph.x, sph.v, sph.w, sph.r, sph.f, sph.t, prs.start, prs.nbr, prs.tpos, prs.ut, prs.active,
                      prs.pf, prm.kn, prm.ks, prm.damp_n, prm.damp_s, prm.mu, sim.dt, pax, plen, 64, with_law)

    s0 = state()
    real()
    want = state()
    restore(s0)
    buffered()
    got = state()
    total = int(prs.start[-1])
    same = {k: bool(np.array_equal(want[k][:total] if k in ("pf", "ut", "active") else want[k],
                                   got[k][:total] if k in ("pf", "ut", "active") else got[k])) for k in names}
    runs = {"real": real, "buffered": buffered, "gather_scatter_only": lambda: buffered(False)}
    cpu = {k: [] for k in runs}
    for rnd in range(args.rounds):
        for name in (list(runs) if rnd % 2 == 0 else list(runs)[::-1]):
            restore(s0)
            c = time.process_time()
            for _ in range(args.passes):
                runs[name]()
            cpu[name].append((time.process_time() - c) / args.passes)

    def ratio(name):
        r = [b / a for a, b in zip(cpu["real"], cpu[name])]
        q = statistics.quantiles(r, n=4)
        return {"median": statistics.median(r), "quartiles": [q[0], q[2]]}

    out = {"cpu": _cpu_model(), "load_average_1min": os.getloadavg()[0],
           "listed_pairs": total, "touching_pairs": int(prs.active[:total].sum()), "pairs_per_buffer": CAP,
           "same_bits_as_the_real_pass": same, "law_buffer_machine_code": _vector_ops(law_buffer),
           "pass_ms": {k: 1e3 * statistics.median(v) for k, v in cpu.items()},
           "time_over_the_real_pass": {k: ratio(k) for k in ("buffered", "gather_scatter_only")},
           "rounds": args.rounds, "passes_per_block": args.passes, "threads": 1}
    print(json.dumps(out, indent=1))
    if args.out:
        args.out.write_text(json.dumps(out, indent=1) + "\n")
    os._exit(0)


if __name__ == "__main__":
    main()
