"""Rerun recordings of wallsim runs. The only module family that imports ``rerun``.

Engines yield frames (plain numpy arrays, duck-typed; dem2d and dem3d use the same
field names): ``step, time, positions (n,d), radii (n,), velocities (n,d)``, optional
``body_id (n,)``, ``contact_a/contact_b (m,d)`` and ``contact_force (m,)`` (normal force
of each particle-particle contact, N), ``panel_corners`` ((p,4,3) in 3D, (p,2,2) in 2D),
``panel_normal (p,d)`` (unit, from the wall into the backfill), ``panel_force (p,d)``
(force by the particles on the panel, N; per metre of wall in 2D) and
``panel_area (p,)`` (m^2 in 3D, m per metre in 2D), optional ``block_outlines``
(list of (k,2) polygons).

Always an explicit ``RecordingStream`` written to a file (plus a viewer with
``spawn=True``); never the global stream, never a stream without a sink (it would
buffer everything in RAM).
"""

from __future__ import annotations

import functools
import os
import shutil
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from analytic.frame import panel_normal_stress  # noqa: F401 - re-exported, the one definition

from . import paths as P

_RGB_WALL_LOW = np.array([60, 90, 200], dtype=float)
_RGB_WALL_HIGH = np.array([230, 40, 40], dtype=float)


def _viridis(values: np.ndarray, vmax: float) -> np.ndarray:
    """uint8 RGB colours for values in [0, vmax] (a 5-stop viridis approximation)."""
    stops = np.array([[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]], float)
    t = np.clip(values / vmax, 0.0, 1.0) if vmax > 0 else np.zeros_like(values)
    x = t * (len(stops) - 1)
    i = np.minimum(x.astype(int), len(stops) - 2)
    f = (x - i)[:, None]
    return (stops[i] * (1 - f) + stops[i + 1] * f).astype(np.uint8)


def _diverging(values: np.ndarray, vmax: float) -> np.ndarray:
    """uint8 RGB colours for values in [-vmax, vmax]: blue, white at 0, red."""
    t = np.clip(values / vmax, -1.0, 1.0)[:, None] if vmax > 0 else np.zeros((len(values), 1))
    white = np.array([245, 245, 245], float)
    neg = white * (1 + np.minimum(t, 0)) + _RGB_WALL_LOW * -np.minimum(t, 0)
    pos = white * (1 - np.maximum(t, 0)) + _RGB_WALL_HIGH * np.maximum(t, 0)
    return np.where(t < 0, neg, pos).astype(np.uint8)



@dataclass(frozen=True)
class Series:
    """A time-series panel of a recording's layout: its ``title``, the entity ``origin``
    and, when given, the entities under it that it shows (``$origin/...``)."""

    title: str
    origin: str
    contents: tuple[str, ...] = ()


@dataclass(frozen=True)
class Layout:
    """How a recording opens in the viewer: the scene (2D or 3D, titled) on the left; on
    the right, with ``profile``, the wall-pressure profile (DEM against every theory),
    then the ``series`` panels, and the case text last."""

    dim: int
    scene: str
    series: tuple[Series, ...] = ()
    profile: bool = False


def wall_layout(dim: int, scene: str = "particles and force chains", extra_series: tuple[str, ...] = ()) -> Layout:
    """A wall-load run: the profile, K and the resultant height, and any ``extra_series``
    (entity paths, titled by their last part)."""
    series = (Series("K", P.METRIC_K), Series("resultant height / H", P.METRIC_RESULTANT_HEIGHT))
    return Layout(dim, scene, series + tuple(Series(e.rsplit("/", 1)[-1], e) for e in extra_series), profile=True)


def blueprint(layout: Layout) -> rrb.Blueprint:
    """The Rerun blueprint of ``layout``."""
    scene = (rrb.Spatial3DView(origin=P.WORLD, name=layout.scene) if layout.dim == 3
             else rrb.Spatial2DView(origin=P.WORLD, name=layout.scene))
    right = [rrb.Spatial2DView(origin=P.PROFILE, name="sigma_h/(gamma H) (x) against -depth/H (y)")] \
        if layout.profile else []
    for s in layout.series:
        right.append(rrb.TimeSeriesView(origin=s.origin, contents=list(s.contents), name=s.title) if s.contents
                     else rrb.TimeSeriesView(origin=s.origin, name=s.title))
    right.append(rrb.TextDocumentView(origin=P.CASE, name="case"))
    return rrb.Blueprint(rrb.Horizontal(scene, rrb.Vertical(*right), column_shares=[3, 2]),
                         collapse_panels=True)


def _timed(method):
    """Add the method's wall time to ``self.seconds`` (the cost of the Rerun recording,
    reported per run; the VTK files count their own, ``vtk.seconds``)."""
    @functools.wraps(method)
    def wrapper(self, *args, **kwargs):
        t0 = time.perf_counter()
        v0 = self.vtk.seconds if self.vtk is not None else 0.0
        try:
            return method(self, *args, **kwargs)
        finally:
            v1 = self.vtk.seconds if self.vtk is not None else 0.0
            self.seconds += time.perf_counter() - t0 - (v1 - v0)
    return wrapper


class Recorder:
    """One recording per run.

    path:        .rrd file to write (None with spawn=True: viewer only)
    dim:         2 or 3 (the scene's dimension)
    every:       log the scene every N-th ``log_frame`` call (metrics are kept for all)
    spawn:       also open the native viewer (never in CI)
    enabled:     False: no Rerun recording (``--no-rrd``); ``self.enabled`` is then True
                 only when ``vtk`` is given
    layout:      how the recording opens in the viewer (default: ``wall_layout(dim)``)
    flush_every: flush the sink every N scene frames so memory stays flat
    vtk:         also write every scene frame as VTK files (``viz.vtk.VtkSeries``, ``--vtk``)
    """

    def __init__(self, path: str | Path | None, *, app_id: str = "wallsim", recording_id: str | None = None,
                 dim: int = 3, every: int = 1, spawn: bool = False, enabled: bool = True,
                 layout: Layout | None = None, flush_every: int = 20,
                 chain_radius_scale: float | None = None, vtk=None):
        self.vtk = vtk
        rerun_on = enabled and (path is not None or spawn)
        self.enabled = rerun_on or vtk is not None
        self.dim = dim
        self.every = max(int(every), 1)
        self.flush_every = flush_every
        self.chain_radius_scale = chain_radius_scale
        self.seconds = 0.0            # wall time spent in logging calls
        self._calls = 0
        self._logged = 0
        self._n_radii = -1
        self._x0: np.ndarray | None = None
        self._series: dict[str, list] = {}
        self._series_time: dict[str, list] = {}
        self.path = Path(path) if path is not None else None
        if not rerun_on:
            self.rec = None
            return
        self.rec = rr.RecordingStream(app_id, recording_id=recording_id)
        self.rec.set_log_time_enabled(False)  # smaller files, comparable between runs
        bp = blueprint(layout or wall_layout(dim))
        spawn = spawn and _spawn_viewer(self.rec, self.path)
        sinks = []
        if self.path is not None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            sinks.append(rr.FileSink(str(self.path)))
        if spawn:
            sinks.append(rr.GrpcSink())
        self.rec.set_sinks(*sinks, default_blueprint=bp)

    # ------------------------------------------------------------------ static content
    @_timed
    def log_case(self, text: str) -> None:
        """Case description and resolved config, as markdown."""
        if self.rec is None:
            return
        self.rec.log(P.CASE, rr.TextDocument(text, media_type=rr.MediaType.MARKDOWN), static=True)

    @_timed
    def log_theory_profiles(self, profiles, gamma: float, H: float) -> None:
        """Each theory's sigma_h(z) as a static line: x = sigma_h/(gamma H), y = -z/H."""
        if self.rec is None:
            return
        for prof in profiles:
            pts = np.column_stack([prof.sigma_h / (gamma * H), -prof.z / H]).astype(np.float32)
            self.rec.log(f"{P.PROFILE_THEORY}/{prof.method}", rr.LineStrips2D([pts], labels=[prof.method]),
                         static=True)

    # ------------------------------------------------------------------ per frame
    def _set_time(self, step: int, time: float, wall_disp_over_H: float | None) -> None:
        self.rec.set_time(P.TIMELINE_STEP, sequence=int(step))
        self.rec.set_time(P.TIMELINE_TIME, duration=float(time))
        if wall_disp_over_H is not None:
            self.rec.set_time(P.TIMELINE_DISP, sequence=int(round(wall_disp_over_H * P.DISP_TIMELINE_SCALE)))

    @_timed
    def log_frame(self, frame, *, wall_disp_over_H: float | None = None, colour_by: str = "displacement",
                  profile: tuple[np.ndarray, np.ndarray] | None = None,
                  metrics: dict[str, float] | None = None) -> bool:
        """Log one engine frame. ``profile`` = (z/H at panel centres, sigma_h/(gamma H));
        ``metrics`` = scalars (e.g. K, thrust_kN, resultant_height_over_H) kept as time series.
        Returns True when the scene was logged (every N-th call)."""
        if not self.enabled:
            return False
        self._calls += 1
        if self.rec is not None:
            self._remember(frame.step, frame.time, wall_disp_over_H, metrics)
        if (self._calls - 1) % self.every:
            return False
        if self.vtk is not None:
            self.vtk.write_frame(frame)
        if self.rec is None:
            return True
        self._set_time(frame.step, frame.time, wall_disp_over_H)
        self._log_particles(frame, colour_by)
        self._log_walls(frame)
        self._log_chains(frame)
        if getattr(frame, "block_outlines", None) is not None:
            self.rec.log(P.BLOCKS, rr.LineStrips2D([np.vstack([b, b[:1]]) for b in frame.block_outlines]))
        if profile is not None:
            zh, s = profile
            pts = np.column_stack([s, -np.asarray(zh)]).astype(np.float32)
            self.rec.log(P.PROFILE_DEM, rr.LineStrips2D([pts], labels=["DEM"], colors=[[0, 0, 0]]))
        self._logged += 1
        if self._logged % self.flush_every == 0:
            self.rec.flush()
        return True

    def _log_particles(self, frame, colour_by: str) -> None:
        pos = np.asarray(frame.positions)
        n = len(pos)
        Points = rr.Points3D if self.dim == 3 else rr.Points2D
        if n != self._n_radii:
            # radii are temporal (never static) so a changing particle count stays visible
            self.rec.log(P.PARTICLES, Points.from_fields(radii=np.asarray(frame.radii, np.float32)))
            self._n_radii = n
            self._x0 = pos.copy()
        if colour_by == "velocity":
            v = np.linalg.norm(frame.velocities, axis=1)
            colours = _viridis(v, float(np.percentile(v, 99)) if n else 1.0)
        elif colour_by == "displacement" and self._x0 is not None:
            u = np.linalg.norm(pos - self._x0, axis=1)
            colours = _viridis(u, float(np.percentile(u, 99)) if n else 1.0)
        else:
            colours = None
        self.rec.log(P.PARTICLES, Points.from_fields(positions=pos.astype(np.float32), colors=colours))

    def _log_walls(self, frame) -> None:
        corners = getattr(frame, "panel_corners", None)
        if corners is None or len(corners) == 0:
            return
        sigma = panel_normal_stress(frame)
        smax = float(np.max(np.abs(sigma))) if len(sigma) else 0.0
        t = np.clip(sigma / smax, 0, 1)[:, None] if smax > 0 else np.zeros((len(sigma), 1))
        colours = (_RGB_WALL_LOW * (1 - t) + _RGB_WALL_HIGH * t).astype(np.uint8)
        if self.dim == 3:
            strips = [np.vstack([c, c[:1]]).astype(np.float32) for c in corners]
            self.rec.log(P.WALL, rr.LineStrips3D(strips, colors=colours, radii=[0.01]))
        else:
            self.rec.log(P.WALL, rr.LineStrips2D([c.astype(np.float32) for c in corners], colors=colours,
                                                 radii=[0.002 * _scene_size(frame)]))

    def _log_chains(self, frame) -> None:
        f = getattr(frame, "contact_force", None)
        if f is None or len(f) == 0:
            return
        strong = f > f.mean()
        if not strong.any():
            return
        a, b, fs = frame.contact_a[strong], frame.contact_b[strong], f[strong]
        scale = self.chain_radius_scale or 0.5 * float(np.mean(frame.radii))
        radii = (scale * fs / fs.max()).astype(np.float32)
        strips = np.stack([a, b], axis=1).astype(np.float32)
        Strips = rr.LineStrips3D if self.dim == 3 else rr.LineStrips2D
        self.rec.log(P.FORCE_CHAINS, Strips(strips, radii=radii, colors=[[200, 30, 30]]))

    @_timed
    def log_displacement(self, x0: np.ndarray, x1: np.ndarray, *, step: int, time: float,
                         max_arrows: int = 3000, wall_disp_over_H: float | None = None) -> None:
        """Displacement field x1 - x0 as arrows (evenly subsampled to ``max_arrows``)."""
        if self.rec is None:
            return
        k = max(len(x0) // max_arrows, 1)
        self._set_time(step, time, wall_disp_over_H)
        Arrows = rr.Arrows3D if self.dim == 3 else rr.Arrows2D
        self.rec.log(P.DISPLACEMENT, Arrows(origins=x0[::k].astype(np.float32),
                                            vectors=(x1 - x0)[::k].astype(np.float32)))

    def _log_blocks(self, step: int, time: float, outlines: list, displacement: np.ndarray, metrics) -> None:
        """The frame's time and series, and the block outlines (k,2) coloured by each
        block's displacement magnitude (m, viridis up to the largest)."""
        self._remember(step, time, None, metrics)
        self._set_time(step, time, None)
        d = np.asarray(displacement, float)
        colours = _viridis(d, float(d.max()) if len(d) and d.max() > 0 else 1.0)
        strips = [np.vstack([b, b[:1]]).astype(np.float32) for b in outlines]
        self.rec.log(P.BLOCKS, rr.LineStrips2D(strips, colors=colours, radii=[0.004]))

    @_timed
    def log_block_wall(self, step: int, time: float, outlines: list, displacement: np.ndarray, *,
                       water_height: float, water_x: tuple[float, float],
                       contact_points: np.ndarray | None = None, contact_forces: np.ndarray | None = None,
                       block_forces: dict[str, np.ndarray] | None = None,
                       metrics: dict[str, float] | None = None) -> None:
        """A wall of polygon blocks: outlines (k,2) coloured by each block's displacement
        magnitude (m, viridis up to the largest), the water surface as a line over
        ``water_x`` at ``water_height``, and joint contact points sized by normal force.
        ``block_forces`` (name -> (k,2) [N/m], e.g. the water load of each block) go to
        the VTK files only."""
        if self.vtk is not None:
            self.vtk.write_blocks(step, time, outlines, displacement, forces=block_forces)
            if contact_points is not None:
                self.vtk.write_points("joints", step, time, contact_points, {"normal_force": contact_forces})
        if self.rec is None:
            return
        self._log_blocks(step, time, outlines, displacement, metrics)
        self.rec.log(P.WATER, rr.LineStrips2D([np.array([[water_x[0], water_height], [water_x[1], water_height]],
                                                        np.float32)], colors=[[40, 110, 230]], radii=[0.01]))
        if contact_points is not None and len(contact_points):
            f = np.asarray(contact_forces, float)
            radii = (0.03 * f / f.max()).astype(np.float32) if f.max() > 0 else np.full(len(f), 0.002, np.float32)
            self.rec.log(P.JOINT_FORCES, rr.Points2D(np.asarray(contact_points, np.float32), radii=radii,
                                                     colors=[[200, 30, 30]]))
        self._logged += 1
        if self._logged % self.flush_every == 0:
            self.rec.flush()

    @_timed
    def log_backfilled_wall(self, step: int, time: float, outlines: list, displacement: np.ndarray, *,
                            grain_outlines: np.ndarray, grain_held: np.ndarray, chain_segments: np.ndarray,
                            chain_forces: np.ndarray, block_centres: np.ndarray | None = None,
                            block_velocities: np.ndarray | None = None,
                            metrics: dict[str, float] | None = None) -> None:
        """A block wall under a granular fill of polygonal grains: block outlines coloured
        by displacement (as ``log_block_wall``), grain outlines (n,k,2) (free grey, held
        darker), force chains of fill and wall together (contacts above the mean force,
        radius ~ force, as ``_log_chains``), and block velocity arrows [m/s, drawn x 0.5 s]
        when given (at failure)."""
        if self.vtk is not None:
            self.vtk.write_blocks(step, time, outlines, displacement)
            self.vtk.write_grains(step, time, grain_outlines, grain_held)
            self.vtk.write_segments(step, time, chain_segments, chain_forces)
        if self.rec is None:
            return
        self._log_blocks(step, time, outlines, displacement, metrics)
        g = np.asarray(grain_outlines, np.float32)
        if len(g):
            closed = np.concatenate([g, g[:, :1]], axis=1)
            held = np.asarray(grain_held, bool)
            gcol = np.where(held[:, None], np.array([[90, 90, 90]]), np.array([[170, 170, 170]])).astype(np.uint8)
            self.rec.log(P.GRAINS, rr.LineStrips2D(list(closed), colors=gcol, radii=[0.0008]))
        f = np.asarray(chain_forces, float)
        strong = f > f.mean() if len(f) else np.zeros(0, bool)
        if strong.any():
            fs = f[strong]
            self.rec.log(P.FORCE_CHAINS, rr.LineStrips2D(list(np.asarray(chain_segments, np.float32)[strong]),
                                                         radii=(0.006 * fs / fs.max()).astype(np.float32),
                                                         colors=[[200, 30, 30]]))
        if block_velocities is not None:
            self.rec.log(P.BLOCK_VELOCITY, rr.Arrows2D(origins=np.asarray(block_centres, np.float32),
                                                       vectors=0.5 * np.asarray(block_velocities, np.float32),
                                                       colors=[[30, 120, 220]], radii=[0.003]))
        self._logged += 1
        if self._logged % self.flush_every == 0:
            self.rec.flush()

    @_timed
    def log_polygons(self, step: int, time: float, outlines: list, *, kind: str = "polygons") -> None:
        """Outlines (each (k,2) [m]) of rigid polygons, e.g. the blocks of a tilt test:
        closed line strips under world/<kind>, and VTK polygons of that kind."""
        if self.vtk is not None:
            self.vtk.write_polygons(kind, step, time, outlines)
        if self.rec is None:
            return
        self._set_time(step, time, None)
        self.rec.log(f"{P.WORLD}/{kind}", rr.LineStrips2D([np.vstack([o, o[:1]]).astype(np.float32)
                                                           for o in outlines], radii=[0.002]))

    @_timed
    def log_scalar_points(self, entity: str, step: int, time: float, positions: np.ndarray, radii,
                          values: np.ndarray, vmax: float, *, diverging: bool = False) -> None:
        """Points coloured by a scalar per point: viridis over [0, vmax], or with
        ``diverging`` blue-white-red over [-vmax, vmax] (e.g. the sheet pile's moment).
        VTK: a point set named after the entity's last part, ``value`` per point."""
        if self.vtk is not None:
            self.vtk.write_points(entity.rsplit("/", 1)[-1], step, time, positions,
                                  {"value": values, "radius": np.broadcast_to(np.asarray(radii, float), len(values))})
        if self.rec is None:
            return
        self._set_time(step, time, None)
        v = np.asarray(values, float)
        colours = _diverging(v, vmax) if diverging else _viridis(v, vmax)
        self.rec.log(entity, rr.Points3D(np.asarray(positions, np.float32), radii=np.asarray(radii, np.float32),
                                         colors=colours))

    @_timed
    def log_scalar_boxes(self, entity: str, step: int, time: float, centres: np.ndarray, half_sizes: np.ndarray,
                         values: np.ndarray, vmax: float) -> None:
        """Solid boxes coloured (viridis over [0, vmax]) by a scalar per box; nan boxes
        are left out (e.g. a strain field's empty cells)."""
        if self.rec is None:
            return
        v = np.asarray(values, float)
        ok = np.isfinite(v)
        self._set_time(step, time, None)
        self.rec.log(entity, rr.Boxes3D(centers=np.asarray(centres, np.float32)[ok],
                                        half_sizes=np.asarray(half_sizes, np.float32)[ok],
                                        colors=_viridis(v[ok], vmax), fill_mode="solid"))

    # ------------------------------------------------------------------ series
    @_timed
    def log_metrics(self, step: int, time: float, metrics: dict[str, float],
                    wall_disp_over_H: float | None = None) -> None:
        """Buffer scalar series (sent with ``send_columns`` on close); cheap per call."""
        if self.rec is not None:
            self._remember(step, time, wall_disp_over_H, metrics)

    def _remember(self, step, time, disp, metrics) -> None:
        if not metrics:
            return
        for name, value in metrics.items():
            self._series.setdefault(name, []).append(value)
            self._series_time.setdefault(name, []).append((step, time, disp))

    def _send_series(self) -> None:
        for name, values in self._series.items():
            times = np.array(self._series_time[name], dtype=object)
            steps = np.array([t[0] for t in times], dtype=np.int64)
            secs = np.array([t[1] for t in times], dtype=np.float64)
            idx = [rr.TimeColumn(P.TIMELINE_STEP, sequence=steps),
                   rr.TimeColumn(P.TIMELINE_TIME, duration=secs)]
            if all(t[2] is not None for t in times):
                idx.append(rr.TimeColumn(P.TIMELINE_DISP, sequence=np.array(
                    [round(t[2] * P.DISP_TIMELINE_SCALE) for t in times], dtype=np.int64)))
            vals = np.asarray(values, dtype=np.float64)
            entity = f"{P.METRICS}/{name}"
            if vals.ndim == 1:
                self.rec.send_columns(entity, indexes=idx, columns=rr.Scalars.columns(scalars=vals))
            else:
                self.rec.send_columns(entity, indexes=idx, columns=rr.Scalars.columns(
                    scalars=vals.ravel()).partition(np.full(len(vals), vals.shape[1])))

    @_timed
    def close(self) -> None:
        """Send the buffered time series, flush and close the file (and the VTK index)."""
        if self.vtk is not None:
            self.vtk.close()
        if self.rec is None:
            return
        self._send_series()
        self.rec.flush()
        self.rec.disconnect()
        self.rec = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _viewer_executable() -> str | None:
    """The ``rerun`` viewer installed beside this Python (the venv's bin), else on PATH."""
    here = Path(sys.executable).parent / "rerun"
    return str(here) if here.exists() else shutil.which("rerun")


def _spawn_viewer(rec, path: Path | None) -> bool:
    """Start the native viewer for ``rec``; without a display or a viewer say so in one
    line (the recording file is still written) and return False."""
    where = f"; open the recording later with: rerun {path}" if path is not None else ""
    if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        print(f"wallsim: no display for --spawn{where}", file=sys.stderr)
        return False
    exe = _viewer_executable()
    try:
        if exe is None:
            raise FileNotFoundError("rerun")
        rr.spawn(connect=False, executable_path=exe, recording=rec)
        return True
    except Exception as err:          # the run must go on without a viewer
        print(f"wallsim: could not start the viewer ({type(err).__name__}){where}", file=sys.stderr)
        return False


def _scene_size(frame) -> float:
    pos = np.asarray(frame.positions)
    return float(np.ptp(pos, axis=0).max()) if len(pos) else 1.0
