"""Simulated garments in the try-on .glb: one mesh per garment, one morph target per frame.

A garment is written as one mesh node at the scene root (identity transform, named after the
garment) whose mesh has one primitive per panel (its own material: the panel's texture, embedded,
or its colour). The base positions are frame 0; frame *i* is morph target *i* (``POSITION``
displacements from the base). A STEP ``weights`` channel in the body's animation clip (one clip
for the whole scene) sets weight *i* to 1 and all others to 0 from ``times[i]`` on, so a player
shows, at time *t*, the last frame whose time is ≤ *t* (the first one before it).

See ``docs/tryon-format.md`` for the whole layout and how three.js plays it.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pygltflib as g

from catwalk.body.types import Body, Motion
from catwalk.errors import InputError
from catwalk.exchange.gltf import (
    GlbBuilder,
    _read_accessor,
    add_body,
    add_motion,
    load_glb,
)
from catwalk.exchange.source import source_name
from catwalk.render.raster import vertex_normals

CLIP = "walk"
FORMAT = "catwalk-tryon"
VERSION = 1


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

    def frame_at(self, t: float) -> int:
        """The frame shown at time ``t`` under STEP playback: the last frame with time ≤ t
        (frame 0 before the first time)."""
        i = int(np.searchsorted(np.asarray(self.times), t, side="right")) - 1
        return max(i, 0)

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
        t32 = _float32_times(times)
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
        if rgb is None:
            rgb = np.asarray([c[:3] for c in self.colors], dtype=np.float64)[
                np.asarray(self.panel)]
        return (self.name, np.asarray(self.positions[i], dtype=np.float64),
                np.asarray(self.triangles, dtype=np.int64), rgb)


def _float32_times(times) -> np.ndarray:
    """Key times as float32, rounded down: a player that asks for exactly ``times[i]`` (in
    double precision, as JavaScript does) must get frame ``i``, not frame ``i - 1``."""
    t = np.asarray(times, dtype=np.float64)
    t32 = t.astype(np.float32)
    up = t32.astype(np.float64) > t
    t32[up] = np.nextafter(t32[up], np.float32(-np.inf))
    return t32


_MAGIC = {b"\x89PNG\r\n\x1a\n": "image/png", b"\xff\xd8\xff": "image/jpeg"}


def _image_bytes(path: str | Path, who: str) -> tuple[bytes, str]:
    data = Path(path).read_bytes()
    for magic, mime in _MAGIC.items():
        if data.startswith(magic):
            return data, mime
    raise InputError(f"{who}: texture {path} is neither PNG nor JPEG (glTF embeds only those)")


def _unit_normals(v: np.ndarray, tri: np.ndarray) -> np.ndarray:
    n = vertex_normals(v, tri)
    bad = np.linalg.norm(n, axis=1) < 0.5
    n[bad] = (0.0, 1.0, 0.0)   # points in no (non-degenerate) triangle: any unit vector
    return n


def _clip(builder: GlbBuilder, animation: int | None) -> int:
    if animation is not None:
        if not 0 <= animation < len(builder.gltf.animations):
            raise ValueError(f"no animation {animation} in the builder")
        return animation
    for i, a in enumerate(builder.gltf.animations):
        if a.name == CLIP:
            return i
    builder.gltf.animations.append(g.Animation(name=CLIP, samplers=[], channels=[]))
    return len(builder.gltf.animations) - 1


def add_garment(builder: GlbBuilder, garment: GarmentFrames, animation: int | None, *,
                morph_normals: bool = False) -> int:
    """Add ``garment`` as a morph-target mesh node at the scene root; its STEP weights channel
    goes into clip ``animation`` (None: the clip named ``walk``, made if missing). Returns the
    node index. ``morph_normals`` also stores per-frame NORMAL displacements (doubles the size;
    without them a player lights every frame with frame 0's normals)."""
    garment.check()
    pos = np.asarray(garment.positions, dtype=np.float32)
    nframes = pos.shape[0]
    tri_all = np.asarray(garment.triangles, dtype=np.int64)
    panel = np.asarray(garment.panel)
    texcoord = garment.texcoords()
    images: dict[str, int] = {}
    primitives = []
    panels_meta = []
    tri_panel = panel[tri_all[:, 0]]
    for i, pname in enumerate(garment.panel_names):
        idx = garment.panel_points(i)
        local = np.full(len(panel), -1, dtype=np.int64)
        local[idx] = np.arange(len(idx))
        tri = local[tri_all[tri_panel == i]]
        base = pos[0, idx]
        normals = _unit_normals(base, tri)
        attrs = g.Attributes(
            POSITION=builder.accessor(base, target=g.ARRAY_BUFFER, minmax=True),
            NORMAL=builder.accessor(normals.astype(np.float32), target=g.ARRAY_BUFFER),
            TEXCOORD_0=builder.accessor(texcoord[idx], target=g.ARRAY_BUFFER))
        disp = pos[:, idx] - base[None]
        targets_pos = builder.stacked_accessors(disp, target=g.ARRAY_BUFFER, minmax=True)
        if morph_normals:
            nrm = np.stack([normals if f == 0 else _unit_normals(pos[f, idx], tri)
                            for f in range(nframes)])
            targets_nrm = builder.stacked_accessors((nrm - normals[None]).astype(np.float32),
                                                    target=g.ARRAY_BUFFER)
            targets = [{"POSITION": a, "NORMAL": b} for a, b in zip(targets_pos, targets_nrm,
                                                                      strict=True)]
        else:
            targets = [{"POSITION": a} for a in targets_pos]
        rgba = [float(x) for x in garment.colors[i]]
        tex = garment.textures[i]
        mat = builder.material(f"{garment.name}/{pname}", rgba if tex is None
                               else (1.0, 1.0, 1.0, rgba[3]))
        material = builder.gltf.materials[mat]
        if rgba[3] < 1.0:
            material.alphaMode = g.BLEND
        if tex is not None:
            key = str(Path(tex[0]).resolve())
            if key not in images:
                data, mime = _image_bytes(tex[0], f"garment {garment.name!r} panel {pname!r}")
                images[key] = builder.repeat_texture(
                    builder.image(data, mime, name=Path(tex[0]).name))
            material.pbrMetallicRoughness.baseColorTexture = g.TextureInfo(index=images[key],
                                                                           texCoord=0)
        primitives.append(g.Primitive(
            attributes=attrs, targets=targets, material=mat, mode=g.TRIANGLES,
            indices=builder.accessor(tri.astype(np.uint32).reshape(-1),
                                     target=g.ELEMENT_ARRAY_BUFFER)))
        panels_meta.append({
            "name": pname, "color": rgba,
            "texture": None if tex is None else {"image": str(tex[0]),
                                                 "size": [float(tex[1][0]), float(tex[1][1])]}})
    extras = {"targetNames": [f"frame{f:04d}" for f in range(nframes)],
              "catwalk": {"garment": garment.name, "frames": nframes, "panels": panels_meta,
                          "uv": "TEXCOORD_0 = (u / w, -v / h): pattern metres over the "
                                "texture size (1 m without a texture)"}}
    builder.gltf.meshes.append(g.Mesh(name=garment.name, primitives=primitives, extras=extras))
    node = builder.node(g.Node(name=garment.name, mesh=len(builder.gltf.meshes) - 1), root=True)

    clip = builder.gltf.animations[_clip(builder, animation)]
    times = _float32_times(garment.times)
    weights = np.eye(nframes, dtype=np.float32).reshape(-1)   # key i: weight i = 1
    clip.samplers.append(g.AnimationSampler(input=builder.accessor(times, minmax=True),
                                            output=builder.accessor(weights),
                                            interpolation="STEP"))
    clip.channels.append(g.AnimationChannel(
        sampler=len(clip.samplers) - 1,
        target=g.AnimationChannelTarget(node=node, path="weights")))
    return node


def build_tryon(body: Body, motion: Motion | None, garments: list[GarmentFrames], *,
                extras: dict | None = None, morph_normals: bool = False) -> GlbBuilder:
    """The try-on scene in a :class:`GlbBuilder` (not yet written)."""
    names = [gm.name for gm in garments]
    if len(set(names)) != len(names):
        raise InputError(f"garment names must be unique, got {names}")
    if "body" in names:
        raise InputError("a garment cannot be named 'body'")
    b = GlbBuilder()
    _, joint_nodes = add_body(b, body)
    clip = None
    if motion is not None:
        if body.skeleton is None:
            raise InputError("a motion needs a rigged body")
        if motion.rotations.shape[1] != len(joint_nodes):
            raise InputError(f"the motion has {motion.rotations.shape[1]} joints, the body's "
                             f"skeleton {len(joint_nodes)}")
        clip = add_motion(b, motion, joint_nodes, name=CLIP)
    for gm in garments:
        add_garment(b, gm, clip, morph_normals=morph_normals)
        clip = _clip(b, clip)
    b.gltf.extras = {"catwalk": {"format": FORMAT, "version": VERSION, "garments": names,
                                 **(extras or {})}}
    return b


def write_tryon(path, body: Body, motion: Motion | None, garments: list[GarmentFrames], *,
                extras: dict | None = None, morph_normals: bool = False) -> None:
    """Write the dressed, walking body as one .glb (atomically): the skinned body, its
    skeleton, each garment as a morph-target mesh and one clip ``walk`` driving both.
    ``extras`` go to the file's top-level ``extras.catwalk``."""
    build_tryon(body, motion, garments, extras=extras, morph_normals=morph_normals).save(path)


def tryon_bytes(body: Body, motion: Motion | None, garments: list[GarmentFrames], *,
                extras: dict | None = None, morph_normals: bool = False) -> bytes:
    """The .glb :func:`write_tryon` writes, as bytes."""
    return build_tryon(body, motion, garments, extras=extras,
                       morph_normals=morph_normals).to_bytes()


# ----------------------------------------------------------------------------- reading

def _weights_channel(gltf: g.GLTF2, node: int):
    for anim in gltf.animations or []:
        for ch in anim.channels:
            if ch.target.node == node and ch.target.path == "weights":
                return anim, anim.samplers[ch.sampler]
    return None, None


def read_garments(path) -> list[GarmentFrames]:
    """The garments of a try-on .glb written by :func:`write_tryon`: positions of frame *i* =
    base + the morph target that the weights channel switches on at key *i*. Points come back
    grouped by panel (in the order written: stable by panel index); textures name the image
    file as it was written (the image itself is embedded in the .glb)."""
    gltf, blob = load_glb(path)
    path = source_name(path, "try-on")
    out = []
    for ni, node in enumerate(gltf.nodes):
        if node.mesh is None:
            continue
        mesh = gltf.meshes[node.mesh]
        meta = (mesh.extras or {}).get("catwalk") or {}
        if "garment" not in meta:
            continue
        anim, sampler = _weights_channel(gltf, ni)
        ntargets = len(mesh.primitives[0].targets or [])
        if ntargets == 0:
            raise InputError(f"{path}: garment {meta['garment']!r} has no morph targets")
        if sampler is None:
            times = np.zeros(1)
            order = np.zeros(1, dtype=np.int64)
        else:
            times = _read_accessor(gltf, blob, sampler.input).astype(np.float64)
            w = _read_accessor(gltf, blob, sampler.output).reshape(len(times), ntargets)
            order = np.argmax(w, axis=1)
        panels = meta.get("panels") or [{} for _ in mesh.primitives]
        pos_parts, tri_parts, uv_parts, panel_parts = [], [], [], []
        textures, colors, names = [], [], []
        offset = 0
        for pi, prim in enumerate(mesh.primitives):
            pm = panels[pi] if pi < len(panels) else {}
            base = _read_accessor(gltf, blob, prim.attributes.POSITION).astype(np.float64)
            if len(prim.targets or []) != ntargets:
                raise InputError(f"{path}: garment {meta['garment']!r}: primitives have "
                                 "different morph target counts")
            disp = np.stack([_read_accessor(gltf, blob, t["POSITION"]) for t in prim.targets])
            pos_parts.append(base[None] + disp[order])
            tri = _read_accessor(gltf, blob, prim.indices).astype(np.int64).reshape(-1, 3)
            tri_parts.append(tri + offset)
            tex = pm.get("texture")
            size = (1.0, 1.0) if not tex else tuple(tex["size"])
            tc = _read_accessor(gltf, blob, prim.attributes.TEXCOORD_0).astype(np.float64)
            uv_parts.append(np.stack([tc[:, 0] * size[0], -tc[:, 1] * size[1]], axis=1))
            panel_parts.append(np.full(len(base), pi, dtype=np.int32))
            textures.append(None if not tex else (tex["image"], size))
            colors.append(tuple(pm.get("color", (0.7, 0.7, 0.7, 1.0))))
            names.append(pm.get("name", f"panel{pi}"))
            offset += len(base)
        out.append(GarmentFrames(
            name=node.name or meta["garment"], triangles=np.concatenate(tri_parts),
            uv=np.concatenate(uv_parts), panel=np.concatenate(panel_parts), panel_names=names,
            textures=textures, colors=colors, times=times,
            positions=np.concatenate(pos_parts, axis=1)))
    return out


def embedded_images(path) -> dict[int, np.ndarray]:
    """Decoded embedded images of a .glb, by image index, as float RGB(A) arrays in 0..1."""
    import io

    from PIL import Image

    gltf, blob = load_glb(path)
    path = source_name(path, "try-on")
    out = {}
    for i, im in enumerate(gltf.images or []):
        if im.bufferView is None:
            continue
        view = gltf.bufferViews[im.bufferView]
        start = view.byteOffset or 0
        data = blob[start:start + view.byteLength]
        try:
            pic = Image.open(io.BytesIO(data)).convert("RGBA")
        except Exception as exc:   # PIL raises several kinds on bad data
            raise InputError(f"{path}: image {i} cannot be decoded ({exc})") from exc
        out[i] = np.asarray(pic, dtype=np.float64) / 255.0
    return out


def panel_texture_images(path) -> dict[str, list[int | None]]:
    """Per garment (by node name), per panel: the index of the embedded image its material
    uses as base colour, or None."""
    gltf, _ = load_glb(path)
    out = {}
    for node in gltf.nodes:
        if node.mesh is None:
            continue
        mesh = gltf.meshes[node.mesh]
        if "garment" not in ((mesh.extras or {}).get("catwalk") or {}):
            continue
        idx = []
        for prim in mesh.primitives:
            im = None
            if prim.material is not None:
                pbr = gltf.materials[prim.material].pbrMetallicRoughness
                if pbr is not None and pbr.baseColorTexture is not None:
                    im = gltf.textures[pbr.baseColorTexture.index].source
            idx.append(im)
        out[node.name] = idx
    return out
