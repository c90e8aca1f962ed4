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

import copy
import functools
import hashlib
import json
import math
import struct
import subprocess
from pathlib import Path

import numpy as np
import pygltflib as g
from scipy.spatial.transform import Rotation

from catwalk.body.types import Body, Motion, Skeleton
from catwalk.config import get_config
from catwalk.errors import InputError
from catwalk.exchange.source import MAX_JSON_BYTES, parse_json, read_source, source_name
from catwalk.fileio import atomic_path
from catwalk.geometry.raster import vertex_normals

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
#
# Every reader checks what it uses before using it: indices into the file's tables, accessor
# types and counts, byte ranges inside the binary chunk, finite numbers, a human size. Bad input
# raises InputError naming the file and the object (mesh, accessor, node, skin, animation).

HUMAN_HEIGHT = (1.0, 2.3)     # metres: how tall a body read from a file may be
MAX_JOINTS = 1024             # joints of one skin
MAX_GLB_BYTES = 1 << 30       # a .glb read (a minute's try-on is ~100 MB)
MAX_IMAGE_PIXELS = 4096 * 4096   # an embedded texture's pixels (decoded as floats)


def _quiet(reader):
    """Run a reader with numpy's floating-point warnings off: it checks every value it returns
    for NaN and infinity itself (a signalling NaN in a float32 accessor, an overflow, would
    otherwise print a warning before the clear error)."""
    @functools.wraps(reader)
    def run(*args, **kwargs):
        with np.errstate(all="ignore"):
            return reader(*args, **kwargs)
    return run


def _is_int(v) -> bool:
    return isinstance(v, (int, np.integer)) and not isinstance(v, bool)


def _is_num(v) -> bool:
    return isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool) \
        and math.isfinite(float(v))


def _index(items, i, path: str, what: str, table: str) -> int:
    """``i`` checked as an index into the glTF table ``items`` (``table`` names it)."""
    n = len(items) if isinstance(items, list) else 0
    if not _is_int(i) or not 0 <= i < n:
        raise InputError(f"{path}: {what} refers to {table} {i!r}, which does not exist "
                         f"(the file has {n})")
    return int(i)


def _numbers(v, n: int, path: str, what: str) -> list[float]:
    """A list of ``n`` finite numbers."""
    if not isinstance(v, (list, tuple)) or len(v) != n or not all(_is_num(x) for x in v):
        raise InputError(f"{path}: {what} must be {n} finite numbers, got {v!r:.80}")
    return [float(x) for x in v]


def _read_accessor(gltf: Gltf, blob: bytes, index, path: str = "glb",
                   what: str | None = None, *, width: int | None = None,
                   kinds: str | None = None, count: int | None = None) -> np.ndarray:
    """The data of accessor ``index``: (count,) for scalars, else (count, width). Checked: the
    accessor, its buffer view and their byte ranges lie inside the binary chunk ``blob``; and,
    when given, the ``width`` (components per element), the component ``kinds`` (numpy
    kind letters, e.g. "f" or "iu") and the ``count``."""
    i = _index(gltf.accessors, index, path, what or "a reader", "accessor")
    what = f"{what or 'accessor'} (accessor {i})"
    acc = gltf.accessors[i]
    if acc.sparse is not None:
        raise InputError(f"{path}: {what}: sparse accessors are not read")
    if acc.bufferView is None:
        raise InputError(f"{path}: {what} has no bufferView")
    bv = _index(gltf.bufferViews, acc.bufferView, path, what, "bufferView")
    view = gltf.bufferViews[bv]
    if view.buffer not in (0, None):
        raise InputError(f"{path}: {what}: data outside the GLB's binary chunk (buffer "
                         f"{view.buffer!r}) is not read")
    if not _is_int(acc.componentType) or acc.componentType not in _NUMPY:
        raise InputError(f"{path}: {what}: componentType {acc.componentType!r} is not one "
                         "glTF defines")
    if not isinstance(acc.type, str) or acc.type not in _WIDTH:
        raise InputError(f"{path}: {what}: type {acc.type!r} is not one glTF defines")
    dtype = np.dtype(_NUMPY[acc.componentType])
    w = _WIDTH[acc.type]
    n = acc.count
    if not _is_int(n) or n < 0:
        raise InputError(f"{path}: {what}: count {n!r} is not a count")
    v_off, v_len, a_off = view.byteOffset or 0, view.byteLength, acc.byteOffset or 0
    for name, val in (("byteOffset", v_off), ("byteLength", v_len)):
        if not _is_int(val) or val < 0:
            raise InputError(f"{path}: bufferView {bv}: {name} {val!r} is not a byte count")
    if not _is_int(a_off) or a_off < 0:
        raise InputError(f"{path}: {what}: byteOffset {a_off!r} is not a byte count")
    if v_off + v_len > len(blob):
        raise InputError(f"{path}: bufferView {bv} ends at byte {v_off + v_len:,}, but the "
                         f"binary chunk has {len(blob):,} bytes (truncated or damaged file)")
    elem = dtype.itemsize * w
    stride = view.byteStride or elem
    if not _is_int(stride) or stride < elem:
        raise InputError(f"{path}: bufferView {bv}: byteStride {view.byteStride!r} is less than "
                         f"an element ({elem} bytes)")
    need = a_off + stride * (n - 1) + elem if n else 0
    if need > v_len:
        raise InputError(f"{path}: {what}: {n:,} elements need {need:,} bytes of bufferView "
                         f"{bv}, which has {v_len:,} (truncated or damaged file)")
    if width is not None and w != width:
        raise InputError(f"{path}: {what} has {w} component(s) per element, not {width}")
    if kinds is not None and dtype.kind not in kinds:
        raise InputError(f"{path}: {what} holds {dtype.name} values, not "
                         f"{'integers' if kinds == 'iu' else 'floats'}")
    if count is not None and n != count:
        raise InputError(f"{path}: {what} has {n:,} elements, not {count:,}")
    start = v_off + a_off
    if n == 0:
        arr = np.zeros(0, dtype)
    elif stride == elem:
        arr = np.frombuffer(blob, dtype=dtype, count=n * w, offset=start)
    else:
        raw = np.frombuffer(blob, dtype=np.uint8, count=stride * (n - 1) + elem, offset=start)
        rows = np.lib.stride_tricks.as_strided(raw, shape=(n, elem), strides=(stride, 1))
        arr = np.ascontiguousarray(rows).view(dtype).reshape(-1)
    arr = arr.reshape(n, w) if w > 1 else arr.copy()
    if acc.normalized and dtype.kind in "ui":
        arr = arr.astype(np.float32) / np.iinfo(dtype).max
    return np.array(arr)


# the glTF tables (lists of objects) at the top of a file, and the lists of objects inside them
_TABLES = ("accessors", "animations", "bufferViews", "buffers", "cameras", "images",
           "materials", "meshes", "nodes", "samplers", "scenes", "skins", "textures")
_OBJECT_LISTS = frozenset(("primitives", "channels", "samplers"))
_RAW_OBJECTS = frozenset(("extras", "extensions"))
_DEFAULTS = {"interpolation": "LINEAR"}   # the specification's defaults that readers use


class GltfObject:
    """A glTF JSON object read as attributes, as pygltflib's classes are (``node.mesh``,
    ``prim.attributes.POSITION``, ``mesh.extras``): a missing property is None, objects inside
    are GltfObjects (``extras`` and ``extensions`` stay dicts, morph ``targets`` a list of
    dicts). Values are the file's own, unchecked: the readers check what they use. Reading
    with pygltflib took seconds a megabyte of JSON (a long try-on, a hostile file); this
    costs what ``json.loads`` costs."""

    def __init__(self, data: dict):
        self.__dict__["_data"] = data

    def __getattr__(self, name: str):
        if name.startswith("__"):
            raise AttributeError(name)
        v = self._data.get(name, _DEFAULTS.get(name))
        if isinstance(v, dict) and name not in _RAW_OBJECTS:
            v = GltfObject(v)
        elif isinstance(v, list) and name in _OBJECT_LISTS:
            v = [GltfObject(x if isinstance(x, dict) else {}) for x in v]
        self.__dict__[name] = v   # once: the same objects on every access
        return v

    def __setattr__(self, name, value):
        raise AttributeError("a glTF file read back is not changed")


class Gltf(GltfObject):
    """A .glb's JSON (tables always lists, possibly empty) and its binary chunk."""

    def __init__(self, data: dict, blob: bytes):
        super().__init__(data)
        for table in _TABLES:
            self.__dict__[table] = [GltfObject(x) for x in data.get(table) or []]
        self.__dict__["_blob"] = blob

    def binary_blob(self) -> bytes:
        return self._blob


def load_glb(source, what: str = "glb") -> tuple[Gltf, bytes]:
    """The glTF document (:class:`Gltf`) and binary chunk of a .glb given as a path, bytes or
    a file object (``what`` names bytes in messages)."""
    data, path = read_source(source, what, max_bytes=MAX_GLB_BYTES)
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
    if length < 20:
        raise InputError(f"{path}: damaged GLB: header says {length} bytes")
    (json_len,) = struct.unpack("<I", data[12:16])
    if data[16:20] != b"JSON" or 20 + json_len > length:
        raise InputError(f"{path}: damaged GLB: the first chunk is not a JSON chunk within "
                         "the file")
    if json_len > MAX_JSON_BYTES:   # a glTF's JSON describes; the geometry is in the binary
        raise InputError(f"{path}: its JSON chunk is {json_len:,} bytes; at most "
                         f"{MAX_JSON_BYTES:,} are read")

    key = hashlib.sha1(data).digest()
    if key in _PARSED:   # several readers of one file parse it once
        return _PARSED[key]

    doc = parse_json(data[20:20 + json_len], f"{path}: its JSON chunk")
    if not isinstance(doc, dict):
        raise InputError(f"{path}: its JSON chunk is not a glTF object")
    blob = b""
    at = 20 + json_len
    while at + 8 <= length:   # the first BIN chunk after the JSON; other chunks are skipped
        chunk_len, kind = struct.unpack("<I4s", data[at:at + 8])
        if at + 8 + chunk_len > length:
            raise InputError(f"{path}: truncated GLB: a chunk of {chunk_len:,} bytes at byte "
                             f"{at:,} runs past the end ({length:,} bytes)")
        if kind == b"BIN\0":
            blob = data[at + 8:at + 8 + chunk_len]
            break
        at += 8 + chunk_len
    for table in _TABLES:
        items = doc.get(table)
        if items is not None and (not isinstance(items, list)
                                  or not all(isinstance(x, dict) for x in items)):
            raise InputError(f"{path}: {table} must be a list of objects")
    gltf = Gltf(doc, blob)
    if not gltf.meshes:
        raise InputError(f"{path}: contains no mesh")
    if gltf.buffers:
        claimed = gltf.buffers[0].byteLength
        if not _is_int(claimed) or claimed < 0:
            raise InputError(f"{path}: buffer 0: byteLength {claimed!r} is not a byte count")
        if claimed > len(blob):
            raise InputError(f"{path}: buffer 0 claims {claimed:,} bytes, but the binary chunk "
                             f"has {len(blob):,} (truncated or damaged file)")
    _PARSED[key] = (gltf, blob)
    while len(_PARSED) > 2:
        _PARSED.pop(next(iter(_PARSED)))
    return gltf, blob


# the last files parsed; readers never modify them
_PARSED: dict[bytes, tuple[Gltf, bytes]] = {}


@_quiet
def check_meshes(source, what: str = "glb") -> None:
    """Check a .glb's mesh data before another library parses it (trimesh, for a scan): the
    document (:func:`load_glb`) and, for every primitive, its ``POSITION`` (3 floats) and
    ``indices`` (integers) accessors inside the binary chunk — so a header that claims 4 GB
    or a billion elements is refused before anything is allocated."""
    gltf, blob = load_glb(source, what)
    path = what if isinstance(source, (bytes, bytearray, memoryview)) else str(source)
    for mi, mesh in enumerate(gltf.meshes):
        prims = mesh.primitives
        if not isinstance(prims, list):
            raise InputError(f"{path}: mesh {mi}: primitives must be a list, got {prims!r:.40}")
        for pi, prim in enumerate(prims):
            where = f"mesh {mi} primitive {pi}"
            attrs = prim.attributes
            if not isinstance(attrs, GltfObject):
                raise InputError(f"{path}: {where}: attributes must be an object")
            position = attrs.POSITION
            if position is None:
                raise InputError(f"{path}: {where} has no POSITION")
            _read_accessor(gltf, blob, position, path, f"{where} POSITION", width=3,
                           kinds="f")
            if prim.indices is not None:
                _read_accessor(gltf, blob, prim.indices, path, f"{where} indices", width=1,
                               kinds="iu")


def _node_local(node: GltfObject, path: str = "glb", what: str = "node") -> np.ndarray:
    """A node's local transform, its TRS or matrix checked (finite, a proper rotation)."""
    if node.matrix:
        m = np.asarray(_numbers(node.matrix, 16, path, f"{what} matrix"),
                       dtype=np.float64).reshape(4, 4).T
        if not np.allclose(m[3], (0, 0, 0, 1)) or abs(np.linalg.det(m[:3, :3])) < 1e-12:
            raise InputError(f"{path}: {what} matrix is not an invertible affine transform")
        return m
    m = np.eye(4)
    if node.rotation:
        q = np.asarray(_numbers(node.rotation, 4, path, f"{what} rotation"))
        if np.linalg.norm(q) < 1e-9:
            raise InputError(f"{path}: {what} rotation is not a rotation (zero quaternion)")
        m[:3, :3] = Rotation.from_quat(q).as_matrix()
    if node.scale:
        s = _numbers(node.scale, 3, path, f"{what} scale")
        if min(abs(x) for x in s) < 1e-9:
            raise InputError(f"{path}: {what} scale {s} flattens it (a zero scale)")
        m[:3, :3] = m[:3, :3] @ np.diag(s)
    if node.translation:
        m[:3, 3] = _numbers(node.translation, 3, path, f"{what} translation")
    return m


def _catwalk_extras(obj, path: str, what: str) -> dict:
    """``obj.extras["catwalk"]`` (catwalk's own data), checked to be an object; {} if none."""
    extras = obj.extras if isinstance(getattr(obj, "extras", None), dict) else {}
    cw = extras.get("catwalk", {})
    if cw is None:
        return {}
    if not isinstance(cw, dict):
        raise InputError(f"{path}: {what} extras.catwalk must be an object, got {cw!r:.60}")
    return cw


def _skin_joints(gltf: Gltf, skin_index, path: str, what: str) -> tuple[int, list[int]]:
    """(skin index, its joint nodes), checked."""
    si = _index(gltf.skins, skin_index, path, what, "skin")
    joints = gltf.skins[si].joints
    if not isinstance(joints, list) or not joints:
        raise InputError(f"{path}: skin {si} has no joints")
    if len(joints) > MAX_JOINTS:
        raise InputError(f"{path}: skin {si} has {len(joints):,} joints; at most "
                         f"{MAX_JOINTS:,} are read")
    joints = [_index(gltf.nodes, n, path, f"skin {si} joint {k}", "node")
              for k, n in enumerate(joints)]
    if len(set(joints)) != len(joints):
        raise InputError(f"{path}: skin {si} lists a joint node twice")
    return si, joints


def _skinned_node(gltf: Gltf) -> int | None:
    """The node :func:`read_body` reads: the first with a mesh and a skin, else with a mesh."""
    nodes = gltf.nodes
    with_mesh = [i for i, n in enumerate(nodes) if n.mesh is not None]
    return next((i for i in with_mesh if nodes[i].skin is not None),
                with_mesh[0] if with_mesh else None)


@_quiet
def read_body(source, *, label: str | None = None) -> Body:
    """Read a body written by :func:`write_glb` (or any glb with one skinned mesh) from a path,
    bytes or a file object (``label`` names it in messages). glTF is in metres: a body must be
    :data:`HUMAN_HEIGHT` tall."""
    gltf, blob = load_glb(source, label or "body")
    path = label or source_name(source, "body")
    nodes = gltf.nodes
    mesh_node = _skinned_node(gltf)
    if mesh_node is None:
        raise InputError(f"{path}: no node shows a mesh")
    node = nodes[mesh_node]
    mi = _index(gltf.meshes, node.mesh, path, f"node {mesh_node}", "mesh")
    mesh = gltf.meshes[mi]
    if not isinstance(mesh.primitives, list) or not mesh.primitives:
        raise InputError(f"{path}: mesh {mi} has no primitives")
    prim = mesh.primitives[0]
    if prim.mode not in (None, g.TRIANGLES):
        raise InputError(f"{path}: mesh {mi} is not made of triangles (mode {prim.mode!r})")
    attrs = prim.attributes
    if getattr(attrs, "POSITION", None) is None:
        raise InputError(f"{path}: mesh {mi} has no POSITION")
    v = _read_accessor(gltf, blob, attrs.POSITION, path, f"mesh {mi} POSITION", width=3,
                       kinds="f").astype(np.float64)
    if len(v) < 3:
        raise InputError(f"{path}: mesh {mi} has {len(v)} vertices: not a body")
    bad = int(np.count_nonzero(~np.isfinite(v).all(axis=1)))
    if bad:
        raise InputError(f"{path}: {bad:,} body vertices have NaN or infinite coordinates")
    if prim.indices is None:
        if len(v) % 3:
            raise InputError(f"{path}: mesh {mi} has no indices and {len(v):,} vertices, not a "
                             "whole number of triangles")
        faces = np.arange(len(v), dtype=np.int32).reshape(-1, 3)
    else:
        idx = _read_accessor(gltf, blob, prim.indices, path, f"mesh {mi} indices", width=1,
                             kinds="iu")
        if len(idx) == 0 or len(idx) % 3:
            raise InputError(f"{path}: mesh {mi} has {len(idx):,} indices, not a whole number "
                             "of triangles")
        if int(idx.max()) >= len(v):
            raise InputError(f"{path}: mesh {mi}: a triangle refers to vertex {int(idx.max()):,}"
                             f", but there are {len(v):,}")
        faces = idx.astype(np.int32).reshape(-1, 3)
    used = v[np.unique(faces)]
    height = float(np.ptp(used[:, 1]))
    if not HUMAN_HEIGHT[0] <= height <= HUMAN_HEIGHT[1]:
        raise InputError(f"{path}: the body is {height:.4g} m tall: not a human size (glTF "
                         f"files are in metres; a body is {HUMAN_HEIGHT[0]}–"
                         f"{HUMAN_HEIGHT[1]} m tall)")
    parts = getattr(attrs, "_PART", None)
    if parts is not None:
        parts = _read_accessor(gltf, blob, parts, path, f"mesh {mi} _PART", width=1,
                               count=len(v)).astype(np.float64)
        if not np.isfinite(parts).all() or parts.min() < -0.5 or parts.max() > 4.5:
            raise InputError(f"{path}: mesh {mi} _PART: body parts are 0–4 (torso, arms, legs)")
        parts = np.rint(parts).astype(np.int8)
    cw = _catwalk_extras(mesh, path, f"mesh {mi}")
    landmarks = cw.get("landmarks", {})
    if not isinstance(landmarks, dict):
        raise InputError(f"{path}: mesh {mi} landmarks must be an object of name: [x, y, z]")
    landmarks = {str(k): _numbers(p, 3, path, f"landmark {k!r}") for k, p in landmarks.items()}
    meta = cw.get("meta", {})
    if not isinstance(meta, dict):
        raise InputError(f"{path}: mesh {mi} meta must be an object, got {meta!r:.60}")
    body = Body(vertices=v, faces=faces, parts=parts, landmarks=landmarks,
                meta=copy.deepcopy(meta))   # the parsed file is cached: callers get a copy
    if node.skin is not None:
        si, joints = _skin_joints(gltf, node.skin, path, f"node {mesh_node}")
        pos = {n: j for j, n in enumerate(joints)}
        parents = np.full(len(joints), -1, dtype=np.int32)
        for j, n in enumerate(joints):
            children = nodes[n].children or []
            if not isinstance(children, list):
                raise InputError(f"{path}: node {n} children must be a list")
            for c in children:
                if _is_int(c) and c in pos:
                    parents[pos[c]] = j
        if not all(parents[j] < j for j in range(len(joints))):
            raise InputError(f"{path}: skin joints are not ordered parents-first")
        rest_local = np.stack([_node_local(nodes[n], path, f"node {n}") for n in joints])
        names = [nodes[n].name if isinstance(nodes[n].name, str) and nodes[n].name
                 else f"joint{j}" for j, n in enumerate(joints)]
        skeleton = Skeleton(names=names, parents=parents, rest_local=rest_local)
        world = skeleton.rest_world
        if not np.isfinite(world).all() or np.any(np.abs(np.linalg.det(world[:, :3, :3]))
                                                  < 1e-12):
            raise InputError(f"{path}: skin {si}: a joint's rest transform is not invertible")
        for key in ("JOINTS_0", "WEIGHTS_0"):
            if getattr(attrs, key, None) is None:
                raise InputError(f"{path}: mesh {mi} is skinned but has no {key}")
        sj = _read_accessor(gltf, blob, attrs.JOINTS_0, path, f"mesh {mi} JOINTS_0", width=4,
                            kinds="iu", count=len(v))
        if int(sj.max()) >= len(joints):
            raise InputError(f"{path}: mesh {mi} JOINTS_0 refers to joint {int(sj.max())}, but "
                             f"skin {si} has {len(joints)}")
        sw = _read_accessor(gltf, blob, attrs.WEIGHTS_0, path, f"mesh {mi} WEIGHTS_0", width=4,
                            count=len(v)).astype(np.float32)
        if not np.isfinite(sw).all() or sw.min() < 0 or np.any(sw.sum(axis=1) <= 0):
            raise InputError(f"{path}: mesh {mi} WEIGHTS_0: skin weights must be finite, ≥ 0 "
                             "and not all zero for a vertex")
        body.skeleton = skeleton
        body.skin_joints = sj.astype(np.uint16)
        body.skin_weights = sw
    return body


@_quiet
def read_motion(source, name: str | None = None, *, label: str | None = None) -> Motion | None:
    """The joint animation of a file written by :func:`write_glb`, at its stored frames
    (``label`` names bytes in messages)."""
    gltf, blob = load_glb(source, label or "glb")
    path = label or source_name(source, "glb")
    if not gltf.animations:
        return None
    anim = next((a for a in gltf.animations if name is None or a.name == name), None)
    if anim is None:
        return None
    mesh_node = _skinned_node(gltf)
    if mesh_node is None or gltf.nodes[mesh_node].skin is None:
        return None
    _, joints = _skin_joints(gltf, gltf.nodes[mesh_node].skin, path, f"node {mesh_node}")
    pos = {n: j for j, n in enumerate(joints)}
    ai = gltf.animations.index(anim)
    cw = _catwalk_extras(anim, path, f"animation {ai}")
    fps = cw.get("fps", 30.0)
    if not _is_num(fps) or not 0 < fps <= 1000:
        raise InputError(f"{path}: animation {ai}: fps {fps!r} is not a frame rate")
    fps = float(fps)
    meta = cw.get("meta", {})
    if not isinstance(meta, dict):
        raise InputError(f"{path}: animation {ai}: meta must be an object")
    if not isinstance(anim.channels, list) or not isinstance(anim.samplers, list):
        raise InputError(f"{path}: animation {ai}: channels and samplers must be lists")
    times = rot = trans = None
    frames = 0
    for k, ch in enumerate(anim.channels):
        target = getattr(ch, "target", None)
        node = getattr(target, "node", None)
        if not _is_int(node) or node not in pos or target.path not in ("rotation",
                                                                      "translation"):
            continue
        where = f"animation {ai} channel {k}"
        s = anim.samplers[_index(anim.samplers, ch.sampler, path, where, "sampler")]
        t = _read_accessor(gltf, blob, s.input, path, f"{where} times", width=1, kinds="f")
        if times is None:
            if len(t) == 0 or not np.isfinite(t).all():
                raise InputError(f"{path}: {where}: key times must be finite, at least one")
            times, frames = t, len(t)
            rot = np.stack([np.tile(_trs(_node_local(gltf.nodes[n], path, f"node {n}"))[1],
                                    (frames, 1)) for n in joints], axis=1)
            trans = np.stack([np.tile(_node_local(gltf.nodes[n], path, f"node {n}")[:3, 3],
                                      (frames, 1)) for n in joints], axis=1)
        elif len(t) != frames:
            raise InputError(f"{path}: {where} has {len(t)} keys, the first channel {frames}")
        width = 4 if target.path == "rotation" else 3
        out = _read_accessor(gltf, blob, s.output, path, f"{where} values", width=width,
                             kinds="f", count=frames).astype(np.float64)
        if not np.isfinite(out).all():
            raise InputError(f"{path}: {where}: values must be finite")
        j = pos[node]
        if target.path == "rotation":
            norm = np.linalg.norm(out, axis=1, keepdims=True)
            if np.any(norm < 1e-9):
                raise InputError(f"{path}: {where}: a rotation key is a zero quaternion")
            rot[:, j] = out / norm
        else:
            trans[:, j] = out
    if times is None:
        return None
    return Motion(fps=fps, rotations=rot, translations=trans, loop=bool(cw.get("loop", True)),
                  meta=copy.deepcopy(meta))


def validate(paths: list[str | Path]) -> list[dict]:
    """Run the Khronos glTF validator (npm gltf-validator, in tools/node) on files."""
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
