"""VTK files of a run for ParaView: per recorded frame, the particles as points, the
contacts as lines, the wall panels and blocks as polygons; and one ``.pvd`` collection
per kind with the simulation time of each frame (what ParaView's time slider reads).

Written with pyevtk: binary VTU (appended raw data, little endian) and the .pvd
collections, so no XML is written by hand here. Float data stay float64 so a force read
back is the force the run computed (the test sums them to the run's own thrust). 2D
runs are written as z = 0 geometry, their vectors with a zero z component, forces per
metre of wall.

The folder (``vtk/`` in the run folder) holds ``<kind>_<step>.vtu`` files, ``<kind>.pvd``
and ``frames.jsonl``, the index: one line appended per file written (and the writing
time), from which the collections are rebuilt every ``FLUSH_EVERY`` files and at the
end, and from which a resumed run goes on (its frames join those written before the
interruption). Appending keeps a long run's cost per frame constant; an interrupted run's
.pvd may lag its last files, which its resume writes again. Files are written whole (a
temporary name, then a rename): an interrupted run leaves readable files only.

Kinds and their arrays (units SI; 2D forces N/m):

* ``particles``: vertices; ``radius`` [m], ``velocity`` [m/s], ``force`` (contact force on
  the sphere / body, when the engine gives it) [N], ``body_id`` (clump or body), ``material``
* ``contacts``: lines between the two centres; ``normal_force`` (compression +) [N],
  ``shear_force`` (magnitude) [N]; in a run with parallel bonds the intact bonds follow
  the touching pairs as lines of their own, ``bonded`` 1 (0 for a contact)
* ``walls``: panels (3D quadrilaterals, 2D segments); ``panel`` (index in the run's
  panel order), ``force`` (by the particles on the panel) [N], ``normal`` (into the
  fill), ``area`` [m^2; m in 2D], ``normal_stress`` (compression +) [Pa]
* ``blocks``: polygons of rigid blocks (a block wall) with ``displacement`` [m] and any
  per-block forces the run gives (e.g. ``water_force``) [N/m]
* ``grains``: polygons of polygonal grains (a fill of them), ``held`` (1: held fixed)
* ``polygons``: the polygonal bodies of a frame (e.g. a gravel biaxial specimen)
* ``joints``: points, ``normal_force`` of each block contact [N/m]
* ``points``: any other point set a study logs with a value per point (e.g. the sheet
  pile's balls with their bending moment)
"""

from __future__ import annotations

import json
import os
import time as _time
from pathlib import Path

import numpy as np
from pyevtk.hl import unstructuredGridToVTK
from pyevtk.vtk import VtkGroup, VtkLine, VtkPolygon, VtkVertex

from analytic.frame import panel_normal_stress

#: the index of the files written (JSON lines), from which every .pvd is rebuilt
INDEX = "frames.jsonl"
#: files written between two rebuilds of the collections
FLUSH_EVERY = 20


def _read_index(folder: Path) -> tuple[dict[str, list[list]], float]:
    """(kind -> [[time, file], ...] in time order, write seconds) from the index; a file
    written again replaces its earlier line."""
    frames: dict[str, dict[str, float]] = {}
    seconds = 0.0
    index = folder / INDEX
    if index.is_file():
        for line in index.read_text().splitlines():
            rec = json.loads(line)
            if "file" in rec:
                frames.setdefault(rec["kind"], {})[rec["file"]] = rec["time"]
            else:
                seconds = rec["write_seconds"]
    ordered = {k: sorted(([t, f] for f, t in v.items()), key=lambda e: (e[0], e[1])) for k, v in frames.items()}
    return ordered, seconds


def _xyz(points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(n, 2|3) -> three contiguous float64 coordinate arrays (z = 0 for 2D)."""
    p = np.asarray(points, np.float64).reshape(len(points), -1)
    z = p[:, 2] if p.shape[1] > 2 else np.zeros(len(p))
    return tuple(np.ascontiguousarray(c) for c in (p[:, 0], p[:, 1], z))


def _vector(values, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(n, 2|3) -> a VTK 3-vector (three contiguous arrays)."""
    v = np.asarray(values, np.float64).reshape(n, -1)
    z = v[:, 2] if v.shape[1] > 2 else np.zeros(n)
    return tuple(np.ascontiguousarray(c) for c in (v[:, 0], v[:, 1], z))


def _scalar(values, dtype=np.float64) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(values), dtype=dtype)


class VtkSeries:
    """The VTK files of one run, in ``folder`` (created on the first frame).

    seconds:  wall time spent writing [s] (before an interruption too: kept in the index,
              up to the last file written)
    """

    def __init__(self, folder: str | Path):
        self.folder = Path(folder)
        #: kind -> [[time, file name], ...] in time order
        self.frames, self.seconds = _read_index(self.folder)
        self._unsaved: set[str] = set(self.frames)      # a resumed run rebuilds every collection
        self._pending = 0

    # ------------------------------------------------------------------ one frame
    def write_frame(self, frame) -> None:
        """Particles, contacts, wall panels and (2D) block outlines of an engine Frame."""
        t0 = _time.perf_counter()
        step, t = int(frame.step), float(frame.time)
        if len(frame.positions):
            self._particles(frame, step, t)
        self._contacts(frame, step, t)
        self._walls(frame, step, t)
        if getattr(frame, "block_outlines", None) is not None:
            self._polygons("polygons", step, t, frame.block_outlines, {})
        self.seconds += _time.perf_counter() - t0

    def write_blocks(self, step: int, time: float, outlines: list, displacement: np.ndarray, *,
                     forces: dict[str, np.ndarray] | None = None) -> None:
        """Rigid blocks as polygons with their displacement [m] and per-block forces
        (name -> (k, 2) [N/m])."""
        t0 = _time.perf_counter()
        data = {"displacement": _scalar(displacement)}
        for name, f in (forces or {}).items():
            data[name] = _vector(f, len(outlines))
        self._polygons("blocks", int(step), float(time), outlines, data)
        self.seconds += _time.perf_counter() - t0

    def write_polygons(self, kind: str, step: int, time: float, outlines: list) -> None:
        """Polygons (each (k, 2|3) [m]) of rigid bodies under ``kind`` (e.g. the blocks of a
        tilt test, the grains of an interface box)."""
        t0 = _time.perf_counter()
        self._polygons(kind, int(step), float(time), list(outlines), {})
        self.seconds += _time.perf_counter() - t0

    def write_grains(self, step: int, time: float, outlines: np.ndarray, held: np.ndarray) -> None:
        """Polygonal grains (n, k, 2) as polygons, ``held`` (n,) bool."""
        t0 = _time.perf_counter()
        self._polygons("grains", int(step), float(time), list(outlines), {"held": _scalar(held, np.uint8)})
        self.seconds += _time.perf_counter() - t0

    def write_segments(self, step: int, time: float, segments: np.ndarray, normal_force: np.ndarray) -> None:
        """Contacts given as (m, 2, d) segments with a force each [N; N/m]."""
        t0 = _time.perf_counter()
        seg = np.asarray(segments, float)
        self._lines("contacts", int(step), float(time), seg[:, 0], seg[:, 1], {"normal_force": _scalar(normal_force)})
        self.seconds += _time.perf_counter() - t0

    def write_points(self, kind: str, step: int, time: float, positions: np.ndarray,
                     data: dict[str, np.ndarray]) -> None:
        """A point set with scalars per point (``kind``: joints, points, ...)."""
        t0 = _time.perf_counter()
        self._vertices(kind, int(step), float(time), positions, {k: _scalar(v) for k, v in data.items()})
        self.seconds += _time.perf_counter() - t0

    # ------------------------------------------------------------------ kinds
    def _particles(self, frame, step: int, t: float) -> None:
        n = len(frame.positions)
        data = {"radius": _scalar(frame.radii), "velocity": _vector(frame.velocities, n)}
        if getattr(frame, "particle_force", None) is not None:
            data["force"] = _vector(frame.particle_force, n)
        data["body_id"] = _scalar(frame.body_id, np.int64)
        if getattr(frame, "material", None) is not None:
            data["material"] = _scalar(frame.material, np.int32)
        self._vertices("particles", step, t, frame.positions, data)

    def _contacts(self, frame, step: int, t: float) -> None:
        """Touching pairs, then the intact bonds (``bonded`` 1) when the run has any."""
        a, b, fn = frame.contact_a, frame.contact_b, np.asarray(frame.contact_force, float)
        shear = getattr(frame, "contact_shear", None)
        data = {"normal_force": fn}
        if getattr(frame, "bond_a", None) is not None:
            k = len(frame.bond_a)
            a, b = np.concatenate([a, frame.bond_a]), np.concatenate([b, frame.bond_b])
            data["normal_force"] = np.concatenate([fn, frame.bond_force])
            if shear is not None:
                shear = np.concatenate([shear, frame.bond_shear])
            data["bonded"] = np.concatenate([np.zeros(len(fn), np.uint8), np.ones(k, np.uint8)])
        if shear is not None:
            data["shear_force"] = shear
        self._lines("contacts", step, t, a, b, {key: _scalar(v, v.dtype) for key, v in data.items()})

    def _walls(self, frame, step: int, t: float) -> None:
        corners = np.asarray(frame.panel_corners, float)
        p = len(corners)
        if p == 0:
            return
        data = {"panel": np.arange(p, dtype=np.int32), "force": _vector(frame.panel_force, p),
                "normal": _vector(frame.panel_normal, p), "area": _scalar(frame.panel_area),
                "normal_stress": _scalar(panel_normal_stress(frame))}
        if corners.shape[1] == 2:                       # 2D: a panel is a segment
            self._lines("walls", step, t, corners[:, 0], corners[:, 1], data)
        else:
            self._polygons("walls", step, t, list(corners), data)

    # ------------------------------------------------------------------ cells
    def _vertices(self, kind, step, t, positions, data) -> None:
        n = len(positions)
        x, y, z = _xyz(np.asarray(positions).reshape(n, -1)) if n else (np.zeros(0),) * 3
        self._write(kind, step, t, x, y, z, np.arange(n, dtype=np.int64), np.arange(1, n + 1, dtype=np.int64),
                    np.full(n, VtkVertex.tid, np.uint8), point_data=data)

    def _lines(self, kind, step, t, a, b, data) -> None:
        m = len(a)
        ends = np.empty((2 * m, np.asarray(a).shape[1] if m else 3))
        if m:
            ends[0::2], ends[1::2] = a, b
        x, y, z = _xyz(ends) if m else (np.zeros(0),) * 3
        self._write(kind, step, t, x, y, z, np.arange(2 * m, dtype=np.int64),
                    np.arange(2, 2 * m + 1, 2, dtype=np.int64), np.full(m, VtkLine.tid, np.uint8), cell_data=data)

    def _polygons(self, kind, step, t, outlines, data) -> None:
        sizes = np.array([len(o) for o in outlines], dtype=np.int64)
        pts = np.concatenate([np.asarray(o, float) for o in outlines]) if len(outlines) else np.zeros((0, 3))
        x, y, z = _xyz(pts) if len(pts) else (np.zeros(0),) * 3
        self._write(kind, step, t, x, y, z, np.arange(len(pts), dtype=np.int64), np.cumsum(sizes),
                    np.full(len(outlines), VtkPolygon.tid, np.uint8), cell_data=data)

    def _write(self, kind, step, t, x, y, z, connectivity, offsets, types, *, point_data=None,
               cell_data=None) -> None:
        """One file, written whole, and the kind's collection rebuilt with it."""
        self.folder.mkdir(parents=True, exist_ok=True)
        name = f"{kind}_{step:010d}"
        tmp = self.folder / f".{name}.tmp"
        unstructuredGridToVTK(str(tmp), x, y, z, connectivity=connectivity, offsets=offsets, cell_types=types,
                              cellData=cell_data or None, pointData=point_data or None)
        os.replace(f"{tmp}.vtu", self.folder / f"{name}.vtu")
        with open(self.folder / INDEX, "a") as index:
            index.write(json.dumps({"kind": kind, "time": t, "file": f"{name}.vtu"}) + "\n")
        entries = self.frames.setdefault(kind, [])
        if entries and entries[-1][0] < t:
            entries.append([t, f"{name}.vtu"])                # the usual case: time goes on
        else:
            entries[:] = sorted([e for e in entries if e[1] != f"{name}.vtu"] + [[t, f"{name}.vtu"]],
                                key=lambda e: (e[0], e[1]))
        self._unsaved.add(kind)
        self._pending += 1
        if self._pending >= FLUSH_EVERY:
            self.flush()

    def flush(self) -> None:
        """Rebuild the collections of the kinds with new files (``<kind>.pvd``: every
        frame of the kind with its time) and note the writing time in the index."""
        for kind in sorted(self._unsaved):
            tmp = self.folder / f".{kind}.tmp"
            group = VtkGroup(str(tmp))
            for t, name in self.frames[kind]:
                group.addFile(str(self.folder / name), sim_time=repr(float(t)))
            group.save()
            os.replace(f"{tmp}.pvd", self.folder / f"{kind}.pvd")
        if self._unsaved:
            with open(self.folder / INDEX, "a") as index:
                index.write(json.dumps({"write_seconds": self.seconds}) + "\n")
        self._unsaved.clear()
        self._pending = 0

    def close(self) -> None:
        """The collections and the index, up to the last file written."""
        self.flush()


def summary(folder: str | Path) -> dict | None:
    """What a run's vtk/ folder holds and what it cost (None when there is none): the
    collections, the frames of each kind and their size [MB] (also per frame), and the
    wall time spent writing them all [s]. A run of several tests (one subfolder each):
    ``parts``, the same for each, with the totals."""
    folder = Path(folder)
    if not (folder / INDEX).is_file():
        parts = {p.name: summary(p) for p in sorted(folder.iterdir()) if (p / INDEX).is_file()} \
            if folder.is_dir() else {}
        if not parts:
            return None
        return {"folder": str(folder), "parts": parts, "MB": sum(p["MB"] for p in parts.values()),
                "write_seconds": sum(p["write_seconds"] for p in parts.values())}
    frames, seconds = _read_index(folder)
    size = {k: sum((folder / name).stat().st_size for _, name in v) / 1e6 for k, v in frames.items()}
    return {"folder": str(folder), "collections": sorted(f"{k}.pvd" for k in frames),
            "frames": {k: len(v) for k, v in frames.items()}, "MB": sum(size.values()),
            "MB_per_frame": {k: size[k] / max(len(frames[k]), 1) for k in frames},
            "write_seconds": seconds}
