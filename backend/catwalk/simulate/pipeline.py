"""The whole try-on as one call: dress, walk, and the numbers that describe the result."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from catwalk.body.types import Motion
from catwalk.export.garment import GarmentFrames
from catwalk.simulate.dressing import Dressed, dress
from catwalk.simulate.settings import PRESETS, Settings
from catwalk.simulate.walking import Walked, walk


@dataclass
class TryOn:
    dressed: Dressed
    walked: Walked | None
    metrics: dict


def garment_frames(dressed: Dressed, times: np.ndarray, positions: np.ndarray,
                   name: str | None = None) -> GarmentFrames:
    """The simulated garment as :class:`~catwalk.export.garment.GarmentFrames`: one vertex
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


def run_tryon(body, garment, motion: Motion | None, *, size: str | None = None, fabric=None,
              settings: Settings | None = None, progress=None, cancel=None,
              measure: bool = True) -> TryOn:
    """Dress ``body`` in ``garment`` and, if ``motion`` is given, walk it. ``metrics``: the
    keys of ``metrics.json`` (docs/tryon.md)."""
    settings = (settings or PRESETS["balanced"]).check()
    d = dress(body, garment, size, fabric, settings, progress=progress, cancel=cancel)
    w = None
    if motion is not None:
        w = walk(body, motion, d, settings, progress=progress, cancel=cancel, measure=measure)
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
    return TryOn(d, w, metrics)
