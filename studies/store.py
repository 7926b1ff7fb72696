"""One store for everything a run keeps for the next one: settled specimens, mid-run
checkpoints, calibration tests and cards.

An entry is named by a content key, the hash of everything that shapes it
(``content_key``), so a changed setting never reuses a stale entry; every write goes to
a temporary file first and is renamed into place (``atomic_write``), so an interrupted
run never leaves half a file for the next one to read.
"""

from __future__ import annotations

import dataclasses
import hashlib
import io
import json
import math
import os
import tempfile
from pathlib import Path

import numpy as np

from analytic.schema import left_out_of_keys


def to_plain(obj, *, for_key: bool = False):
    """Dataclasses, numpy scalars/arrays and paths -> JSON/TOML-friendly Python values;
    ``for_key``: without the fields a content key leaves out (``schema.left_out_of_keys``)."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: to_plain(getattr(obj, f.name), for_key=for_key) for f in dataclasses.fields(obj)
                if not (for_key and left_out_of_keys(obj, f))}
    if isinstance(obj, dict):
        return {str(k): to_plain(v, for_key=for_key) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_plain(v, for_key=for_key) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_plain(obj.tolist())
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def content_key(obj, length: int = 16) -> str:
    """Hex SHA-256 of ``obj`` as sorted JSON (dataclasses and numpy values made plain,
    fields added later left out while they hold what earlier runs had), cut to
    ``length`` characters."""
    blob = json.dumps(to_plain(obj, for_key=True), sort_keys=True)
    return hashlib.sha256(blob.encode()).hexdigest()[:length]


def _umask() -> int:
    """The process's umask (read by setting it and putting it back)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def atomic_write(path: str | Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` through a temporary file renamed into place, with the
    permissions any other file the user creates gets (mkstemp alone makes it 0600)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    # a temporary name of its own: two runs writing the same entry must not share one
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name + ".", suffix=".tmp")
    try:
        os.fchmod(fd, 0o666 & ~_umask())
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def npz_bytes(arrays: dict) -> bytes:
    """``arrays`` as the bytes of an uncompressed .npz (what ``np.savez`` writes)."""
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def load_npz(path: str | Path) -> dict:
    with np.load(path, allow_pickle=False) as data:
        return {k: data[k] for k in data.files}


class Store:
    """A folder of keyed entries: ``<key>.npz`` + ``<key>.json`` (arrays and what they
    are), ``<key><suffix>`` bytes, or ``<key>.json`` alone."""

    def __init__(self, folder: str | Path):
        self.folder = Path(folder)

    def path(self, key: str, suffix: str) -> Path:
        return self.folder / f"{key}{suffix}"

    def load_arrays(self, key: str) -> tuple[dict, dict] | None:
        """(arrays, metadata) stored under ``key``, or None."""
        npz, meta = self.path(key, ".npz"), self.path(key, ".json")
        if not (npz.exists() and meta.exists()):
            return None
        return load_npz(npz), json.loads(meta.read_text())

    def save_arrays(self, key: str, arrays: dict, meta: dict) -> None:
        """Arrays first, metadata (JSON-ready: NaN stays NaN) last: an entry counts as
        present once both exist."""
        atomic_write(self.path(key, ".npz"), npz_bytes(arrays))
        atomic_write(self.path(key, ".json"), json.dumps(meta, indent=1).encode())

    def load_bytes(self, key: str, suffix: str) -> bytes | None:
        p = self.path(key, suffix)
        return p.read_bytes() if p.exists() else None

    def save_bytes(self, key: str, suffix: str, data: bytes) -> Path:
        return atomic_write(self.path(key, suffix), data)

    def discard(self, key: str, suffix: str) -> None:
        self.path(key, suffix).unlink(missing_ok=True)

    def load_json(self, key: str) -> dict | None:
        p = self.path(key, ".json")
        return json.loads(p.read_text()) if p.exists() else None

    def save_json(self, key: str, obj) -> Path:
        return atomic_write(self.path(key, ".json"), (json.dumps(to_plain(obj), indent=2) + "\n").encode())


def find_card_entry(paths, match) -> tuple[dict, Path] | None:
    """The first entry of the calibration cards at ``paths`` (searched in order; missing
    files skipped) for which ``match(entry)`` holds, and the card it came from. An
    entry is one of a card's "tests", or the card itself when it has none (a triaxial
    card is one test). The one look-up of phi behind every study's theories."""
    for path in map(Path, [paths] if isinstance(paths, (str, Path)) else paths):
        if not path.is_file():
            continue
        card = json.loads(path.read_text())
        for entry in card.get("tests", [card]):
            if match(entry):
                return entry, path
    return None


def read_report(out_dir: str | Path, name: str) -> dict:
    """The validation report ``name`` (e.g. heap.json) that ``out_dir`` holds, for a
    rewrite without runs; a folder without it is the user's --docs, named in the error."""
    path = Path(out_dir) / name
    if not path.is_file():
        from analytic.errors import InvalidParameter
        raise InvalidParameter("--docs", str(out_dir), f"a folder holding {name}", "there is no report to rewrite")
    return json.loads(path.read_text())
