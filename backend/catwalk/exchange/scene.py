"""A .glb written by catwalk, evaluated at any time: the skinned body and its garments.

``load_scene(path).meshes_at(t)`` gives ``[(name, vertices, faces, rgb)]`` in world space —
the body skinned from the joint animation stored in the file itself (quaternions interpolated
between the stored frames) and each garment at the frame its STEP weights channel shows at
``t`` (the last frame whose time is ≤ t), coloured per vertex from its panels' textures (sampled
at the texture coordinates, pre-filtered to the mesh's resolution) or colours — so what is
checked or rendered is what a viewer plays.
"""

from __future__ import annotations

import io
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np
from PIL import Image

from catwalk.body.skinning import joint_world_matrices, skin
from catwalk.body.types import Body, Motion
from catwalk.exchange.gltf import read_body, read_motion
from catwalk.exchange.source import read_source
from catwalk.exchange.tryon_glb import (
    embedded_images,
    panel_texture_images,
    read_garments,
)
from catwalk.garment.frames import GarmentFrames

SKIN_RGB = (0.80, 0.66, 0.58)


def sample_motion(motion: Motion, t: float) -> tuple[np.ndarray, np.ndarray]:
    """(rotations (J,4), translations (J,3)) at time ``t`` (clamped to the clip), normalised
    lerp between the stored frames."""
    n = motion.frames
    f = min(max(t * motion.fps, 0.0), n - 1.0)
    k = int(np.floor(f))
    k1 = min(k + 1, n - 1)
    a = f - k
    q0, q1 = motion.rotations[k], motion.rotations[k1]
    sign = np.where(np.sum(q0 * q1, axis=1, keepdims=True) < 0, -1.0, 1.0)
    q = (1 - a) * q0 + a * sign * q1
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    tr = (1 - a) * motion.translations[k] + a * motion.translations[k1]
    return q, tr


def texture_vertex_colours(image: np.ndarray, texcoord: np.ndarray,
                           triangles: np.ndarray) -> np.ndarray:
    """RGB per vertex of ``image`` (H, W, 3|4 floats in 0..1, REPEAT-wrapped) at ``texcoord``
    (n, 2), the image first box-filtered so one texel is about one mesh edge long (a mip level:
    a fine pattern averages out instead of aliasing)."""
    tc = np.asarray(texcoord, dtype=np.float64)
    tri = np.asarray(triangles, dtype=np.int64)
    rgb = np.asarray(image, dtype=np.float64)[..., :3]
    h, w = rgb.shape[:2]
    edge = np.abs(tc[tri] - tc[np.roll(tri, 1, axis=1)]).reshape(-1, 2)
    step = np.maximum(np.median(edge, axis=0), 1e-6) if len(edge) else np.ones(2)
    nw = int(np.clip(round(1.0 / step[0]), 1, w))
    nh = int(np.clip(round(1.0 / step[1]), 1, h))
    if (nw, nh) != (w, h):
        pic = Image.fromarray(np.uint8(np.clip(rgb, 0, 1) * 255 + 0.5))
        rgb = np.asarray(pic.resize((nw, nh), Image.Resampling.BOX), dtype=np.float64) / 255.0
    u = np.mod(tc[:, 0], 1.0)
    v = np.mod(tc[:, 1], 1.0)
    j = np.minimum((u * nw).astype(np.int64), nw - 1)
    i = np.minimum((v * nh).astype(np.int64), nh - 1)
    return rgb[i, j]


def garment_vertex_colours(garment: GarmentFrames,
                           images: list[np.ndarray | None]) -> np.ndarray:
    """(P, 3) colours: per panel, its texture sampled (times its colour's RGB) or its colour."""
    panel = np.asarray(garment.panel)
    tri = np.asarray(garment.triangles)
    tc = garment.texcoords()
    out = np.empty((len(panel), 3))
    for i in range(len(garment.panel_names)):
        pts = np.flatnonzero(panel == i)
        c = np.asarray(garment.colors[i][:3], dtype=np.float64)
        img = images[i] if i < len(images) else None
        if img is None:
            out[pts] = c
            continue
        local = np.full(len(panel), -1, dtype=np.int64)
        local[pts] = np.arange(len(pts))
        t = local[tri[panel[tri[:, 0]] == i]]
        # textured materials carry a white factor: the colour is the texture's
        factor = c if garment.textures[i] is None else np.ones(3)
        out[pts] = texture_vertex_colours(img, tc[pts], t) * factor
    return out


@dataclass
class Scene:
    body: Body
    motion: Motion | None
    garments: list[GarmentFrames] = field(default_factory=list)
    garment_rgb: list[np.ndarray] = field(default_factory=list)   # (P, 3) per garment

    @cached_property
    def _inverse_bind(self) -> np.ndarray:
        return self.body.skeleton.inverse_bind   # rest pose: computed once, not per frame

    @property
    def animated(self) -> bool:
        return self.motion is not None or any(gm.frames > 1 for gm in self.garments)

    @property
    def duration(self) -> float:
        """Length of the clip: its last key, body or garment."""
        ends = [0.0 if self.motion is None else (self.motion.frames - 1) / self.motion.fps]
        ends += [float(gm.times[-1]) for gm in self.garments]
        return max(ends)

    def body_vertices_at(self, t: float) -> np.ndarray:
        if self.motion is None or self.body.skeleton is None:
            return self.body.vertices

        rot, tr = sample_motion(self.motion, t)
        world = joint_world_matrices(self.body.skeleton, rot, tr)
        mats = world @ self._inverse_bind
        return skin(self.body.vertices, self.body.skin_joints, self.body.skin_weights, mats)

    def meshes_at(self, t: float) -> list[tuple[str, np.ndarray, np.ndarray, tuple]]:
        out = [("body", self.body_vertices_at(t), self.body.faces, SKIN_RGB)]
        for k, gm in enumerate(self.garments):
            rgb = self.garment_rgb[k] if k < len(self.garment_rgb) else None
            out.append(gm.mesh_at(gm.positions_at(t), rgb))   # interpolated, as players do
        return out


def scene_of(body: Body, motion: Motion | None, garments: list[GarmentFrames]) -> Scene:
    """The scene of a try-on still in memory (no file read back): textures from the image
    files the garment frames name."""
    def image(tex):
        if tex is None:
            return None
        pic = Image.open(io.BytesIO(Path(tex[0]).read_bytes())).convert("RGBA")
        return np.asarray(pic, dtype=np.float64) / 255.0

    rgb = [garment_vertex_colours(gm, [image(t) for t in gm.textures]) for gm in garments]
    return Scene(body=body, motion=motion, garments=list(garments), garment_rgb=rgb)


def load_scene(source) -> Scene:
    """The scene of a try-on .glb (a path, bytes or a binary file object)."""
    data, name = read_source(source, "try-on")   # read once: several readers parse it
    garments = read_garments(data, label=name)
    rgb = []
    if garments:
        images = embedded_images(data, label=name)
        uses = panel_texture_images(data, label=name)
        for gm in garments:
            rgb.append(garment_vertex_colours(
                gm, [None if i is None else images.get(i) for i in uses.get(gm.name, [])]))
    return Scene(body=read_body(data, label=name), motion=read_motion(data, label=name),
                 garments=garments, garment_rgb=rgb)
