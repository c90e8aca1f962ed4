"""Simulated garments in the try-on .glb, laid out for browsers to play.

Each garment is one or more *chunk* meshes whose morph targets are its frames: a chunk holds at
most :data:`CHUNK_TARGETS` frames (WebGL2 guarantees only 256 texture layers and 256 vertex
uniform vectors, and a player loops over every target of a mesh for every vertex), and
consecutive chunks share one frame. A chunk's base positions are its first frame; target *j* is
frame ``first + j`` (``POSITION`` and ``NORMAL`` displacements from the base, so every frame is
lit with its own normals; the web copy leaves them out and the player computes them). Its
``weights`` channel is LINEAR with one-hot keys at the frame
times, so a player shows the positions interpolated between two frames, as the skinned body's
joints are; its ``scale`` channel (STEP, 1 or 0) shows exactly one chunk at any time.

Chunk nodes sit at the scene root with identity transforms: positions are world metres. (Local
offsets under a node following the walker were tried: gltfpack quantises a morph displacement
with its mesh's position step whatever its size, so they bought no precision, and the web copy
of the 4 s dress grew from 1.61 to 2.12 MB.) Each target accessor has ``min``/``max``, so a
player that takes a mesh's bounds from them with its targets (three.js's GLTFLoader does)
keeps the garment drawn wherever it walks. Each primitive (one per panel) also carries
``TEXCOORD_1``: each vertex's position in its flat cutting pattern (metres, unscaled: no
material uses it), the rest shape a player measures stretch against (the fit map).

See ``docs/tryon-format.md`` for the whole layout and how three.js plays it.
"""

from __future__ import annotations

import io
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
import pygltflib as g
from PIL import Image

from catwalk.body.types import Body, Motion
from catwalk.errors import InputError
from catwalk.exchange.gltf import (
    MAX_IMAGE_PIXELS,
    GlbBuilder,
    Gltf,
    GltfObject,
    _catwalk_extras,
    _index,
    _is_int,
    _numbers,
    _quiet,
    _read_accessor,
    add_body,
    add_motion,
    load_glb,
)
from catwalk.exchange.source import source_name
from catwalk.garment.frames import GarmentFrames, float32_times
from catwalk.geometry.raster import vertex_normals

CLIP = "walk"
FORMAT = "catwalk-tryon"
VERSION = 2
CHUNK_TARGETS = 64   # morph targets per mesh at most


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


def chunk_spans(frames: int, size: int = CHUNK_TARGETS) -> list[tuple[int, int]]:
    """``(first, last)`` frames of each chunk: at most ``size`` frames, consecutive chunks
    sharing one frame (so a player interpolates across the seam between two)."""
    if frames <= size:
        return [(0, frames - 1)]
    spans, first = [], 0
    while first < frames - 1:
        last = min(first + size - 1, frames - 1)
        spans.append((first, last))
        first = last
    return spans


def _panel_materials(builder: GlbBuilder, garment: GarmentFrames) -> tuple[list[int], list]:
    """One material per panel (its texture embedded once per image, or its colour) and the
    panels' metadata for the mesh extras."""
    images: dict[str, int] = {}
    materials, meta = [], []
    for i, pname in enumerate(garment.panel_names):
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
        materials.append(mat)
        # the image's file name only: the file's bytes do not depend on where it was made
        meta.append({"name": pname, "color": rgba,
                     "texture": None if tex is None else {
                         "image": Path(tex[0]).name,
                         "size": [float(tex[1][0]), float(tex[1][1])]}})
    return materials, meta


def _chunk_mesh(builder: GlbBuilder, garment: GarmentFrames, local: np.ndarray,
                span: tuple[int, int], materials: list[int], panels_meta: list,
                chunk: int, chunks: int, normals: bool) -> int:
    """The mesh of frames ``span`` (local positions, (F, P, 3)): one primitive per panel;
    ``normals``: NORMAL targets too (else every frame has the first frame's normals)."""
    first, last = span
    frames = local[first:last + 1]
    tri_all = np.asarray(garment.triangles, dtype=np.int64)
    panel = np.asarray(garment.panel)
    texcoord = garment.texcoords()
    pattern = np.asarray(garment.uv, dtype=np.float32)
    tri_panel = panel[tri_all[:, 0]]
    primitives = []
    for i in range(len(garment.panel_names)):
        idx = garment.panel_points(i)
        where = np.full(len(panel), -1, dtype=np.int64)
        where[idx] = np.arange(len(idx))
        tri = where[tri_all[tri_panel == i]]
        pts = frames[:, idx]
        nrm = np.stack([_unit_normals(f, tri) for f in (pts if normals else pts[:1])]
                       ).astype(np.float32)
        base, base_n = pts[0], nrm[0]
        attrs = g.Attributes(
            POSITION=builder.accessor(base, target=g.ARRAY_BUFFER, minmax=True),
            NORMAL=builder.accessor(base_n, target=g.ARRAY_BUFFER),
            TEXCOORD_0=builder.accessor(texcoord[idx], target=g.ARRAY_BUFFER))
        attrs.TEXCOORD_1 = builder.accessor(np.ascontiguousarray(pattern[idx]),
                                            target=g.ARRAY_BUFFER)
        t_pos = builder.stacked_accessors(pts - base[None], target=g.ARRAY_BUFFER, minmax=True)
        targets = [{"POSITION": a} for a in t_pos]
        if normals:
            t_nrm = builder.stacked_accessors(nrm - base_n[None], target=g.ARRAY_BUFFER)
            for t, b in zip(targets, t_nrm, strict=True):
                t["NORMAL"] = b
        primitives.append(g.Primitive(
            attributes=attrs, material=materials[i], mode=g.TRIANGLES, targets=targets,
            indices=builder.accessor(tri.astype(np.uint32).reshape(-1),
                                     target=g.ELEMENT_ARRAY_BUFFER)))
    n = last - first + 1
    extras = {"targetNames": [f"frame{f:04d}" for f in range(first, last + 1)],
              "catwalk": {"garment": garment.name, "chunk": chunk, "chunks": chunks,
                          "first_frame": first, "frames": n, "morph_normals": normals,
                          "panels": panels_meta,
                          "uv": "TEXCOORD_0 = (u / w, -v / h): pattern metres over the "
                                "texture size (1 m without a texture); TEXCOORD_1 = (u, v): "
                                "pattern metres (the rest shape, for the fit map)"}}
    builder.gltf.meshes.append(g.Mesh(name=f"{garment.name}#{chunk}", primitives=primitives,
                                      extras=extras))
    return len(builder.gltf.meshes) - 1


def _channel(builder: GlbBuilder, clip: int, node: int, path: str, times: np.ndarray,
             values: np.ndarray, interpolation: str) -> None:
    anim = builder.gltf.animations[clip]
    anim.samplers.append(g.AnimationSampler(
        input=builder.accessor(np.asarray(times, dtype=np.float32), minmax=True),
        output=builder.accessor(np.ascontiguousarray(values, dtype=np.float32)),
        interpolation=interpolation))
    anim.channels.append(g.AnimationChannel(sampler=len(anim.samplers) - 1,
                                            target=g.AnimationChannelTarget(node=node,
                                                                            path=path)))


def add_garment(builder: GlbBuilder, garment: GarmentFrames, animation: int | None,
                normals: bool = True) -> list[int]:
    """Add ``garment`` as chunk meshes at the scene root; their LINEAR weights and STEP scale
    channels go into clip ``animation`` (None: the clip named ``walk``, made if missing).
    ``normals``: NORMAL morph targets (per-frame lighting in any player; without them — the
    web copy, 40 % of the size — the player computes them). Returns the chunk nodes."""
    garment.check()
    local = np.asarray(garment.positions, dtype=np.float32)
    times = float32_times(garment.times)
    materials, panels_meta = _panel_materials(builder, garment)
    spans = chunk_spans(len(times))
    nodes = []
    for k, span in enumerate(spans):
        mesh = _chunk_mesh(builder, garment, local, span, materials, panels_meta, k,
                           len(spans), normals)
        node = builder.node(g.Node(name=f"{garment.name}#{k}", mesh=mesh), root=True)
        nodes.append(node)
        first, last = span
        n = last - first + 1
        if len(times) > 1:
            clip = _clip(builder, animation)
            _channel(builder, clip, node, "weights", times[first:last + 1],
                     np.eye(n, dtype=np.float32).reshape(-1), "LINEAR")
            if len(spans) > 1:   # shown from its first frame until the next chunk's
                keys, scale = [times[0]], [0.0 if k else 1.0]
                if k:
                    keys.append(times[first])
                    scale.append(1.0)
                if k < len(spans) - 1:
                    keys.append(times[spans[k + 1][0]])
                    scale.append(0.0)
                _channel(builder, clip, node, "scale", np.asarray(keys),
                         np.repeat(np.asarray(scale, np.float32)[:, None], 3, axis=1),
                         "STEP")
    return nodes


#: the body's metadata a try-on's file keeps: where the body model came from and how it was
#: skinned, never the person's measurements or sex (a try-on's file is reachable by its id
#: alone; the body's own .glb keeps them)
SHARED_META = ("source", "skin")


def shared_body(body: Body) -> Body:
    """The body as a try-on's file shows it: its mesh, rig and landmarks, its metadata cut to
    :data:`SHARED_META`."""
    return replace(body, meta={k: v for k, v in body.meta.items() if k in SHARED_META})


def build_tryon(body: Body, motion: Motion | None, garments: list[GarmentFrames], *,
                extras: dict | None = None, normals: bool = True) -> GlbBuilder:
    """The try-on scene in a :class:`GlbBuilder` (not yet written); ``normals``: the
    garments' per-frame NORMAL targets (:func:`add_garment`). The body's measurements stay
    out of it (:func:`shared_body`)."""
    names = [gm.name for gm in garments]
    if len(set(names)) != len(names):
        raise InputError(f"garment names must be unique, got {names}")
    if "body" in names:
        raise InputError("a garment cannot be named 'body'")
    if any("#" in n for n in names):
        raise InputError(f"garment names cannot contain '#' (it numbers the chunks): {names}")
    b = GlbBuilder()
    _, joint_nodes = add_body(b, shared_body(body))
    clip = None
    if motion is not None:
        if body.skeleton is None:
            raise InputError("a motion needs a rigged body")
        if motion.rotations.shape[1] != len(joint_nodes):
            raise InputError(f"the motion has {motion.rotations.shape[1]} joints, the body's "
                             f"skeleton {len(joint_nodes)}")
        clip = add_motion(b, motion, joint_nodes, name=CLIP)
    for gm in garments:   # the clip "walk" is made by the first channel that needs it
        add_garment(b, gm, clip, normals)
    b.gltf.extras = {"catwalk": {"format": FORMAT, "version": VERSION, "garments": names,
                                 **(extras or {})}}
    return b


def write_tryon(path, body: Body, motion: Motion | None, garments: list[GarmentFrames], *,
                extras: dict | None = None, normals: bool = True) -> None:
    """Write the dressed, walking body as one .glb (atomically): the skinned body, its
    skeleton, each garment as chunk meshes, one clip ``walk`` driving all.
    ``extras`` go to the file's top-level ``extras.catwalk``."""
    build_tryon(body, motion, garments, extras=extras, normals=normals).save(path)


def tryon_bytes(body: Body, motion: Motion | None, garments: list[GarmentFrames], *,
                extras: dict | None = None, normals: bool = True) -> bytes:
    """The .glb :func:`write_tryon` writes, as bytes."""
    return build_tryon(body, motion, garments, extras=extras, normals=normals).to_bytes()


# ----------------------------------------------------------------------------- reading

def _channel_of(gltf: Gltf, node: int, channel: str, path: str = "glb"):
    """The sampler animating ``channel`` (e.g. "weights") of ``node``, or None."""
    for ai, anim in enumerate(gltf.animations or []):
        for ch in anim.channels if isinstance(anim.channels, list) else []:
            target = getattr(ch, "target", None)
            if getattr(target, "node", None) == node and getattr(target, "path", None) == channel:
                return anim.samplers[_index(anim.samplers, ch.sampler, path, f"animation {ai}",
                                            "sampler")]
    return None


def _chunk_frames(gltf: Gltf, blob: bytes, mesh: GltfObject, path: str, who: str,
                  counts: list[int]):
    """Per panel: (frames, points, 3) local positions of a chunk mesh (base + each target);
    ``counts``: each panel's points (from the garment's first chunk)."""
    out = []
    if len(mesh.primitives) != len(counts):
        raise InputError(f"{path}: garment {who!r}: chunks have different panel counts")
    targets = mesh.primitives[0].targets
    n = len(targets) if isinstance(targets, list) else 0
    if n == 0:
        raise InputError(f"{path}: garment {who!r} has no morph targets")
    for pi, prim in enumerate(mesh.primitives):
        targets = prim.targets if isinstance(prim.targets, list) else []
        if len(targets) != n:
            raise InputError(f"{path}: garment {who!r}: primitives have different morph "
                             "target counts")
        what = f"garment {who!r} panel {pi}"
        base = _read_accessor(gltf, blob, prim.attributes.POSITION, path, f"{what} POSITION",
                              width=3, kinds="f", count=counts[pi]).astype(np.float64)
        disp = []
        for k, t in enumerate(targets):
            if not isinstance(t, dict) or "POSITION" not in t:
                raise InputError(f"{path}: {what}: morph target {k} has no POSITION")
            disp.append(_read_accessor(gltf, blob, t["POSITION"], path,
                                       f"{what} target {k}", width=3, kinds="f",
                                       count=counts[pi]))
        frames = base[None] + np.stack(disp)
        if not np.isfinite(frames).all():
            raise InputError(f"{path}: {what}: positions must be finite")
        out.append(frames)
    return out


def _panels(gltf: Gltf, blob: bytes, mesh: GltfObject, path: str, who: str):
    """Triangles, pattern coordinates, panel index, textures, colours, names and point counts
    of a chunk mesh's primitives (the same in every chunk of a garment)."""
    meta = _catwalk_extras(mesh, path, f"garment {who!r}")
    panels = meta.get("panels") or [{} for _ in mesh.primitives]
    if not isinstance(panels, list):
        raise InputError(f"{path}: garment {who!r}: panels must be a list")
    tri_parts, uv_parts, panel_parts, textures, colors, names, counts = [], [], [], [], [], [], []
    offset = 0
    for pi, prim in enumerate(mesh.primitives):
        what = f"garment {who!r} panel {pi}"
        pm = panels[pi] if pi < len(panels) else {}
        if not isinstance(pm, dict):
            raise InputError(f"{path}: {what}: its description must be an object")
        if prim.mode not in (None, g.TRIANGLES):
            raise InputError(f"{path}: {what} is not made of triangles (mode {prim.mode!r})")
        attrs = prim.attributes
        if getattr(attrs, "POSITION", None) is None or prim.indices is None:
            raise InputError(f"{path}: {what} needs POSITION and indices")
        n = gltf.accessors[_index(gltf.accessors, attrs.POSITION, path, f"{what} POSITION",
                                  "accessor")].count
        if not _is_int(n) or n < 3:
            raise InputError(f"{path}: {what}: {n!r} points: not a panel")
        tri = _read_accessor(gltf, blob, prim.indices, path, f"{what} indices", width=1,
                             kinds="iu").astype(np.int64)
        if len(tri) == 0 or len(tri) % 3 or int(tri.max()) >= n:
            raise InputError(f"{path}: {what}: indices must be whole triangles of its {n:,} "
                             "points")
        tri_parts.append(tri.reshape(-1, 3) + offset)
        tex = pm.get("texture")
        size = (1.0, 1.0)
        if tex:
            if not isinstance(tex, dict) or not isinstance(tex.get("image"), str):
                raise InputError(f"{path}: {what}: texture must be {{\"image\", \"size\"}}")
            size = tuple(_numbers(tex.get("size"), 2, path, f"{what} texture size"))
            if min(size) <= 0:
                raise InputError(f"{path}: {what}: texture size must be positive")
        pattern = getattr(attrs, "TEXCOORD_1", None)
        if pattern is not None:
            uv = _read_accessor(gltf, blob, pattern, path, f"{what} TEXCOORD_1", width=2,
                                kinds="f", count=n).astype(np.float64)
        else:
            if getattr(attrs, "TEXCOORD_0", None) is None:
                raise InputError(f"{path}: {what} has neither TEXCOORD_1 nor TEXCOORD_0")
            tc = _read_accessor(gltf, blob, attrs.TEXCOORD_0, path, f"{what} TEXCOORD_0",
                                width=2, kinds="f", count=n).astype(np.float64)
            uv = np.stack([tc[:, 0] * size[0], -tc[:, 1] * size[1]], axis=1)
        if not np.isfinite(uv).all():
            raise InputError(f"{path}: {what}: texture coordinates must be finite")
        uv_parts.append(uv)
        panel_parts.append(np.full(n, pi, dtype=np.int32))
        textures.append(None if not tex else (tex["image"], size))
        color = pm.get("color", (0.7, 0.7, 0.7, 1.0))
        if not isinstance(color, (list, tuple)) or len(color) not in (3, 4):
            raise InputError(f"{path}: {what}: colour must be RGB(A) in 0..1")
        color = _numbers(color, len(color), path, f"{what} colour")
        if not all(0.0 <= c <= 1.0 for c in color):
            raise InputError(f"{path}: {what}: colour must be RGB(A) in 0..1")
        colors.append(tuple(color))
        name = pm.get("name", f"panel{pi}")
        names.append(name if isinstance(name, str) else f"panel{pi}")
        counts.append(n)
        offset += n
    return (np.concatenate(tri_parts), np.concatenate(uv_parts),
            np.concatenate(panel_parts), textures, colors, names, counts)


@_quiet
def read_garments(path, *, label: str | None = None) -> list[GarmentFrames]:
    """The garments of a try-on .glb written by :func:`write_tryon`: each chunk's base +
    its targets, the chunks' frames joined. Points come back grouped by panel (in the order
    written); textures name the image file as it was written (the image itself is embedded
    in the .glb). ``label`` names bytes in messages."""
    gltf, blob = load_glb(path, label or "try-on")
    path = label or source_name(path, "try-on")
    top = _catwalk_extras(gltf, path, "the file's")
    if top.get("format") == FORMAT and top.get("version") != VERSION:
        raise InputError(f"{path}: try-on format version {top.get('version')!r}; this catwalk "
                         f"reads version {VERSION} (make the try-on again)")
    chunks: dict[str, list] = {}
    for ni, node in enumerate(gltf.nodes):
        if node.mesh is None:
            continue
        mi = _index(gltf.meshes, node.mesh, path, f"node {ni}", "mesh")
        meta = _catwalk_extras(gltf.meshes[mi], path, f"mesh {mi}")
        if "garment" in meta:
            who, chunk = meta["garment"], meta.get("chunk", 0)
            if not isinstance(who, str) or not who or not _is_int(chunk):
                raise InputError(f"{path}: mesh {mi}: a garment chunk needs a garment name "
                                 "and a chunk number")
            if not isinstance(gltf.meshes[mi].primitives, list) or \
                    not gltf.meshes[mi].primitives:
                raise InputError(f"{path}: mesh {mi} (garment {who!r}) has no primitives")
            chunks.setdefault(who, []).append((int(chunk), ni, mi))
    out = []
    for name, found in chunks.items():
        found.sort()
        tri, uv, panel, textures, colors, names, counts = _panels(
            gltf, blob, gltf.meshes[found[0][2]], path, name)
        frames: dict[int, np.ndarray] = {}
        times: dict[int, float] = {}
        for _, ni, mi in found:
            mesh = gltf.meshes[mi]
            first = _catwalk_extras(mesh, path, f"mesh {mi}").get("first_frame", 0)
            if not _is_int(first) or first < 0:
                raise InputError(f"{path}: mesh {mi}: first_frame {first!r} is not a frame")
            local = np.concatenate(_chunk_frames(gltf, blob, mesh, path, name, counts), axis=1)
            sampler = _channel_of(gltf, ni, "weights", path)
            t = (np.zeros(1) if sampler is None else
                 _read_accessor(gltf, blob, sampler.input, path, f"garment {name!r} times",
                                width=1, kinds="f").astype(np.float64))
            if len(t) != len(local):
                raise InputError(f"{path}: garment {name!r}: {len(local)} frames but "
                                 f"{len(t)} keys")
            if not np.isfinite(t).all() or t.min() < 0 or np.any(np.diff(t) <= 0):
                raise InputError(f"{path}: garment {name!r}: frame times must be finite, ≥ 0 "
                                 "and increasing")
            for j in range(len(local)):
                frames[first + j] = local[j]
                times[first + j] = float(t[j])
        order = sorted(frames)
        if order != list(range(len(order))):
            raise InputError(f"{path}: garment {name!r}: its chunks leave frames out")
        ts = np.array([times[i] for i in order])
        if np.any(np.diff(ts) <= 0):
            raise InputError(f"{path}: garment {name!r}: frame times must be increasing")
        out.append(GarmentFrames(name=name, triangles=tri, uv=uv, panel=panel,
                                 panel_names=names, textures=textures, colors=colors,
                                 times=ts, positions=np.stack([frames[i] for i in order])))
    return out


def embedded_images(path, *, label: str | None = None) -> dict[int, np.ndarray]:
    """Decoded embedded images of a .glb, by image index, as float RGB(A) arrays in 0..1
    (at most :data:`~catwalk.exchange.gltf.MAX_IMAGE_PIXELS` pixels each)."""
    gltf, blob = load_glb(path, label or "try-on")
    path = label or source_name(path, "try-on")
    out = {}
    for i, im in enumerate(gltf.images or []):
        if im.bufferView is None:
            continue
        bv = _index(gltf.bufferViews, im.bufferView, path, f"image {i}", "bufferView")
        view = gltf.bufferViews[bv]
        start, length = view.byteOffset or 0, view.byteLength
        if not (_is_int(start) and _is_int(length) and start >= 0 and length >= 0
                and start + length <= len(blob)):
            raise InputError(f"{path}: image {i}: bufferView {bv} does not lie inside the "
                             "binary chunk")
        data = blob[start:start + length]
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error", Image.DecompressionBombWarning)
                pic = Image.open(io.BytesIO(data))
                w, h = pic.size
                if w * h > MAX_IMAGE_PIXELS:
                    raise InputError(f"{path}: image {i} is {w}×{h} pixels; at most "
                                     f"{MAX_IMAGE_PIXELS:,} are read")
                pic = pic.convert("RGBA")
        except InputError:
            raise
        except Exception as exc:   # PIL raises several kinds on bad data
            raise InputError(f"{path}: image {i} cannot be decoded ({exc})") from None
        out[i] = np.asarray(pic, dtype=np.float64) / 255.0
    return out


def panel_texture_images(path, *, label: str | None = None) -> dict[str, list[int | None]]:
    """Per garment (by name), per panel: the index of the embedded image its material uses
    as base colour, or None."""
    gltf, _ = load_glb(path, label or "try-on")
    path = label or source_name(path, "try-on")
    out = {}
    for ni, node in enumerate(gltf.nodes):
        if node.mesh is None:
            continue
        mesh = gltf.meshes[_index(gltf.meshes, node.mesh, path, f"node {ni}", "mesh")]
        meta = _catwalk_extras(mesh, path, f"node {ni} mesh")
        who = meta.get("garment")
        if not isinstance(who, str) or who in out:
            continue
        idx = []
        for pi, prim in enumerate(mesh.primitives if isinstance(mesh.primitives, list) else []):
            im = None
            if prim.material is not None:
                what = f"garment {who!r} panel {pi}"
                mat = gltf.materials[_index(gltf.materials, prim.material, path, what,
                                            "material")]
                pbr = mat.pbrMetallicRoughness
                tex = getattr(pbr, "baseColorTexture", None) if pbr is not None else None
                if tex is not None:
                    t = gltf.textures[_index(gltf.textures, tex.index, path, what, "texture")]
                    if t.source is not None:
                        im = _index(gltf.images, t.source, path, f"{what} texture", "image")
            idx.append(im)
        out[who] = idx
    return out
