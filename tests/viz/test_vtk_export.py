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
  (S-OET: first course fixed; docs/reference/drystone-walls.md 2.1).
"""

import csv
import json
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest

import studies
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
    case = s.case(particles=1000, seed=3)
    result = s.run(case, out=str(tmp_path), vtk=True, no_rrd=True)
    folder = _run_folder(result)
    vtk = folder / "vtk"
    assert not list(folder.glob("*.rrd")), "--no-rrd: VTK only"
    assert saved_options(folder)["vtk"] is True          # a resume records as the run started
    particles, contacts, walls = (_collection(vtk, k) for k in ("particles", "contacts", "walls"))
    assert len(particles) == len(contacts) == len(walls) == len(frames) == result["vtk"]["frames"]["particles"] >= 2
    assert [t for t, _ in particles] == [f.time for f in frames] == sorted(t for t, _ in particles)

    from studies.granular.load import wall_load
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


def test_dem3d_bonds_are_lines_of_their_own(tmp_path, seismic_static_cache):
    """The seismic sheet pile's bonded balls: every intact bond is a line with bonded = 1
    after the touching pairs (bonded = 0), carrying the bond's own forces."""
    from studies.seismic.case import SeismicCase
    from studies.seismic.compare import compare_seismic
    from studies.runner import command_envelope
    from tests.studies.test_seismic import TINY

    seismic_static_cache(SeismicCase(**TINY), tmp_path)
    frames = []
    original = VtkSeries.write_frame

    def keep(self, frame):
        frames.append(frame)
        return original(self, frame)

    with pytest.MonkeyPatch.context() as m, command_envelope(vtk=True):
        m.setattr(VtkSeries, "write_frame", keep)
        result, folder = compare_seismic(SeismicCase(**TINY), root=tmp_path, record=False, strain_times=())
    contacts = _collection(Path(folder) / "vtk", "contacts")
    assert len(contacts) == len(frames) >= 2
    frame, mesh = frames[-1], meshio.read(contacts[-1][1])
    touching, bonds = len(frame.contact_force), len(frame.bond_force)
    assert bonds > 0 and _cells(mesh, "line") == touching + bonds
    bonded = _cell_array(mesh, "bonded").ravel()
    assert not bonded[:touching].any() and bonded[touching:].all()
    assert np.array_equal(_cell_array(mesh, "normal_force").ravel()[touching:], frame.bond_force)
    assert len(_collection(Path(folder) / "vtk", "sheet_pile")) > len(contacts)   # the pile: every sample


def test_dem2d_khosravi_run_reads_back(tmp_path, monkeypatch):
    from studies.khosravi.case import KhosraviCase

    frames = _spy_frames(monkeypatch)
    case = KhosraviCase(H=0.1, particles_scale=8, wall_disp_over_H_max=0.001)
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
    """The collections are rebuilt from the index (frames.jsonl, one line per file): a
    writer interrupted before it closed (its .pvd not yet written) and a second writer on
    the same folder (the resumed run) end with every frame, a frame written again (the
    same step) replacing the old one."""
    from analytic.frame import Frame
    from viz.vtk import summary

    def frame(step):
        x = np.array([[0.0, 0.0], [1.0, 0.0]])
        return Frame(step, 0.5 * step, x, np.array([0.5, 0.5]), np.zeros((2, 2)), np.arange(2),
                     x[:1], x[1:], np.array([3.0]), np.zeros((0, 2, 2)), np.zeros((0, 2)), np.zeros((0, 2)),
                     np.zeros(0))

    first = VtkSeries(tmp_path)
    first.write_frame(frame(1))
    first.write_frame(frame(2))                                         # interrupted: never closed
    again = VtkSeries(tmp_path)
    again.write_frame(frame(2))
    again.write_frame(frame(3))
    again.close()
    assert [t for t, _ in _collection(tmp_path, "particles")] == [0.5, 1.0, 1.5]
    assert [name for _, name in _collection(tmp_path, "contacts")][-1].name == "contacts_0000000003.vtu"
    assert summary(tmp_path)["frames"] == {"particles": 3, "contacts": 3}
    assert not list(tmp_path.glob(".*"))                                # no temporary file left


def test_calibrations_write_each_test_as_its_own_series(tmp_path):
    """calibrate triaxial (dem3d) and biaxial (dem2d) with --vtk: the specimen when
    compacted and at every tenth of the shear strain (11 frames a test), each biaxial
    test in a folder of its own (each test has its own clock); all grains in every
    frame, and (dem3d) the platens' forces balanced by the grains' (Newton's third law)."""
    import cli

    out = tmp_path / "runs"
    assert cli.main(["calibrate", "triaxial", "--particles", "300", "--vtk", "--out", str(out), "--quiet"]) == 0
    run = next((out / "triaxial").iterdir())
    card = json.loads((run / "result.json").read_text())
    particles, walls = _collection(run / "vtk", "particles"), _collection(run / "vtk", "walls")
    assert len(particles) == len(walls) == 11
    for (_, p), (_, w) in zip(particles, walls):
        pm, wm = meshio.read(p), meshio.read(w)
        assert len(pm.points) == card["particles"] and _cells(wm, "polygon") == 6
        platens = _cell_array(wm, "force")            # opposite platens: the net is ~1e-3 of each
        assert np.abs(pm.point_data["force"].sum(axis=0) + platens.sum(axis=0)).max() < 1e-9 * np.abs(platens).max()

    assert cli.main(["calibrate", "biaxial", "--friction", "0.3,0.5", "--particles-scale", "8", "--vtk",
                     "--out", str(out), "--quiet"]) == 0
    run = next((out / "biaxial").iterdir())
    result = json.loads((run / "result.json").read_text())
    assert sorted(result["vtk"]["parts"]) == ["mu0.3", "mu0.5"]
    for test in result["tests"]:
        particles = _collection(run / "vtk" / f"mu{test['friction']:g}", "particles")
        assert len(particles) == 11
        assert all(len(meshio.read(p).points) == test["n_grains"] for _, p in particles)


def test_the_block_and_gravel_calibrations_write_their_bodies(tmp_path):
    """calibrate tilt: each test's two blocks at every held angle of its fine search
    (polygons of 4 corners, the free block's corners moving with it); calibrate gravel
    (the reduced plan of tests/studies/test_gravel_study.py): the biaxial specimen's
    grains as polygons at 11 marks, and the interface box (grains, face, lid) after each
    of its 20 readings."""
    import cli

    out = tmp_path / "runs"
    assert cli.main(["calibrate", "tilt", "--friction", "30", "--vtk", "--out", str(out), "--quiet"]) == 0
    run = next((out / "tilt").iterdir())
    parts = json.loads((run / "result.json").read_text())["vtk"]["parts"]
    assert set(parts) == {"slide-30deg", "topple-0.1m", "topple-0.125m"}
    frames = _collection(run / "vtk" / "topple-0.1m", "blocks")
    first, last = meshio.read(frames[0][1]), meshio.read(frames[-1][1])
    assert _cells(first, "polygon") == _cells(last, "polygon") == 2 and len(first.points) == 8
    assert not np.allclose(first.points[4:], last.points[4:])          # the slender block tipped

    cmd = studies.get("gravel").commands[0]
    plan = cmd.resolve(sets=["frictions_deg=45", "seeds=1", "interface_frictions_deg=25",
                             "grain_friction_deg=45", "biaxial.width=0.35", "biaxial.height=0.7",
                             "biaxial.max_strain=0.06", "shear.length_m=0.3", "shear.height_m=0.15",
                             "shear.displacement_m=0.006", "gravel.width_min_m=0.015", "gravel.width_max_m=0.024"])
    result = studies.get("gravel").run(plan, out=str(out), vtk=True)
    vtk = Path(result["vtk"]["folder"])
    biaxial = _collection(vtk / "biaxial-45deg-seed1", "polygons")
    assert len(biaxial) == 11
    assert _cells(meshio.read(biaxial[-1][1]), "polygon") == result["biaxial"]["tests"][0]["n_grains"]
    box = _collection(vtk / "interface-25deg-seed1", "grains")
    assert len(box) == 20
    assert _cells(meshio.read(box[-1][1]), "polygon") == result["interface"]["tests"][0]["n_grains"] + 2
