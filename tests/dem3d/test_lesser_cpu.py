"""The pins hold on a lesser CPU than this machine's (issue 37).

The suite itself runs in the portable mode (tests/conftest.py). Here a child process
also sees a lesser CPU than the machine's, as far as the libraries can tell: numba
compiles for the baseline x86-64 target (SSE2, no AVX, no FMA), and glibc's libm,
besides FMA, loses AVX and AVX2 (its SSE2 variant instead of the AVX one). The pins it
checks (tests/lesser_cpu.py) are the same numbers the suite checks on this machine, so
a pin that passes both holds on the machine's CPU and on the baseline one. numpy and
OpenBLAS need no emulation: the portable mode already runs their baseline code, whatever
the CPU.
"""

import subprocess
import sys
from pathlib import Path

import pytest

import reproducibility
from tests.conftest import portable_only

ROOT = Path(__file__).resolve().parents[2]


def lesser_cpu_environ() -> dict:
    env = reproducibility.portable_environ()
    env["NUMBA_CPU_NAME"] = "generic"
    env["GLIBC_TUNABLES"] += ",-AVX,-AVX2,-AVX512F"
    return env


@portable_only
@pytest.mark.slow
def test_pins_hold_when_the_libraries_see_a_baseline_cpu():
    env = lesser_cpu_environ()
    assert env["GLIBC_TUNABLES"].endswith("-FMA,-FMA4,-AVX,-AVX2,-AVX512F"), env["GLIBC_TUNABLES"]
    run = subprocess.run([sys.executable, "-m", "tests.lesser_cpu"], cwd=ROOT, env=env, capture_output=True,
                         text=True, timeout=1800)
    assert run.returncode == 0, (run.stdout + run.stderr)[-3000:]
    # the child really ran in the portable mode on the baseline target
    probe = subprocess.run([sys.executable, "-c", "import json, numba, reproducibility; "
                            "print(json.dumps([reproducibility.describe()['mode'], numba.config.CPU_NAME]))"],
                           cwd=ROOT, env=env, capture_output=True, text=True, timeout=120)
    assert probe.stdout.strip() == '["portable", "generic"]', probe.stderr[-500:]
