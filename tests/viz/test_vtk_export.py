"""``--vtk``: every DEM engine's run read back from its VTK files with an independent
reader (meshio; the files are written by pyevtk) at reduced size.

What each test holds the files to:
* counts: as many points, lines and polygons as the run had particles, contacts and
  panels or blocks, one file per recorded frame, and a .pvd per kind listing each
  frame's simulation time;
* forces: the wall panels' normal forces sum to the run's own wall thrust (the
  Khosravi result's active thrust; the Nadukuru study's ``wall_load`` of the same
  frame); Newton's third law (the contact forces on all spheres and on all panels
  cancel) for dem3d; for a dry-stone wall, the blocks' water loads sum to the
  hydrostatic thrust gamma_w (h_w - h_1)^2 / 2 on the face above the fixed first course
  (S-OET: first course fixed; ../shared/reference/drystone-walls.md 2.1).
"""

import csv
import json
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest

from studies import get
from studies.runner import saved_options
from viz.vtk import VtkSeries

GAMMA_WATER = 9810.0       # N/m^3, the unit weight the dry-stone study applies (dem2d.blocks)


def _spy_frames(monkeypatch) -> list:
    """Keep every Frame the recorder hands to the VTK writer."""
    kept = []
    original = VtkSeries.write_frame

    def write_frame(self, frame):
        kept.append(frame)
        return original(self, frame)

    monkeypatch.setattr(VtkSeries, "write_frame", write_frame)
    return kept


def _collection(vtk: Path, kind: str) -> list[tuple[float, Path]]:
    """(time, file) of every frame the kind's .pvd lists."""
    root = ET.parse(vtk / f"{kind}.pvd").getroot()
    return [(float(d.get("timestep")), vtk / d.get("file")) for d in root.iter("DataSet")]


def _cells(mesh, kind: str) -> int:
    return sum(len(c.data) for c in mesh.cells if c.type == kind)


def _cell_array(mesh, name: str) -> np.ndarray:
    return np.concatenate(mesh.cell_data[name])


def _run_folder(result: dict) -> Path:
    return Path(result["vtk"]["folder"]).parent


def test_dem3d_nadukuru_run_reads_back(tmp_path, monkeypatch):
    frames = _spy_frames(monkeypatch)
    s = get("nadukuru")
    case = s.case(particles=1500, seed=3)
    result = s.run(case, out=str(tmp_path), vtk=True, no_rrd=True)
    folder = _run_folder(result)
    vtk = folder / "vtk"
    assert not list(folder.glob("*.rrd")), "--no-rrd: VTK only"
    assert saved_options(folder)["vtk"] is True          # a resume records as the run started
    particles, contacts, walls = (_collection(vtk, k) for k in ("particles", "contacts", "walls"))
    assert len(particles) == len(contacts) == len(walls) == len(frames) == result["vtk"]["frames"]["particles"] >= 2
    assert [t for t, _ in particles] == [f.time for f in frames] == sorted(t for t, _ in particles)

    from studies.nadukuru.model import wall_load
    wall_ids = np.arange(case.wall.segments)          # the wall's panels come first (dem3d walls)
    for frame, (_, p), (_, c), (_, w) in zip(frames, particles, contacts, walls):
        pm, cm, wm = meshio.read(p), meshio.read(c), meshio.read(w)
        assert _cells(pm, "vertex") == len(pm.points) == result["particles"] == len(frame.positions)
        assert _cells(cm, "line") == len(frame.contact_force) > 0
        assert _cells(wm, "polygon") == len(frame.panel_area)
        force, normal = _cell_array(wm, "force"), _cell_array(wm, "normal")
        thrust = -np.einsum("pd,pd->p", force, normal)[wall_ids].sum()
        assert thrust == pytest.approx(wall_load(frame, wall_ids, case.wall.height).normal, rel=1e-12)
        # action and reaction: the grains push the panels as hard as the panels push them
        on_spheres, on_panels = pm.point_data["force"].sum(axis=0), force.sum(axis=0)
        assert np.abs(on_spheres + on_panels).max() < 1e-9 * np.abs(on_panels).max()
        assert np.array_equal(_cell_array(cm, "normal_force").ravel(), frame.contact_force)


def test_dem2d_khosravi_run_reads_back(tmp_path, monkeypatch):
    from studies.khosravi.case import KhosraviCase

    frames = _spy_frames(monkeypatch)
    case = KhosraviCase(H=0.1, particles_scale=5, wall_disp_over_H_max=0.001)
    result = get("khosravi").run(case, out=str(tmp_path), vtk=True, no_cache=True)
    folder = _run_folder(result)
    walls = _collection(folder / "vtk", "walls")
    particles = _collection(folder / "vtk", "particles")
    assert len(walls) == len(particles) == len(frames) == 4          # at rest and 3 readings
    pm = meshio.read(particles[-1][1])
    assert len(pm.points) == _cells(pm, "vertex") == result["particles"]
    assert np.all(pm.points[:, 2] == 0.0)                             # 2D as z = 0
    cm = meshio.read(_collection(folder / "vtk", "contacts")[-1][1])
    assert _cells(cm, "line") == len(frames[-1].contact_force) > 0
    wm = meshio.read(walls[-1][1])
    assert _cells(wm, "line") == len(frames[-1].panel_area)           # 2D panels are segments
    # the last reading is the active one here (Dis/H 0.001 < 0.003): its thrust is the
    # normal force on the 40 cells whose centres are below the surface
    depth = np.array([float(r["depth_m"]) for r in csv.DictReader(open(folder / "active_panels.csv"))])
    normal = -np.einsum("pd,pd->p", _cell_array(wm, "force"), _cell_array(wm, "normal"))
    assert normal[:40][depth > 0].sum() == pytest.approx(result["dem"]["active_thrust_N_per_m"], rel=1e-12)


def test_drystone_wall_reads_back(tmp_path):
    s = get("drystone")
    case = s.case(height_m=1.0, base_width_m=0.4, increment_fraction=0.02)
    result = s.run(case, out=str(tmp_path), vtk=True, no_rrd=True)
    folder = _run_folder(result)
    blocks = _collection(folder / "vtk", "blocks")
    joints = _collection(folder / "vtk", "joints")
    history = list(csv.DictReader(open(folder / "history.csv")))
    assert len(blocks) == len(joints) == len(history)                 # a frame per water increment
    assert [t for t, _ in blocks] == pytest.approx([float(r["time_s"]) for r in history], rel=1e-8)  # CSV: 9 digits
    first_course = case.block_height_m if case.block_height_m else 0.125     # S-OET's 0.30 x 0.125 m blocks
    slop = 1e-4                                                         # dem2d.blocks.BlockSolver: overlap allowed
    checked = 0
    for (_, path), row in zip(blocks, history):
        m = meshio.read(path)
        assert _cells(m, "polygon") == result["particles"]
        wet = float(row["water_height_m"]) - first_course
        if row["settled"] != "1" or wet <= 0:
            continue
        water = _cell_array(m, "water_force").sum(axis=0)
        hydrostatic = 0.5 * GAMMA_WATER * wet ** 2
        # a settled course may sink into the one below by up to the slop: (wet + slop)^2
        assert -water[0] == pytest.approx(hydrostatic, rel=2 * slop / wet + (slop / wet) ** 2)
        checked += 1
    assert checked >= 10


def test_a_resumed_series_keeps_the_frames_before_the_interruption(tmp_path):
    """The collection is rebuilt from frames.json: a second writer on the same folder (a
    resumed run) adds its frames to the first one's, and a frame written again (the
    same step) replaces the old one."""
    from analytic.frame import Frame

    def frame(step):
        x = np.array([[0.0, 0.0], [1.0, 0.0]])
        return Frame(step, 0.5 * step, x, np.array([0.5, 0.5]), np.zeros((2, 2)), np.arange(2),
                     x[:1], x[1:], np.array([3.0]), np.zeros((0, 2, 2)), np.zeros((0, 2)), np.zeros((0, 2)),
                     np.zeros(0))

    first = VtkSeries(tmp_path)
    first.write_frame(frame(1))
    first.write_frame(frame(2))
    again = VtkSeries(tmp_path)
    again.write_frame(frame(2))
    again.write_frame(frame(3))
    assert [t for t, _ in _collection(tmp_path, "particles")] == [0.5, 1.0, 1.5]
    assert json.loads((tmp_path / "frames.json").read_text())["frames"]["contacts"][-1][1] == "contacts_0000000003.vtu"
    assert not list(tmp_path.glob(".*"))                                # no temporary file left
