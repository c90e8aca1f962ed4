"""The try-on as one call: catwalk's public entry point, ``catwalk.tryon(...)``.

The command line (``catwalk tryon``, ``catwalk dress``), the service's workers and the service
benchmark all call :func:`tryon`; it checks its inputs (every problem an
:class:`~catwalk.errors.InputError` naming the parameter, before any simulation), dresses the
body, walks it, and returns a :class:`TryOn` whose :meth:`TryOn.glb` is the result file.

The same inputs give the same bytes: the simulation is deterministic and the file holds no
clock time (wall-clock timings are in :attr:`TryOn.metrics` only, never in the .glb).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from catwalk.body.from_scan import body_from_scan
from catwalk.body.types import Body, Motion
from catwalk.cloth.fabrics import resolve_fabric
from catwalk.errors import InputError
from catwalk.exchange.garment_json import load_garment
from catwalk.exchange.gltf import load_glb, read_body
from catwalk.exchange.scan import load_scan
from catwalk.exchange.tryon_glb import tryon_bytes
from catwalk.fileio import atomic_path
from catwalk.garment.check import require_valid
from catwalk.garment.frames import GarmentFrames
from catwalk.garment.model import Garment
from catwalk.motion.gait import walk_motion
from catwalk.simulate.dressing import Dressed, dress
from catwalk.simulate.progress import Progress, tryon_plan
from catwalk.simulate.settings import PRESETS, Settings, preset
from catwalk.simulate.walking import Walked, blend_frame_count, walk

SECONDS = (0.0, 60.0)   # the walk's length; 0: dressed only, standing
FPS = (10.0, 60.0)

# metrics that are wall-clock times: in TryOn.metrics, never in the file
_WALL_CLOCK = ("dressing_seconds", "ms_per_frame", "seconds")
_WALL_CLOCK_DRESSING = ("sewing_s", "settling_s", "dressing_s")


@dataclass
class TryOn:
    """A finished try-on: the body, the garment, the walk, the simulated cloth, the metrics
    (docs/tryon.md: the keys of ``metrics.json``)."""

    body: Body
    garment: Garment
    motion: Motion | None          # None: dressed only
    dressed: Dressed
    walked: Walked | None
    metrics: dict = field(default_factory=dict)
    name: str | None = None        # the garment's node in the file: "garment:<name>"

    def frames(self) -> GarmentFrames:
        """The garment as shown, per frame (one frame, standing, when there is no walk)."""
        name = f"garment:{self.name}" if self.name else None
        if self.walked is None:
            return static_frames(self.dressed, name)
        return garment_frames(self.dressed, self.walked.times, self.walked.positions, name)

    def file_metrics(self) -> dict:
        """The metrics the .glb carries: :attr:`metrics` without wall-clock times."""
        out = {k: v for k, v in self.metrics.items()
               if k not in _WALL_CLOCK and k != "penetration_mm_per_frame"}
        if "dressing" in out:
            out["dressing"] = {k: v for k, v in out["dressing"].items()
                               if k not in _WALL_CLOCK_DRESSING}
        return out

    def glb(self, normals: bool = True) -> bytes:
        """The try-on .glb (docs/tryon-format.md): byte-identical for the same inputs.
        ``normals=False``: without the garment's per-frame normals (the web copy: a player
        computes them)."""
        return tryon_bytes(self.body, self.motion, [self.frames()],
                           extras={"metrics": self.file_metrics()}, normals=normals)

    def write(self, path: str | Path) -> None:
        """Write :meth:`glb` to ``path`` atomically."""
        data = self.glb()
        with atomic_path(path) as tmp:
            tmp.write_bytes(data)


def garment_frames(dressed: Dressed, times: np.ndarray, positions: np.ndarray,
                   name: str | None = None) -> GarmentFrames:
    """The simulated garment as :class:`~catwalk.garment.frames.GarmentFrames`: one vertex
    per pattern point (panels keep their own UVs along seams)."""
    gc = dressed.cloth
    m = gc.model
    slug = name or "garment:" + (gc.garment.path.stem if gc.garment.path else gc.garment.type)
    return GarmentFrames(
        name=slug, triangles=m.triangles.astype(np.int64), uv=m.uv, panel=m.panel,
        panel_names=list(m.panel_names), textures=list(gc.textures), colors=list(gc.colors),
        times=np.asarray(times, dtype=np.float64),
        positions=np.asarray(positions, dtype=np.float32))


def static_frames(dressed: Dressed, name: str | None = None) -> GarmentFrames:
    """The dressed garment at rest as a one-frame :class:`GarmentFrames`."""
    return garment_frames(dressed, np.zeros(1), dressed.pattern_positions(dressed.display)[None],
                          name)


# ---------------------------------------------------------------------------- the inputs

def load_body(body, cancel=None) -> Body:
    """A body ready to dress and walk: a :class:`Body`, a .glb from ``catwalk body make`` or
    ``catwalk body from-scan`` as a path, bytes or a file object, or a scan's file (OBJ, PLY,
    STL, or a GLB with no skin), registered to the template as ``catwalk body from-scan``
    does (``cancel()`` asked between its stages)."""
    if not isinstance(body, Body):
        if isinstance(body, (str, Path)) and not Path(body).is_file():
            raise InputError(f"body {body}: no such file", "body")
        if isinstance(body, (str, Path)) and (Path(body).suffix.lower() != ".glb"
                                              or not _has_skin(body)):
            return body_of_scan(body, cancel)
        body = read_body(body)
    if body.parts is None or not body.landmarks:
        raise InputError("body: the body has no parts or landmarks; make it with "
                         "`catwalk body make` (or POST /api/bodies)", "body")
    return body


def _has_skin(path) -> bool:
    """Whether the .glb at ``path`` has a skin (a body) rather than none (a scan); a file that
    is no readable GLB is left to the body reader's message."""
    try:
        doc, _ = load_glb(path)
    except (InputError, ValueError, OSError):
        return True
    return bool(doc.skins)


def body_of_scan(path, cancel=None) -> Body:
    """The template registered to the scan at ``path`` (see :mod:`catwalk.body.from_scan`)."""
    scan = load_scan(path)
    try:
        return body_from_scan(scan, cancel=cancel)[0]
    except InputError as exc:
        raise InputError(f"body {scan.path}: {exc}", "body") from None


def load_checked_garment(garment, base_dir: str | Path | None = None) -> Garment:
    """A garment that passes ``catwalk garment check``: a :class:`Garment`, a parsed dict, or
    a garment JSON file as a path, bytes or a file object (textures relative to its folder,
    or to ``base_dir``)."""
    if not isinstance(garment, Garment):
        garment = load_garment(garment, base_dir=base_dir)
    folder = garment.path.parent if garment.path is not None else (
        Path(base_dir) if base_dir is not None else Path("."))
    require_valid(garment, folder)
    return garment


def check_options(garment: Garment, *, size: str | None, fabric, seconds: float, fps: float,
                  settings: Settings) -> str:
    """Check the options against the garment before any work; returns the size used."""
    if not isinstance(seconds, (int, float)) or not math.isfinite(seconds) \
            or not SECONDS[0] <= seconds <= SECONDS[1]:
        raise InputError(f"seconds must be within 0–{SECONDS[1]:g} (0: dressed, standing), "
                         f"got {seconds}", "seconds")
    if not isinstance(fps, (int, float)) or not math.isfinite(fps) \
            or not FPS[0] <= fps <= FPS[1]:
        raise InputError(f"fps must be within {FPS[0]:g}–{FPS[1]:g}, got {fps}", "fps")
    try:
        used = garment.size(size)
    except InputError as exc:
        raise InputError(str(exc), "size") from None
    if fabric is not None:
        resolve_fabric(fabric, "fabric")
    settings.check()
    return used


def resolve_settings(preset_name: str | Settings = "balanced", **changes) -> Settings:
    """A preset by name (or a :class:`Settings`) with some settings changed (None: kept)."""
    base = preset_name if isinstance(preset_name, Settings) else preset(preset_name)
    try:
        return base.with_(**changes)
    except TypeError as exc:
        raise InputError(f"unknown setting ({exc})", "settings") from None


# ---------------------------------------------------------------------------- the call

def tryon(body, garment, *, size: str | None = None, fabric=None, seconds: float = 4.0,
          fps: float = 30.0, speed: float = 1.2, style: str = "catwalk",
          preset: str | Settings = "balanced", collider: str | None = None,
          h: float | None = None, garment_dir: str | Path | None = None,
          garment_id: str | None = None,
          progress: Callable[[float, str], None] | Progress | None = None,
          cancel: Callable[[], bool] | None = None, measure: bool = True) -> TryOn:
    """Dress ``body`` in ``garment`` and walk it ``seconds`` (0: dressed, standing).

    ``body``: a :class:`Body`, a body .glb (path, bytes, file object) or a scan's file
    (registered first, :mod:`catwalk.body.from_scan`); ``garment``: a
    :class:`Garment`, a dict or a garment JSON (path, bytes, file object; textures relative to
    its folder or ``garment_dir``; ``garment_id`` names it in the file, by default its file's
    stem, else its type); ``size``: one of the garment's (default: its default);
    ``fabric``: a preset name or custom fabric instead of the garment's; ``preset``: ``fast``,
    ``balanced``, ``accurate`` or a :class:`Settings`, with ``collider`` and ``h`` changed
    when given; ``speed`` (m/s) and ``style`` (``catwalk``, ``normal``) shape the walk.

    ``progress(stage, fraction, 1.0)`` (:mod:`catwalk.progress`): the stage and the overall
    fraction 0..1 (monotonic) of the try-on
    (``placing``, ``sewing``, ``settling``, ``relief``, ``gait``, ``skinning``,
    ``blending``, ``walking``, then ``done``); or a :class:`Progress` with a plan of the
    caller's (:func:`~catwalk.simulate.progress.tryon_plan` with the caller's own stages after
    the simulation's; the caller then reports those and ``done`` itself). ``cancel()`` is asked a
    few milliseconds apart in every stage; :class:`~catwalk.errors.Cancelled` is raised once
    it returns true. Bad input raises :class:`~catwalk.errors.InputError` (``field`` names the
    parameter) before anything is simulated; a simulation that fails raises
    :class:`~catwalk.errors.SimulationError`.
    """
    t0 = time.perf_counter()
    settings = resolve_settings(preset, collider=collider, h=h)
    garment = load_checked_garment(garment, garment_dir)
    used_size = check_options(garment, size=size, fabric=fabric, seconds=seconds, fps=fps,
                              settings=settings)
    body = load_body(body, cancel)
    walking = seconds > 0
    if walking and (body.skeleton is None or body.skin_joints is None):
        raise InputError("body: the body has no rig; make it with `catwalk body make`", "body")
    frames = int(round(seconds * fps))
    blend = blend_frame_count(settings, fps) if walking else 0
    own = not isinstance(progress, Progress)
    if own:
        progress = Progress(tryon_plan(settings, frames, blend, walking), progress, cancel)
    progress.enter("placing")
    motion = None
    d = dress(body, garment, used_size, fabric, settings, progress=progress,
              cancel=progress.cancelled)
    w = None
    if walking:
        progress.enter("gait")
        motion = walk_motion(body, seconds, speed=speed, style=style, fps=fps)
        w = walk(body, motion, d, settings, progress=progress, cancel=progress.cancelled,
                 measure=measure)
    result = TryOn(body, garment, motion, d, w, tryon_metrics(body, garment, d, w, settings),
                   garment_id)
    result.metrics["seconds"] = round(time.perf_counter() - t0, 3)
    if own:
        progress.done()
    return result


def tryon_metrics(body: Body, garment: Garment, d: Dressed, w: Walked | None,
                  settings: Settings) -> dict:
    """The keys of ``metrics.json`` (docs/tryon.md)."""
    ds = d.stats
    metrics = {
        "garment": garment.name, "size": ds["size"], "fabric": ds["fabric"],
        "preset": settings.name, "collider": settings.collider, "h_m": settings.h,
        "points": ds["points"], "pattern_points": ds["pattern_points"],
        "springs": ds["springs"], "triangles": ds["triangles"],
        "body_triangles": int(len(body.faces)),
        "dressing_seconds": round(ds["dressing_s"], 3),
        "dressing": {k: v for k, v in ds.items() if k not in ("points", "springs")},
        "max_seam_gap_mm": 1e3 * ds["seam_gap_m"],
    }
    if w is not None:
        ws = w.stats
        metrics.update({
            "frames": ws["frames"], "fps": ws["fps"],
            "substeps_per_frame": {"cloth": ws["cloth_steps_per_frame"],
                                   "collisions": ws["collisions_per_frame"]},
            "ms_per_frame": {k: round(v, 3) for k, v in ws["ms_per_frame"].items()},
            "max_penetration_mm": ws.get("max_penetration_mm"),
            "p99_penetration_mm": ws.get("p99_penetration_mm"),
            "penetration_mm_per_frame": ws.get("penetration_mm_per_frame"),
            "max_strain": ws["max_strain"], "p99_strain": ws["p99_strain"],
            "springs_over_limit": ws.get("springs_over_limit"),
            "over_limit_crossing_body": ws.get("over_limit_crossing_body"),
            "max_seam_gap_mm": max(1e3 * ds["seam_gap_m"], ws["max_seam_gap_mm"]),
            "nan": bool(ws["nan"]), "exploded": bool(ws["exploded"]),
            "slowed_points": ws["slowed_points"] + ds["slowed_points"],
            "sharp_pushes": ws["sharp_pushes"], "sharp_push_max_mm": ws["sharp_push_max_mm"],
        })
    else:
        metrics.update({"max_strain": ds["max_strain"], "nan": False, "exploded": False,
                        "slowed_points": ds["slowed_points"], "sharp_pushes": ds["sharp_pushes"],
                        "sharp_push_max_mm": ds["sharp_push_max_mm"]})
    for k, v in list(metrics.items()):
        if isinstance(v, float) and not math.isfinite(v):
            metrics[k] = None
    return metrics


__all__ = ["PRESETS", "TryOn", "garment_frames", "load_body", "load_checked_garment",
           "static_frames", "tryon", "tryon_metrics"]
