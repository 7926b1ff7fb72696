"""Same seed, same bits: the portable mode, and the record of which mode made a result.

A DEM run is chaotic: one ulp of difference anywhere grows into another K. Three
libraries under wallsim choose their code by the CPU they find, and the choices end
in different last bits (measured on this project's machines):

- glibc's libm (sin, cos, exp, log, pow, atan2, ...; called by the numba kernels, by
  Python's ``math``, by numpy's scalar loops and by pymunk's body rotation) has FMA
  variants that it picks when the CPU has FMA; about one call in 1,500 of sin, exp or
  pow then ends one ulp away from the plain SSE2 variant;
- numpy sends exp, log, power (any exponent but 2 and 0.5), tan, arctan, arctan2,
  arcsin, arccos, cbrt and the hyperbolic functions to AVX2 or AVX-512 loops, and its
  default argsort orders ties by the sort its SIMD level selects;
- OpenBLAS picks its kernels by CPU (dot, the norm of a vector, matmul, solve, eigh,
  lstsq) and splits sums across its threads.

numba's own code is not among them: without fastmath LLVM neither fuses (FMA) nor
reorders floating point, so the vector width of the target cannot change a bit (the pins
give the same bits for the host target, ``generic`` and ``haswell``).

The portable mode pins each library to a path that every x86-64 CPU numpy runs on
has: libm's SSE2 variant (glibc tunables mask FMA and FMA4), numpy's baseline loops (its
dispatched features disabled), OpenBLAS's Nehalem kernels on one thread. The settings
are environment variables that the libraries read when they load, so they take effect
in a process that starts with them: the ``wallsim`` command re-starts itself in them
(``enter_requested_mode``), the test suite does the same (tests/conftest.py), and a
notebook gets them when Jupyter is started from ``wallsim env`` (README). The mode a
process actually runs in is read back from the libraries (``describe``), not assumed,
and goes into every result and manifest.
"""

from __future__ import annotations

import copy
import functools
import math
import os
import sys

#: the environment variable that asks for a mode; unset means portable
MODE_VARIABLE = "WALLSIM_REPRODUCIBILITY"
MODES = ("portable", "native")

_HWCAPS = "glibc.cpu.hwcaps"
_MASK = "-FMA,-FMA4"
#: numpy >= 2.4 on x86-64: every dispatched feature group above the X86_V2 baseline
_NUMPY_DISPATCH = "X86_V3 X86_V4 AVX512_ICL AVX512_SPR"
_OPENBLAS_CORE = "Nehalem"
_REEXEC_MARK = "WALLSIM_REEXEC"

#: (function, argument, SSE2 result, FMA result): points where glibc 2.36's two
#: variants differ in the last bit (found by sampling 200,000 arguments)
_LIBM_PROBES = (
    (math.sin, "0x1.599f16db3e1c0p-1", "0x1.3ff6d3989fa4dp-1", "0x1.3ff6d3989fa4ep-1"),
    (math.exp, "0x1.99330117a2a50p+2", "0x1.2b0b46958ca7ap+9", "0x1.2b0b46958ca7bp+9"),
    (lambda x: x ** 2.5, "0x1.e170680fc40d8p+1", "0x1.b6fbd5efc0226p+4", "0x1.b6fbd5efc0227p+4"),
)


def requested_mode(environ=None) -> str:
    """The mode asked for by ``WALLSIM_REPRODUCIBILITY`` (portable when unset). Raises
    ValueError naming the variable and its valid values for anything else."""
    value = (environ if environ is not None else os.environ).get(MODE_VARIABLE, "portable").strip().lower()
    if value not in MODES:
        raise ValueError(f"{MODE_VARIABLE} = {value!r} is not valid; valid values: {' | '.join(MODES)}")
    return value


def _with_mask(tunables: str) -> str:
    """glibc tunables ('a=b:c=d') with FMA and FMA4 masked in glibc.cpu.hwcaps."""
    parts = [p for p in tunables.split(":") if p]
    for k, part in enumerate(parts):
        name, _, value = part.partition("=")
        if name == _HWCAPS:
            masked = set(value.split(","))
            parts[k] = f"{name}=" + ",".join([v for v in value.split(",") if v] +
                                             [m for m in _MASK.split(",") if m not in masked])
            return ":".join(parts)
    return ":".join(parts + [f"{_HWCAPS}={_MASK}"])


def portable_environ(environ=None) -> dict[str, str]:
    """``environ`` (default: this process's) with the portable settings added."""
    env = dict(environ if environ is not None else os.environ)
    env["GLIBC_TUNABLES"] = _with_mask(env.get("GLIBC_TUNABLES", ""))
    env["NPY_DISABLE_CPU_FEATURES"] = _NUMPY_DISPATCH
    env["OPENBLAS_CORETYPE"] = _OPENBLAS_CORE
    env["OPENBLAS_NUM_THREADS"] = "1"
    return env


def has_portable_settings(environ=None) -> bool:
    """True if ``environ`` (default: this process's) holds every portable setting."""
    environ = environ if environ is not None else os.environ
    want = portable_environ(environ)
    return all(environ.get(k) == v for k, v in want.items())


def enter_requested_mode(argv: list[str] | None = None) -> None:
    """Re-start this process (same interpreter, same arguments) in the portable
    environment when that mode is asked for and the process did not start in it. Call
    it before anything heavy is imported; it returns in a native run, in a process that
    already has the settings, and after one re-start (never loops)."""
    if requested_mode() != "portable" or has_portable_settings() or os.environ.get(_REEXEC_MARK):
        return
    env = portable_environ()
    env[_REEXEC_MARK] = "1"
    args = list(argv if argv is not None else sys.orig_argv)
    sys.stdout.flush()
    sys.stderr.flush()
    os.execve(sys.executable, [sys.executable, *args[1:]], env)


def libm_variant() -> str:
    """Which glibc libm variant this process calls: 'sse2', 'fma' or 'unknown' (another
    libm, whose last bits these probes do not know)."""
    seen = set()
    for f, x, sse2, fma in _LIBM_PROBES:
        y = f(float.fromhex(x))
        seen.add("sse2" if y == float.fromhex(sse2) else "fma" if y == float.fromhex(fma) else "unknown")
    return seen.pop() if len(seen) == 1 else "unknown"


def _numpy_simd() -> list[str]:
    """numpy's dispatched features that are active in this process (empty: baseline)."""
    from numpy._core import _multiarray_umath as umath
    return [f for f in umath.__cpu_dispatch__ if umath.__cpu_features__.get(f)]


def _cpu_model() -> str:
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    import platform
    return platform.processor() or "unknown"


def describe() -> dict:
    """The reproducibility record of this process: its mode, what the mode promises,
    and what each library was found doing. Portable means all three settings are in
    effect (libm answers as the SSE2 variant, numpy runs its baseline loops, OpenBLAS
    its fixed core on one thread). Read once per process (the libraries chose when they
    loaded); each caller gets its own copy."""
    return copy.deepcopy(_probe())


@functools.cache
def _probe() -> dict:
    libm = libm_variant()
    simd = _numpy_simd()
    blas = {k: os.environ.get(k) for k in ("OPENBLAS_CORETYPE", "OPENBLAS_NUM_THREADS")}
    portable = libm == "sse2" and not simd and blas == {"OPENBLAS_CORETYPE": _OPENBLAS_CORE,
                                                        "OPENBLAS_NUM_THREADS": "1"}
    return {
        "mode": "portable" if portable else "native",
        "same_bits": ("on any x86-64 CPU, for the same seed and the same package versions" if portable else
                      "on CPUs with the same features (FMA, numpy's SIMD level, OpenBLAS's core), for the "
                      "same seed and the same package versions; the portable mode gives the same bits "
                      "on any x86-64 CPU"),
        "libm": libm,
        "numpy_simd": simd or "baseline",
        "openblas": blas,
        "cpu": _cpu_model(),
    }


def shell_exports(environ=None) -> str:
    """The portable settings as shell ``export`` lines (``wallsim env``)."""
    import shlex
    env = portable_environ(environ)
    keys = ("GLIBC_TUNABLES", "NPY_DISABLE_CPU_FEATURES", "OPENBLAS_CORETYPE", "OPENBLAS_NUM_THREADS")
    return "\n".join(f"export {k}={shlex.quote(env[k])}" for k in keys)
