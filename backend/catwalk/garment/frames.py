"""What the walk produces for a garment: its points' positions at every frame, and how to draw
its panels (triangles, pattern coordinates, textures, colours). Every writer takes it: the
try-on .glb (:mod:`catwalk.exchange.tryon_glb`, which also reads it back), the OBJ and Open
Inventor frames, the preview renders."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from catwalk.errors import InputError


def float32_times(times) -> np.ndarray:
    """Key times as float32, rounded down: a player that asks for exactly ``times[i]`` (in
    double precision, as JavaScript does) must get frame ``i``, not frame ``i - 1``."""
    t = np.asarray(times, dtype=np.float64)
    t32 = t.astype(np.float32)
    up = t32.astype(np.float64) > t
    t32[up] = np.nextafter(t32[up], np.float32(-np.inf))
    return t32


@dataclass
class GarmentFrames:
    """A simulated garment: per-frame positions of its points, and how to draw its panels."""
    name: str                      # node + mesh name, e.g. "garment:dress"
    triangles: np.ndarray          # (T, 3) int, over the P points
    uv: np.ndarray                 # (P, 2) float, pattern coordinates in metres
    panel: np.ndarray              # (P,) int, panel index of each point (panels never share points)
    panel_names: list[str]
    textures: list[tuple[str, tuple[float, float]] | None]  # per panel: (image, (w, h) metres)
    colors: list[tuple[float, float, float, float]]         # per panel base colour, linear RGBA
    times: np.ndarray              # (F,) seconds, increasing, frame times
    positions: np.ndarray          # (F, P, 3) float world metres (glTF axes: +Y up)

    @property
    def frames(self) -> int:
        return int(np.asarray(self.positions).shape[0])

    def frame_at(self, t: float) -> tuple[int, float]:
        """``(i, s)``: at time ``t`` a player shows frame ``i`` blended ``s`` (0 ≤ s < 1) of
        the way to frame ``i + 1`` (LINEAR keys; clamped before the first and after the last
        frame)."""
        times = np.asarray(self.times, dtype=np.float64)
        i = int(np.searchsorted(times, t, side="right")) - 1
        if i < 0:
            return 0, 0.0
        if i >= len(times) - 1:
            return len(times) - 1, 0.0
        return i, float((t - times[i]) / (times[i + 1] - times[i]))

    def positions_at(self, t: float) -> np.ndarray:
        """(P, 3) positions at time ``t``, interpolated between frames as a player does."""
        i, s = self.frame_at(t)
        pos = np.asarray(self.positions)
        if s == 0.0:
            return np.asarray(pos[i], dtype=np.float64)
        return (1.0 - s) * pos[i].astype(np.float64) + s * pos[i + 1].astype(np.float64)

    def check(self) -> None:
        """Raise :class:`InputError` naming the garment and the field that is wrong."""
        who = f"garment {self.name!r}"
        if not self.name:
            raise InputError("a garment needs a name")
        pos = np.asarray(self.positions)
        if pos.ndim != 3 or pos.shape[2] != 3 or pos.shape[0] < 1 or pos.shape[1] < 3:
            raise InputError(f"{who}: positions must be (frames, points ≥ 3, 3), got {pos.shape}")
        f, p = pos.shape[:2]
        if not np.all(np.isfinite(pos)):
            raise InputError(f"{who}: positions contain NaN or infinity")
        times = np.asarray(self.times, dtype=np.float64)
        if times.shape != (f,):
            raise InputError(f"{who}: {f} frames of positions but times has shape {times.shape}")
        t32 = float32_times(times)
        if not np.all(np.isfinite(times)) or times[0] < 0 or np.any(np.diff(t32) <= 0):
            raise InputError(f"{who}: times must be finite, ≥ 0 and strictly increasing "
                             "(also as float32)")
        uv = np.asarray(self.uv)
        if uv.shape != (p, 2) or not np.all(np.isfinite(uv)):
            raise InputError(f"{who}: uv must be finite ({p}, 2), got {uv.shape}")
        tri = np.asarray(self.triangles)
        if tri.ndim != 2 or tri.shape[1] != 3 or len(tri) == 0 or tri.dtype.kind not in "iu":
            raise InputError(f"{who}: triangles must be a non-empty (T, 3) integer array, "
                             f"got {tri.dtype} {tri.shape}")
        if tri.min() < 0 or tri.max() >= p:
            raise InputError(f"{who}: triangle index out of range 0..{p - 1}")
        panel = np.asarray(self.panel)
        n = len(self.panel_names)
        if panel.shape != (p,) or panel.dtype.kind not in "iu":
            raise InputError(f"{who}: panel must be ({p},) integers, got {panel.dtype} "
                             f"{panel.shape}")
        if n == 0 or panel.min() < 0 or panel.max() >= n:
            raise InputError(f"{who}: panel index out of range 0..{n - 1}")
        if len(self.textures) != n or len(self.colors) != n:
            raise InputError(f"{who}: {n} panel names but {len(self.textures)} textures and "
                             f"{len(self.colors)} colours")
        if len(set(self.panel_names)) != n:
            raise InputError(f"{who}: panel names are not unique: {self.panel_names}")
        tp = panel[tri]
        if np.any(tp[:, 0] != tp[:, 1]) or np.any(tp[:, 0] != tp[:, 2]):
            bad = int(np.flatnonzero((tp[:, 0] != tp[:, 1]) | (tp[:, 0] != tp[:, 2]))[0])
            raise InputError(f"{who}: triangle {bad} joins points of different panels")
        has = np.bincount(tp[:, 0], minlength=n)
        for i, name in enumerate(self.panel_names):
            if has[i] == 0:
                raise InputError(f"{who}: panel {name!r} has no triangles")
            c = self.colors[i]
            if len(c) != 4 or not all(0.0 <= float(x) <= 1.0 for x in c):
                raise InputError(f"{who}: panel {name!r} colour must be RGBA in 0..1, got {c}")
            tex = self.textures[i]
            if tex is not None:
                image, size = tex
                if not Path(image).is_file():
                    raise InputError(f"{who}: panel {name!r} texture {image}: no such file")
                if len(size) != 2 or not all(float(s) > 0 for s in size):
                    raise InputError(f"{who}: panel {name!r} texture size must be two positive "
                                     f"lengths (m), got {size}")

    def panel_points(self, i: int) -> np.ndarray:
        return np.flatnonzero(np.asarray(self.panel) == i)

    def texcoords(self) -> np.ndarray:
        """(P, 2) float32 TEXCOORD_0: pattern metres / the panel texture's size, v flipped
        (glTF's v runs down the image, pattern y runs up); untextured panels: metres."""
        uv = np.asarray(self.uv, dtype=np.float64)
        scale = np.ones((len(self.panel_names), 2))
        for i, tex in enumerate(self.textures):
            if tex is not None:
                scale[i] = tex[1]
        s = scale[np.asarray(self.panel)]
        return np.stack([uv[:, 0] / s[:, 0], -uv[:, 1] / s[:, 1]], axis=1).astype(np.float32)

    def mesh_at_frame(self, i: int, rgb=None) -> tuple[str, np.ndarray, np.ndarray, object]:
        """``(name, vertices, triangles, rgb)`` of frame ``i`` (rgb: per-vertex panel colours
        unless given), the tuple :meth:`catwalk.exchange.scene.Scene.meshes_at` returns."""
        return self.mesh_at(np.asarray(self.positions[i], dtype=np.float64), rgb)

    def mesh_at(self, vertices: np.ndarray, rgb=None) -> tuple[str, np.ndarray, np.ndarray,
                                                               object]:
        if rgb is None:
            rgb = np.asarray([c[:3] for c in self.colors], dtype=np.float64)[
                np.asarray(self.panel)]
        return (self.name, vertices, np.asarray(self.triangles, dtype=np.int64), rgb)
