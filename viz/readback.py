"""Read a wallsim .rrd back (tests, reports). Uses ``rerun.chunk`` (rerun-sdk 0.41):
no viewer, no server, no datafusion."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import rerun.chunk as ch


def summary(path: str | Path) -> str:
    """The chunk store's own summary: entity / rows / static / timelines / columns."""
    return str(ch.RrdReader(str(path)).store().summary())


def _batches(path, entity: str, component: str, static: bool = False):
    stream = (ch.RrdReader(str(path)).store().stream()
              .filter(content=entity, is_static=static, components=component))
    return [c.to_record_batch() for c in stream.to_chunks()]


def entity_paths(path: str | Path) -> set[str]:
    """Entity paths that hold data (static or temporal)."""
    out = set()
    for line in summary(path).splitlines():
        tok = line.strip().split()
        if tok and tok[0].startswith("/"):
            out.add(tok[0])
    return out


def read_scalars(path: str | Path, entity: str, timeline: str = "step") -> tuple[np.ndarray, np.ndarray]:
    """(times, values) of a Scalars series, sorted by the timeline."""
    batches = _batches(path, entity, "Scalars:scalars")
    if not batches:
        return np.array([]), np.array([])
    t = np.concatenate([b.column(timeline).to_numpy() for b in batches])
    v = np.concatenate([np.array(b.column("Scalars:scalars").to_pylist(), dtype=float) for b in batches])
    o = np.argsort(t, kind="stable")
    v = v[o]
    if v.ndim == 2 and v.shape[1] == 1:
        v = v[:, 0]
    return t[o], v


def read_positions(path: str | Path, entity: str, archetype: str = "Points3D",
                   timeline: str = "step") -> tuple[np.ndarray, list[np.ndarray]]:
    """(times, list of (n, d) position arrays) of a points entity, sorted by time."""
    comp = f"{archetype}:positions"
    batches = _batches(path, entity, comp)
    times, frames = [], []
    for b in batches:
        ts = b.column(timeline).to_numpy()
        for t, rows in zip(ts, b.column(comp).to_pylist()):
            if rows is None:
                continue
            times.append(t)
            frames.append(np.array(rows, dtype=float))
    o = np.argsort(np.array(times), kind="stable")
    return np.array(times)[o], [frames[i] for i in o]


def read_column(path: str | Path, entity: str, component: str,
                timeline: str = "step") -> tuple[np.ndarray, list[np.ndarray]]:
    """(times, list of arrays) of any component (e.g. ``Points3D:colors`` as packed
    0xRRGGBBAA, ``Boxes3D:centers``), sorted by the timeline; rows with no value left out."""
    times, values = [], []
    for b in _batches(path, entity, component):
        for t, rows in zip(b.column(timeline).to_numpy(), b.column(component).to_pylist()):
            if rows is not None:
                times.append(t)
                values.append(np.array(rows))
    o = np.argsort(np.array(times), kind="stable")
    return np.array(times)[o], [values[i] for i in o]
