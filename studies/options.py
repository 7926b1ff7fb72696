"""Parsers and flags shared by the studies' commands. Each parser turns the text a user
typed into a value or raises ``InvalidParameter`` naming the flag and its valid range."""

from __future__ import annotations

import math
import os
from pathlib import Path

from analytic.errors import InvalidParameter
from analytic.inputs import _range_text, require_number

from .study import Option


def number(name: str, lo=None, hi=None, *, lo_open=True, hi_open=True, unit=""):
    """A finite float in a range."""
    def parse(text: str) -> float:
        return require_number(name, text, lo, hi, lo_open=lo_open, hi_open=hi_open, unit=unit)
    parse.__name__ = name
    return parse


def count(name: str):
    """A whole number >= 1."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = 0
        if value < 1:
            raise InvalidParameter(name, text, ">= 1")
        return value
    parse.__name__ = name
    return parse


def number_list(name: str, scale: float = 1.0, *, lo=None, hi=None, unit=""):
    """'0.3,0.5,0.7' -> (0.3, 0.5, 0.7) (times ``scale``); numbers >= 0, or (``lo``, ``hi``
    given) each in that open range, the range the case record itself checks; an empty
    item ('2,,5') is refused, not dropped."""
    if lo is None and hi is None:
        valid = "a comma-separated list of numbers >= 0"
    elif hi is None:
        valid = f"a comma-separated list of numbers > {lo:g}" + (f" {unit}" if unit else "")
    else:
        valid = "a comma-separated list of numbers in " + _range_text(lo, hi, True, True, unit)

    def parse(text: str) -> tuple[float, ...]:
        items = [x.strip() for x in text.split(",")]
        if any(not x for x in items):
            raise InvalidParameter(name, text, valid, "an empty item")
        try:
            vals = tuple(float(x) * scale for x in items)
        except ValueError:
            raise InvalidParameter(name, text, valid) from None
        bad = (lambda v: v < 0) if lo is None and hi is None else \
            (lambda v: (lo is not None and v <= lo) or (hi is not None and v >= hi))
        if not vals or any(not math.isfinite(v) or bad(v) for v in vals):
            raise InvalidParameter(name, text, valid)
        return vals
    parse.__name__ = name
    return parse


def kpa_to_pa(value: float) -> float:
    return value * 1e3


def _probe(folder: Path) -> str | None:
    """Why a file cannot be created in the existing folder ``folder`` (None: it can). A
    file is made and removed: permission bits alone pass /proc or a read-only mount."""
    import tempfile
    try:
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=".wallsim-probe-")
        os.close(fd)
        os.unlink(tmp)
    except OSError as err:
        return err.strerror or type(err).__name__
    return None


def output_file(name: str, suffixes: tuple[str, ...]):
    """A path to write: a known suffix and an existing folder a file can be created in
    (checked before the run, so a long run never ends on a file it cannot write)."""
    def parse(text: str) -> str:
        path = Path(text)
        if path.suffix.lower() not in suffixes:
            raise InvalidParameter(name, text, "a file name ending in " + " or ".join(suffixes))
        folder = path.parent if str(path.parent) else Path(".")
        if not folder.is_dir():
            raise InvalidParameter(name, text, "a path in an existing folder", f"no folder {folder}")
        why = "it is a folder" if path.is_dir() else _probe(folder)
        if why or (path.exists() and not os.access(path, os.W_OK)):
            raise InvalidParameter(name, text, "a writable file path", why or f"{path} is read-only")
        return text
    parse.__name__ = name
    return parse


def _existing_ancestor(path: Path) -> Path:
    probe = path
    while not probe.exists() and probe != probe.parent:
        probe = probe.parent
    return probe


def output_folder(name: str):
    """A folder to write into: it exists and files can be made in it, or its nearest
    existing parent can hold it (nothing is created until the run starts)."""
    def parse(text: str) -> str:
        writable_root(name, text)
        return text
    parse.__name__ = name
    return parse


def writable_root(name: str, text: str) -> Path:
    """``text`` as a folder the run can create and write, checked without creating it
    (no folder is left behind by a command refused later); InvalidParameter if not."""
    path = Path(text)
    if not text:
        raise InvalidParameter(name, text, "a writable folder")
    base = _existing_ancestor(path)
    if not base.is_dir():
        raise InvalidParameter(name, text, "a writable folder", f"{base} is a file")
    why = _probe(base)
    if why:
        raise InvalidParameter(name, text, "a writable folder", f"{base}: {why}")
    return path


def scheduler_address(name: str):
    """A Dask scheduler address, ``[tcp|tls|ws|wss|inproc|ucx]://host:port`` or ``host:port``
    (what dask.distributed accepts; it raises a traceback on anything else)."""
    import re
    form = re.compile(r"^(?:(?:tcp|tls|ws|wss|inproc|ucx)://)?[A-Za-z0-9_.\-\[\]:]*[A-Za-z0-9_.\-\]]:\d{1,5}$")

    def parse(text: str) -> str:
        if not form.match(text) or not 0 < int(text.rsplit(":", 1)[1]) < 65536:
            raise InvalidParameter(name, text, "a Dask scheduler address, e.g. tcp://host:8786")
        return text
    parse.__name__ = name
    return parse


def writable_folder(name: str, text: str) -> Path:
    """Make the folder ``text`` (and its parents) and write a probe file in it, so a long
    run never ends on a folder it cannot write; InvalidParameter naming ``name`` if not."""
    path = Path(text)
    try:
        path.mkdir(parents=True, exist_ok=True)
        probe = path / f".wallsim-probe-{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as err:
        raise InvalidParameter(name, text, "a folder that can be created and written",
                               err.strerror or type(err).__name__) from None
    return path


#: the flag of every command that resumes an interrupted run (the envelope reads the
#: folder's config.toml; the study continues from its checkpoint)
RESUME = Option("--resume", "continue an interrupted run from its folder (its config.toml and run options)",
                metavar="RUN_DIR")

#: the recording flags of the 3D runs
RECORDING = (
    Option("--rrd", "recording path (default: recording.rrd in the run folder; written unless --no-rrd)",
           metavar="FILE", parse=output_file("rrd", (".rrd",)), optional=True),
    Option("--no-rrd", "write no recording", switch=True),
    Option("--spawn", "also open the Rerun viewer", switch=True),
    Option("--every", "log the scene (particles, chains) every N x 500 steps (5)", parse=count("every"), default=5),
)

#: the VTK export of the DEM commands (viz/vtk.py): the frames the recording logs, also as
#: VTK files for ParaView, whether or not a Rerun recording is written
VTK = Option("--vtk", "also write the recorded frames as VTK files for ParaView (vtk/ in the run folder: "
                      "particles, contacts, walls, blocks; one .pvd per kind)", switch=True)
