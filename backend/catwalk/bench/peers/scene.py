"""The scene every peer simulates, written to one ``.npz``, and the measures every peer's
result is judged by.

The scene is ``catwalk bench paper``'s: the catalogue dress M at the grid spacing whose sewn
cloth has the paper's number of points, dressed by catwalk on the female base body, then the
body's vertices at every frame the walk steps through (the rest pose it was dressed on, the
blend into the catwalk gait, the gait). A peer starts from the dressed garment (its positions
are its rest shape too: no peer here reads a sewing pattern) and moves it with the body.

The measures are the walk's own (:mod:`catwalk.simulate.walking`): the independent
penetration check of :mod:`catwalk.geometry.surface` on every recorded frame (max, and the
99th percentile over frames of each frame's 99th percentile) and the strain of the welded
model's stretch and shear springs against their pattern rest lengths.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from catwalk.bench.paper import paper_dressed
from catwalk.geometry.surface import BodySurface, penetration
from catwalk.simulate.fidelity import vertex_rms
from catwalk.simulate.walking import strain_of, walk_body_frames


@dataclass
class PeerScene:
    body: object                 # catwalk.body.types.Body
    dressed: object              # catwalk.simulate.dressing.Dressed
    motion: object               # catwalk.body.types.Motion
    settings: object             # catwalk.simulate.settings.Settings (balanced at the paper's h)
    frames: np.ndarray           # (F, V, 3) float32: body vertices at every stepped frame
    n_pre: int                   # frames before the motion's first (not recorded)
    h: float

    @property
    def recorded(self) -> range:
        """Indices into ``frames`` of the recorded (measured) frames."""
        return range(self.n_pre, len(self.frames))

    def save(self, path: str | Path) -> Path:
        """The scene as the peers read it (keys: see ``blender_run.py``)."""
        fab = self.dressed.cloth.fabric
        model, state = self.dressed.model, self.dressed.state
        friction = fab.friction if self.settings.friction is None else self.settings.friction
        path = Path(path)
        np.savez(path, cloth_positions=state.positions.astype(np.float64),
                 cloth_velocities=state.velocities.astype(np.float64),
                 cloth_triangles=np.asarray(model.triangles, dtype=np.int64),
                 cloth_mass=np.asarray(model.mass, dtype=np.float64),
                 body_faces=np.asarray(self.body.faces, dtype=np.int64),
                 body_frames=self.frames.astype(np.float32),
                 fps=float(self.motion.fps), record_from=int(self.n_pre),
                 stretch=0.5 * (fab.stretch_warp + fab.stretch_weft), shear=float(fab.shear),
                 bend=0.5 * (fab.bend_warp + fab.bend_weft), friction=float(friction),
                 damping=float(fab.damping), air=float(fab.air),
                 thickness=float(self.settings.thickness))
        return path


def paper_scene(seconds: float, size: str = "M", progress=None) -> PeerScene:
    """Dress the paper's scene once and skin the body for every frame of the walk."""
    body, motion, settings, dressed = paper_dressed(seconds, size, progress)
    frames, _, n_pre = walk_body_frames(body, motion, settings, progress=progress)
    return PeerScene(body, dressed, motion, settings, frames, n_pre, settings.h)


def welded(dressed, pattern_positions: np.ndarray) -> np.ndarray:
    """Recorded positions per pattern point (F, pattern points, 3) → per welded point."""
    out = np.empty((len(pattern_positions), dressed.model.n_points, 3), dtype=np.float32)
    out[:, dressed.rep] = pattern_positions
    return out


def measure(scene: PeerScene, positions: np.ndarray) -> dict:
    """Penetration and strain of ``positions`` (one per recorded frame, welded points), and
    whether every value is finite."""
    if not np.all(np.isfinite(positions)):
        return {"finite": False}
    surface = BodySurface(scene.body.faces, len(scene.body.vertices))
    pen_max, pen_99, e_max, e_99 = [], [], [], []
    for f, x in zip(scene.recorded, positions, strict=True):
        x = x.astype(np.float64)
        pen = penetration(surface, scene.frames[f], x)
        pen_max.append(float(pen.max()))
        pen_99.append(float(np.percentile(pen, 99)))
        e = strain_of(scene.dressed.model, x)
        e_max.append(float(e.max()))
        e_99.append(float(np.percentile(e, 99)))
    return {"finite": True,
            "max_penetration_mm": round(1e3 * max(pen_max), 2),
            "p99_penetration_mm": round(1e3 * float(np.percentile(pen_99, 99)), 2),
            "max_strain": round(max(e_max), 4), "p99_strain": round(max(e_99), 4)}


def rms_mm(a: np.ndarray, b: np.ndarray) -> float:
    """Per-vertex RMS distance (mm) between two runs over the recorded frames
    (:func:`catwalk.simulate.fidelity.vertex_rms`, rounded to 0.1 mm)."""
    return round(1e3 * vertex_rms(a, b), 1)
