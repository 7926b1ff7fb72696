"""Check the bit-for-bit pins in this process and print every one that differs.

``tests/dem3d/test_lesser_cpu.py`` runs it in a child process whose libraries see a lesser
CPU than the machine's (numba compiling for the baseline x86-64, glibc's libm without
AVX); ``python -m tests.lesser_cpu`` runs it as the process finds itself. Exit 0 when
every pin holds, 1 otherwise (one line per difference on stdout).
"""

from __future__ import annotations

import sys


def differences() -> list[str]:
    """Every dem3d state hash that differs from its pin. Only those: what the emulation
    changes is numba's code and libm's variant, and these cases run the kernel paths of
    the single-material studies (random placement, both contact laws, clumps, periodic
    slabs, translating and rotating segmented walls, re-sorting); the rest of a study is
    numpy, which the portable mode runs on its baseline anyway. Not pinned anywhere yet:
    bonds, material tables and rolling resistance (the seismic study's kernels)."""
    from tests.dem3d.test_pinning import CASES, PINNED, state_hash

    out = []
    for name, build in CASES.items():
        got = state_hash(build())
        if got != PINNED[name]:
            out.append(f"dem3d {name}: {PINNED[name]} -> {got}")
    return out


def main() -> int:
    diff = differences()
    for line in diff:
        print(line)
    return 1 if diff else 0


if __name__ == "__main__":
    sys.exit(main())
