"""glTF 2.0 binary (.glb) writing and reading for bodies, their animation and garments.

A body is written as one skinned mesh (POSITION, NORMAL, JOINTS_0, WEIGHTS_0 and the
application attribute ``_PART``: the body part per vertex) at the scene root, its skeleton as a
separate node tree (joint nodes carry the rest transforms; the skin's inverse bind matrices are
the inverses of the rest world matrices), and, when a motion is given, one animation clip
``walk`` with a LINEAR rotation channel per joint and translation channels for the joints whose
translation moves. Landmarks and metadata go to ``mesh.extras`` under ``catwalk``.

:class:`GlbBuilder` is the one place that packs numpy arrays into buffer views and accessors
(4-byte aligned, ``min``/``max`` where the validator wants them); the garment writer builds on it.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pygltflib as g
from scipy.spatial.transform import Rotation

from catwalk.body.types import Body, Motion, Skeleton
from catwalk.errors import InputError
from catwalk.exchange.source import read_source, source_name
from catwalk.fileio import atomic_path
from catwalk.render.raster import vertex_normals

_TYPE_BY_WIDTH = {1: g.SCALAR, 2: g.VEC2, 3: g.VEC3, 4: g.VEC4, 16: g.MAT4}
_COMPONENT = {
    np.dtype(np.float32): g.FLOAT,
    np.dtype(np.uint32): g.UNSIGNED_INT,
    np.dtype(np.uint16): g.UNSIGNED_SHORT,
    np.dtype(np.uint8): g.UNSIGNED_BYTE,
}
_NUMPY = {g.FLOAT: np.float32, g.UNSIGNED_INT: np.uint32, g.UNSIGNED_SHORT: np.uint16,
          g.UNSIGNED_BYTE: np.uint8, g.SHORT: np.int16, g.BYTE: np.int8}
_WIDTH = {g.SCALAR: 1, g.VEC2: 2, g.VEC3: 3, g.VEC4: 4, g.MAT4: 16}


class GlbBuilder:
    """Accumulates one binary blob and the glTF objects that point into it."""

    def __init__(self) -> None:
        self.gltf = g.GLTF2(asset=g.Asset(generator="catwalk", version="2.0"))
        self.gltf.scenes = [g.Scene(nodes=[])]
        self.gltf.scene = 0
        self._blob = bytearray()

    def accessor(self, array: np.ndarray, *, target: int | None = None,
                 minmax: bool = False, normalized: bool = False) -> int:
        a = np.ascontiguousarray(array)
        if a.dtype not in _COMPONENT:
            raise TypeError(f"unsupported dtype {a.dtype}")
        width = 1 if a.ndim == 1 else int(np.prod(a.shape[1:]))
        count = a.shape[0]
        while len(self._blob) % 4:
            self._blob.append(0)
        offset = len(self._blob)
        self._blob.extend(a.tobytes())
        view = g.BufferView(buffer=0, byteOffset=offset, byteLength=a.nbytes, target=target)
        self.gltf.bufferViews.append(view)
        acc = g.Accessor(bufferView=len(self.gltf.bufferViews) - 1,
                         componentType=_COMPONENT[a.dtype], count=count,
                         type=_TYPE_BY_WIDTH[width], normalized=normalized or None)
        if minmax:
            flat = a.reshape(count, width)
            acc.min = [float(x) if a.dtype.kind == "f" else int(x) for x in flat.min(axis=0)]
            acc.max = [float(x) if a.dtype.kind == "f" else int(x) for x in flat.max(axis=0)]
        self.gltf.accessors.append(acc)
        return len(self.gltf.accessors) - 1

    def stacked_accessors(self, arrays: np.ndarray, *, target: int | None = None,
                          minmax: bool = False) -> list[int]:
        """One accessor per ``arrays[k]`` (shape (K, n, w)), all in one buffer view (fewer JSON
        objects than one view each: morph targets). Vertex data gets an explicit byteStride, as
        the spec wants when accessors share a view."""
        a = np.ascontiguousarray(arrays)
        if a.dtype not in _COMPONENT or a.ndim != 3:
            raise TypeError(f"need a (K, n, w) array of a glTF component type, got {a.dtype} "
                            f"{a.shape}")
        k, count, width = a.shape
        while len(self._blob) % 4:
            self._blob.append(0)
        offset = len(self._blob)
        self._blob.extend(a.tobytes())
        stride = a.dtype.itemsize * width
        view = g.BufferView(buffer=0, byteOffset=offset, byteLength=a.nbytes, target=target,
                            byteStride=stride if target == g.ARRAY_BUFFER else None)
        self.gltf.bufferViews.append(view)
        vi = len(self.gltf.bufferViews) - 1
        out = []
        lo = a.min(axis=1) if minmax and count else None
        hi = a.max(axis=1) if minmax and count else None
        for i in range(k):
            acc = g.Accessor(bufferView=vi, byteOffset=i * count * stride,
                             componentType=_COMPONENT[a.dtype], count=count,
                             type=_TYPE_BY_WIDTH[width])
            if lo is not None:
                acc.min = [float(x) for x in lo[i]]
                acc.max = [float(x) for x in hi[i]]
            self.gltf.accessors.append(acc)
            out.append(len(self.gltf.accessors) - 1)
        return out

    def image(self, data: bytes, mime_type: str, name: str | None = None) -> int:
        """Embed an encoded image (PNG or JPEG bytes) in the binary chunk."""
        while len(self._blob) % 4:
            self._blob.append(0)
        offset = len(self._blob)
        self._blob.extend(data)
        self.gltf.bufferViews.append(g.BufferView(buffer=0, byteOffset=offset,
                                                  byteLength=len(data)))
        self.gltf.images.append(g.Image(name=name, mimeType=mime_type,
                                        bufferView=len(self.gltf.bufferViews) - 1))
        return len(self.gltf.images) - 1

    def repeat_texture(self, image: int) -> int:
        """A texture of ``image`` with REPEAT wrapping and trilinear filtering."""
        if not self.gltf.samplers:
            self.gltf.samplers.append(g.Sampler(magFilter=g.LINEAR,
                                                minFilter=g.LINEAR_MIPMAP_LINEAR,
                                                wrapS=g.REPEAT, wrapT=g.REPEAT))
        self.gltf.textures.append(g.Texture(sampler=0, source=image))
        return len(self.gltf.textures) - 1

    def node(self, node: g.Node, root: bool = False) -> int:
        self.gltf.nodes.append(node)
        idx = len(self.gltf.nodes) - 1
        if root:
            self.gltf.scenes[0].nodes.append(idx)
        return idx

    def material(self, name: str, rgba, roughness: float = 0.8) -> int:
        self.gltf.materials.append(g.Material(
            name=name, doubleSided=True,
            pbrMetallicRoughness=g.PbrMetallicRoughness(baseColorFactor=list(rgba),
                                                        metallicFactor=0.0,
                                                        roughnessFactor=roughness)))
        return len(self.gltf.materials) - 1

    def to_bytes(self) -> bytes:
        """The .glb file as bytes (what :meth:`save` writes)."""
        while len(self._blob) % 4:
            self._blob.append(0)
        self.gltf.buffers = [g.Buffer(byteLength=len(self._blob))]
        self.gltf.set_binary_blob(bytes(self._blob))
        return b"".join(self.gltf.save_to_bytes())

    def save(self, path: str | Path) -> None:
        data = self.to_bytes()
        with atomic_path(path) as tmp:
            tmp.write_bytes(data)


def _trs(m: np.ndarray) -> tuple[list[float], list[float]]:
    t = [float(x) for x in m[:3, 3]]
    q = Rotation.from_matrix(m[:3, :3]).as_quat()
    return t, [float(x) for x in q]


def add_skeleton(b: GlbBuilder, skel: Skeleton) -> list[int]:
    """Joint nodes (roots added to the scene); returns their node indices."""
    nodes = []
    for j, name in enumerate(skel.names):
        t, q = _trs(skel.rest_local[j])
        nodes.append(b.node(g.Node(name=name, translation=t, rotation=q, children=[]),
                            root=skel.parents[j] < 0))
    for j, p in enumerate(skel.parents):
        if p >= 0:
            b.gltf.nodes[nodes[p]].children.append(nodes[j])
    for n in nodes:
        if not b.gltf.nodes[n].children:
            b.gltf.nodes[n].children = None
    return nodes


def add_body(b: GlbBuilder, body: Body, name: str = "body") -> tuple[int, list[int]]:
    """The body mesh (skinned when rigged). Returns (mesh node, joint nodes)."""
    v = np.asarray(body.vertices, dtype=np.float32)
    attrs = g.Attributes(
        POSITION=b.accessor(v, target=g.ARRAY_BUFFER, minmax=True),
        NORMAL=b.accessor(vertex_normals(body.vertices, body.faces).astype(np.float32),
                          target=g.ARRAY_BUFFER))
    if body.parts is not None:
        # float32: vertex attributes must be 4-byte aligned, a scalar byte would not be
        attrs._PART = b.accessor(np.asarray(body.parts, dtype=np.float32),
                                 target=g.ARRAY_BUFFER)
    joint_nodes: list[int] = []
    skin_index = None
    if body.skeleton is not None:
        if body.skin_joints is None or body.skin_weights is None:
            raise ValueError("a rigged body needs skin_joints and skin_weights")
        attrs.JOINTS_0 = b.accessor(np.asarray(body.skin_joints, dtype=np.uint16),
                                    target=g.ARRAY_BUFFER)
        w = np.asarray(body.skin_weights, dtype=np.float32)
        w = w / w.sum(axis=1, keepdims=True)
        attrs.WEIGHTS_0 = b.accessor(w.astype(np.float32), target=g.ARRAY_BUFFER)
        joint_nodes = add_skeleton(b, body.skeleton)
        ibm = np.ascontiguousarray(
            np.transpose(body.skeleton.inverse_bind, (0, 2, 1)).reshape(-1, 16), dtype=np.float32)
        b.gltf.skins.append(g.Skin(name=f"{name}-skin", joints=joint_nodes,
                                   skeleton=joint_nodes[0],
                                   inverseBindMatrices=b.accessor(ibm)))
        skin_index = len(b.gltf.skins) - 1
    idx = b.accessor(np.asarray(body.faces, dtype=np.uint32).reshape(-1),
                     target=g.ELEMENT_ARRAY_BUFFER)
    mat = b.material("skin", (0.80, 0.66, 0.58, 1.0), roughness=0.7)
    extras = {"catwalk": {"landmarks": body.landmarks, "meta": body.meta,
                          "parts": "_PART: 0 torso+head, 1 left arm, 2 right arm, 3 left leg, "
                                   "4 right leg"}}
    b.gltf.meshes.append(g.Mesh(name=name, extras=extras, primitives=[
        g.Primitive(attributes=attrs, indices=idx, material=mat, mode=g.TRIANGLES)]))
    node = b.node(g.Node(name=name, mesh=len(b.gltf.meshes) - 1, skin=skin_index), root=True)
    return node, joint_nodes


def continuous_quaternions(q: np.ndarray) -> np.ndarray:
    """Flip signs along axis 0 so consecutive quaternions share a hemisphere."""
    q = np.array(q, dtype=np.float64)
    for f in range(1, q.shape[0]):
        flip = np.sum(q[f] * q[f - 1], axis=-1) < 0
        q[f][flip] *= -1
    return q


def add_motion(b: GlbBuilder, motion: Motion, joint_nodes: list[int], name: str = "walk") -> int:
    frames = motion.frames
    times = (np.arange(frames, dtype=np.float64) / motion.fps).astype(np.float32)
    t_acc = b.accessor(times, minmax=True)
    samplers, channels = [], []
    rot = continuous_quaternions(motion.rotations)
    for j, node in enumerate(joint_nodes):
        q = rot[:, j, :]
        q = (q / np.linalg.norm(q, axis=1, keepdims=True)).astype(np.float32)
        samplers.append(g.AnimationSampler(input=t_acc, output=b.accessor(q),
                                           interpolation="LINEAR"))
        channels.append(g.AnimationChannel(sampler=len(samplers) - 1,
                                           target=g.AnimationChannelTarget(node=node,
                                                                           path="rotation")))
        tr = motion.translations[:, j, :]
        if np.ptp(tr, axis=0).max() > 1e-7:
            out = b.accessor(tr.astype(np.float32))
            samplers.append(g.AnimationSampler(input=t_acc, output=out, interpolation="LINEAR"))
            channels.append(g.AnimationChannel(sampler=len(samplers) - 1,
                                               target=g.AnimationChannelTarget(node=node,
                                                                               path="translation")))
    b.gltf.animations.append(g.Animation(name=name, samplers=samplers, channels=channels,
                                         extras={"catwalk": {"fps": motion.fps, "loop": motion.loop,
                                                             "meta": motion.meta}}))
    return len(b.gltf.animations) - 1


def write_glb(path: str | Path, body: Body, motion: Motion | None = None) -> None:
    """Write a body (skinned when rigged), with its walk when a motion is given."""
    build_glb(body, motion).save(path)


def glb_bytes(body: Body, motion: Motion | None = None) -> bytes:
    """The .glb :func:`write_glb` writes, as bytes."""
    return build_glb(body, motion).to_bytes()


def build_glb(body: Body, motion: Motion | None = None) -> GlbBuilder:
    b = GlbBuilder()
    _, joint_nodes = add_body(b, body)
    if motion is not None:
        if body.skeleton is None:
            raise ValueError("a motion needs a rigged body")
        if motion.rotations.shape[1] != len(joint_nodes):
            raise ValueError("motion and skeleton have different joint counts")
        add_motion(b, motion, joint_nodes)
    return b


# ----------------------------------------------------------------------------- reading

def _read_accessor(gltf: g.GLTF2, blob: bytes, index: int) -> np.ndarray:
    acc = gltf.accessors[index]
    if acc.bufferView is None:
        raise InputError(f"accessor {index} has no bufferView (sparse accessors unsupported)")
    view = gltf.bufferViews[acc.bufferView]
    dtype = np.dtype(_NUMPY[acc.componentType])
    width = _WIDTH[acc.type]
    start = (view.byteOffset or 0) + (acc.byteOffset or 0)
    stride = view.byteStride or dtype.itemsize * width
    if stride == dtype.itemsize * width:
        arr = np.frombuffer(blob, dtype=dtype, count=acc.count * width, offset=start)
    else:
        raw = np.frombuffer(blob, dtype=np.uint8, count=stride * (acc.count - 1)
                            + dtype.itemsize * width, offset=start)
        rows = np.lib.stride_tricks.as_strided(raw, shape=(acc.count, dtype.itemsize * width),
                                               strides=(stride, 1))
        arr = np.ascontiguousarray(rows).view(dtype).reshape(-1)
    arr = arr.reshape(acc.count, width) if width > 1 else arr.copy()
    if acc.normalized and dtype.kind in "ui":
        arr = arr.astype(np.float32) / np.iinfo(dtype).max
    return np.array(arr)


def load_glb(source, what: str = "glb") -> tuple[g.GLTF2, bytes]:
    """The glTF object and binary chunk of a .glb given as a path, bytes or a file object
    (``what`` names bytes in messages)."""
    import struct

    data, path = read_source(source, what)
    if data[:4] != b"glTF":
        raise InputError(f"{path}: not a GLB file (no 'glTF' magic)")
    if len(data) < 20:
        raise InputError(f"{path}: truncated GLB ({len(data)} bytes)")
    version, length = struct.unpack("<II", data[4:12])
    if version != 2:
        raise InputError(f"{path}: GLB version {version}; only glTF 2.0 is read")
    if length > len(data):
        raise InputError(f"{path}: truncated GLB: header says {length:,} bytes, "
                         f"file has {len(data):,}")
    import hashlib

    key = hashlib.sha1(data).digest()
    if key in _PARSED:   # several readers of one file parse it once
        return _PARSED[key]
    try:
        gltf = g.GLTF2.load_from_bytes(data)
        blob = gltf.binary_blob() or b""
    except Exception as exc:  # pygltflib raises many kinds on damaged files
        raise InputError(f"{path}: not a readable glTF/GLB file ({exc})") from exc
    if gltf is None or not gltf.meshes:
        raise InputError(f"{path}: contains no mesh")
    _PARSED[key] = (gltf, blob)
    while len(_PARSED) > 2:
        _PARSED.pop(next(iter(_PARSED)))
    return gltf, blob


# the last files parsed (pygltflib takes ~1 s for a walk's JSON); readers never modify them
_PARSED: dict[bytes, tuple[g.GLTF2, bytes]] = {}


def _node_local(node: g.Node) -> np.ndarray:
    if node.matrix:
        return np.asarray(node.matrix, dtype=np.float64).reshape(4, 4).T
    m = np.eye(4)
    if node.rotation:
        m[:3, :3] = Rotation.from_quat(node.rotation).as_matrix()
    if node.scale:
        m[:3, :3] = m[:3, :3] @ np.diag(node.scale)
    if node.translation:
        m[:3, 3] = node.translation
    return m


def read_body(source) -> Body:
    """Read a body written by :func:`write_glb` (or any glb with one skinned mesh) from a path,
    bytes or a file object."""
    gltf, blob = load_glb(source, "body")
    path = source_name(source, "body")
    mesh_node = next((i for i, n in enumerate(gltf.nodes) if n.mesh is not None
                      and n.skin is not None), None)
    if mesh_node is None:
        mesh_node = next(i for i, n in enumerate(gltf.nodes) if n.mesh is not None)
    node = gltf.nodes[mesh_node]
    mesh = gltf.meshes[node.mesh]
    prim = mesh.primitives[0]
    v = _read_accessor(gltf, blob, prim.attributes.POSITION).astype(np.float64)
    if prim.indices is None:
        faces = np.arange(len(v), dtype=np.int32).reshape(-1, 3)
    else:
        faces = _read_accessor(gltf, blob, prim.indices).astype(np.int32).reshape(-1, 3)
    parts = getattr(prim.attributes, "_PART", None)
    parts = None if parts is None else np.rint(_read_accessor(gltf, blob, parts)).astype(np.int8)
    extras = (mesh.extras or {}).get("catwalk", {})
    body = Body(vertices=v, faces=faces, parts=parts,
                landmarks=extras.get("landmarks", {}), meta=extras.get("meta", {}))
    if node.skin is not None:
        skin = gltf.skins[node.skin]
        joints = list(skin.joints)
        pos = {n: j for j, n in enumerate(joints)}
        parents = np.full(len(joints), -1, dtype=np.int32)
        for j, n in enumerate(joints):
            for c in gltf.nodes[n].children or []:
                if c in pos:
                    parents[pos[c]] = j
        order_ok = all(parents[j] < j for j in range(len(joints)))
        if not order_ok:
            raise InputError(f"{path}: skin joints are not ordered parents-first")
        rest_local = np.stack([_node_local(gltf.nodes[n]) for n in joints])
        body.skeleton = Skeleton(names=[gltf.nodes[n].name or f"joint{j}"
                                        for j, n in enumerate(joints)],
                                 parents=parents, rest_local=rest_local)
        body.skin_joints = _read_accessor(gltf, blob, prim.attributes.JOINTS_0).astype(np.uint16)
        body.skin_weights = _read_accessor(gltf, blob, prim.attributes.WEIGHTS_0).astype(np.float32)
    return body


def read_motion(source, name: str | None = None) -> Motion | None:
    """The joint animation of a file written by :func:`write_glb`, at its stored frames."""
    gltf, blob = load_glb(source)
    if not gltf.animations:
        return None
    anim = next((a for a in gltf.animations if name is None or a.name == name), None)
    if anim is None:
        return None
    mesh_node = next((n for n in gltf.nodes if n.skin is not None), None)
    if mesh_node is None:
        return None
    joints = list(gltf.skins[mesh_node.skin].joints)
    pos = {n: j for j, n in enumerate(joints)}
    fps = float(((anim.extras or {}).get("catwalk") or {}).get("fps", 30.0))
    times = None
    rot = trans = None
    for ch in anim.channels:
        if ch.target.node not in pos:
            continue
        s = anim.samplers[ch.sampler]
        if times is None:
            times = _read_accessor(gltf, blob, s.input)
            frames = len(times)
            rot = np.stack([np.tile(_trs(_node_local(gltf.nodes[n]))[1], (frames, 1))
                            for n in joints], axis=1)
            trans = np.stack([np.tile(_node_local(gltf.nodes[n])[:3, 3], (frames, 1))
                              for n in joints], axis=1)
        out = _read_accessor(gltf, blob, s.output).astype(np.float64)
        j = pos[ch.target.node]
        if ch.target.path == "rotation":
            rot[:, j] = out
        elif ch.target.path == "translation":
            trans[:, j] = out
    if times is None:
        return None
    meta = ((anim.extras or {}).get("catwalk") or {})
    return Motion(fps=fps, rotations=rot, translations=trans, loop=bool(meta.get("loop", True)),
                  meta=meta.get("meta", {}))


def validate(paths: list[str | Path]) -> list[dict]:
    """Run the Khronos glTF validator (npm gltf-validator, in tools/node) on files."""
    import subprocess

    from catwalk.config import get_config

    tools = get_config().node_tools_dir
    script = tools / "validate.mjs"
    if not (tools / "node_modules" / "gltf-validator").is_dir():
        raise RuntimeError("gltf-validator is not installed: run `make install`")
    files = [str(Path(p).resolve()) for p in paths]   # the script runs in tools/node
    res = subprocess.run(["node", str(script), *files], capture_output=True, text=True,
                         cwd=tools)
    if res.returncode != 0:
        raise RuntimeError(f"gltf-validator failed: {res.stderr[-2000:]}")
    return json.loads(res.stdout)
