"""Loading body scans (OBJ, PLY, STL, GLB) into SI glTF axes.

:func:`load_scan` reads a triangle mesh with trimesh, checks it (readable, finite, not
degenerate, a human size, at most :data:`MAX_FACES` faces), then finds

- the unit: the one of m, dm, cm, mm that makes the body 1.0–2.3 m tall (MakeHuman's OBJ is in
  decimetres); a GLB is always metres (glTF's unit), so one that is not 1.0–2.3 m is refused;
- the up axis: the axis of largest extent (if a second axis is nearly as long, as in a T-pose,
  the one whose end shows two feet wins); its sign: the end whose sections near it (4, 8, 12 %)
  show two loops of a kind side by side (feet, shins; not hair around a head or eyes inside
  it) is down; if neither end does, the end farther from the surface's area centroid is down
  (a body has more surface above mid-height);
- the facing direction: the feet point forwards, so the horizontal offset from the centre of
  the ankle sections (10 % of the height) to the centre of the foot sections (1.5 %) gives
  "forward"; it is snapped to the nearest horizontal axis of the file (scans are axis-aligned;
  the snapped rotation keeps the mesh exact). If the feet give no clear direction the file's
  own convention is kept (+Z forward for a Y-up file, -Y for a Z-up file) and the report says
  it was assumed.

The result is in metres, +Y up, facing +Z (body's left = +X), feet on y = 0, centred on x = z = 0
(bounding box). The conversion is a proper rotation (never a mirror), a scale and a translation;
:attr:`Scan.transform` maps file coordinates to the output.
"""

from __future__ import annotations

import io
import struct
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from catwalk.body.measure.slicing import AREA, CX, CZ, PERIM, XMIN, ZMAX, Slicer
from catwalk.body.measure.topology import mesh_topology
from catwalk.errors import InputError
from catwalk.exchange.gltf import check_meshes
from catwalk.exchange.source import read_source
from catwalk.geometry.mesh import compact, edge_keys
from catwalk.geometry.mesh import components as mesh_components

MAX_FACES = 2_000_000
MAX_VERTICES = 3 * MAX_FACES
MAX_BYTES = 512 << 20          # a scan file (an ASCII STL of MAX_FACES faces is ~500 MB)
MAX_COORDINATE = 1e12          # file units: farther from the origin is no body in any unit
EXTENSIONS = {".obj": "obj", ".ply": "ply", ".stl": "stl", ".glb": "glb"}
UNITS = (("m", 1.0), ("dm", 0.1), ("cm", 0.01), ("mm", 0.001))
HUMAN_HEIGHT = (1.0, 2.3)  # metres
AXES = "XYZ"


@dataclass
class Scan:
    path: str
    vertices: np.ndarray      # (N, 3) float64, metres, glTF axes, feet on y = 0
    faces: np.ndarray         # (M, 3) int32
    units: str                # unit the file was in: m, dm, cm or mm
    scale: float              # file units -> metres
    up: str                   # the file's up axis, e.g. "+Z"
    forward: str              # the file's facing axis, e.g. "-Y"
    forward_detected: bool    # False: no clear facing direction, the file's convention assumed
    transform: np.ndarray     # (4, 4) file coordinates -> output coordinates
    watertight: bool
    holes: int                # boundary loops
    components: int           # connected pieces of surface
    nonmanifold_edges: int
    meta: dict = field(default_factory=dict)

    @property
    def height(self) -> float:
        return float(self.vertices[:, 1].max() - self.vertices[:, 1].min())

    def info(self) -> dict:
        v = self.vertices
        return {
            "file": self.path,
            "format": self.meta.get("format"),
            "vertices": int(len(v)),
            "faces": int(len(self.faces)),
            "units": self.units,
            "scale_to_metres": self.scale,
            "up_axis": self.up,
            "forward_axis": self.forward,
            "forward_detected": self.forward_detected,
            "height_m": round(self.height, 4),
            "bounds_m": [[round(float(a), 4) for a in v.min(axis=0)],
                         [round(float(a), 4) for a in v.max(axis=0)]],
            "watertight": self.watertight,
            "holes": self.holes,
            "components": self.components,
            "nonmanifold_edges": self.nonmanifold_edges,
            "transform": [[round(float(a), 6) for a in row] for row in self.transform],
        }


# ----------------------------------------------------------------------------------------------
# reading


def _precheck(data: bytes, path: str, fmt: str) -> None:
    """Cheap checks before a full parse: empty files and declared face counts."""
    size = len(data)
    if size == 0:
        raise InputError(f"{path}: the file is empty")
    if fmt == "stl":
        head = data[:84]
        if not head.lstrip().lower().startswith(b"solid") and len(head) >= 84:
            (n,) = struct.unpack("<I", head[80:84])
            if size < 84 + 50 * n:
                raise InputError(f"{path}: truncated or not a binary STL: {n:,} triangles "
                                 f"declared, room for {max(0, size - 84) // 50:,}")
            if n > MAX_FACES:
                raise InputError(f"{path}: {n:,} faces; at most {MAX_FACES:,} are accepted")
    elif fmt == "ply":
        head = data[:4096]
        if not head.startswith(b"ply"):
            raise InputError(f"{path}: not a PLY file (no 'ply' magic)")
        for line in head.split(b"\n"):
            parts = line.split()
            if len(parts) >= 2 and parts[0] == b"element":
                try:
                    n = int(parts[2]) if len(parts) == 3 else -1
                except ValueError:
                    n = -1
                if n < 0:
                    raise InputError(f"{path}: bad PLY header line {line[:80]!r}: an element "
                                     "needs a name and a count")
                limit, what = {b"face": (MAX_FACES, "faces"),
                               b"vertex": (MAX_VERTICES, "vertices")}.get(parts[1], (None, ""))
                if limit is not None and n > limit:
                    raise InputError(f"{path}: the header claims {n:,} {what}; at most "
                                     f"{limit:,} are accepted")
            if line.strip() == b"end_header":
                break
    elif fmt == "glb":
        head = data[:12]
        if head[:4] != b"glTF":
            raise InputError(f"{path}: not a GLB file (no 'glTF' magic)")
        if len(head) < 12:
            raise InputError(f"{path}: truncated GLB ({size} bytes)")
        (length,) = struct.unpack("<I", head[8:12])
        if size < length:
            raise InputError(f"{path}: truncated GLB: header says {length:,} bytes, "
                             f"file has {size:,}")

        check_meshes(data, path)


def _read(data: bytes, path: str, fmt: str) -> tuple[np.ndarray, np.ndarray]:
    # trimesh casts what it parses (NaN, overflowing numbers): quietly here, they are
    # reported below as non-finite vertices
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return _read_quietly(data, path, fmt)


def _read_quietly(data: bytes, path: str, fmt: str) -> tuple[np.ndarray, np.ndarray]:
    import trimesh  # deferred: trimesh loads in ≈ 0.4 s; only scan files need it

    try:
        loaded = trimesh.load(io.BytesIO(data), file_type=fmt, force="scene", process=False)
    except InputError:
        raise
    except (UnicodeDecodeError, ModuleNotFoundError):
        raise InputError(f"{path}: not a readable {fmt.upper()} file (binary or garbled "
                         "content where text was expected)") from None
    except Exception as exc:  # trimesh raises many kinds on bad input
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise InputError(f"{path}: cannot read the {fmt.upper()} file "
                         f"(unreadable or truncated): {msg}") from None
    verts, faces = [], []
    offset = 0
    try:
        graph = loaded.graph
        for node in graph.nodes_geometry:
            transform, gname = graph[node]
            geom = loaded.geometry[gname]
            if not isinstance(geom, trimesh.Trimesh):
                continue
            v = np.asarray(geom.vertices, dtype=np.float64)
            f = np.asarray(geom.faces)
            if len(f) == 0:
                continue
            if v.ndim != 2 or v.shape[1] != 3 or f.ndim != 2 or f.shape[1] != 3 \
                    or f.dtype.kind not in "iu":
                raise InputError(f"{path}: cannot read the {fmt.upper()} file: its vertices "
                                 "are not 3D points or its faces not triangles")
            f = f.astype(np.int64)
            T = np.asarray(transform, dtype=np.float64)
            if len(v) and not np.array_equal(T, np.eye(4)):
                v = v @ T[:3, :3].T + T[:3, 3]
            verts.append(v)
            faces.append(f + offset)
            offset += len(v)
    except InputError:
        raise
    except Exception as exc:
        raise InputError(f"{path}: cannot read the {fmt.upper()} file: {exc}") from None
    if not faces or offset == 0 or sum(len(f) for f in faces) == 0:
        raise InputError(f"{path}: no triangles in the file (empty, a point cloud, or "
                         "truncated)")
    return np.concatenate(verts), np.concatenate(faces)


# ----------------------------------------------------------------------------------------------
# checks and topology


def _topology_report(faces: np.ndarray, nverts: int) -> tuple[int, int, int]:
    """(boundary loops, connected components, non-manifold edges)."""
    from scipy.sparse import coo_matrix  # deferred: scipy loads in ≈ 0.3 s; only this path needs it
    from scipy.sparse.csgraph import (
        connected_components,  # deferred: scipy loads in ≈ 0.3 s; only this path needs it
    )  # deferred: scipy loads in ≈ 0.3 s; only this path needs it

    uniq, counts = np.unique(edge_keys(faces, nverts), return_counts=True)
    boundary = uniq[counts == 1]
    nonmanifold = int(np.count_nonzero(counts > 2))
    holes = 0
    if len(boundary):
        a, b = boundary // nverts, boundary % nverts
        g = coo_matrix((np.ones(len(a)), (a, b)), shape=(nverts, nverts))
        ncomp, lab = connected_components(g, directed=False)
        holes = _count_distinct(lab[_used(np.concatenate([a, b]), nverts)])
    _, lab = mesh_components(faces, nverts)
    components = _count_distinct(lab[_used(faces, nverts)])
    return holes, components, nonmanifold


def _used(idx: np.ndarray, n: int) -> np.ndarray:
    """Sorted distinct values of an index array (faster than np.unique for vertex ids)."""
    m = np.zeros(n, bool)
    m[np.asarray(idx).ravel()] = True
    return np.nonzero(m)[0]


def _count_distinct(labels: np.ndarray) -> int:
    return int(np.count_nonzero(np.bincount(labels))) if len(labels) else 0


def _merge_vertices(v: np.ndarray, f: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Weld vertices closer than ``tol`` (grid rounding) and drop faces that collapse."""
    q = np.round((v - v.min(axis=0)) / tol).astype(np.int64)
    size = q.max(axis=0) + 1
    if float(size[0]) * float(size[1]) * float(size[2]) < 2.0**62:
        key = (q[:, 0] * size[1] + q[:, 1]) * size[2] + q[:, 2]  # one int64 per grid cell
        _, first, inv = np.unique(key, return_index=True, return_inverse=True)
    else:
        _, first, inv = np.unique(q, axis=0, return_index=True, return_inverse=True)
    inv = inv.reshape(-1)
    v2 = v[first]
    f2 = inv[f]
    ok = (f2[:, 0] != f2[:, 1]) & (f2[:, 1] != f2[:, 2]) & (f2[:, 2] != f2[:, 0])
    return v2, f2[ok]


# ----------------------------------------------------------------------------------------------
# orientation


def _sections(v, faces, axis, fractions, length, lo):
    """Horizontal-ish sections perpendicular to ``axis`` at the given fractions of the length
    measured from coordinate ``lo``: per level (perimeters, centroids (k, 2), areas, level,
    boxes (k, 4))."""
    topo = mesh_topology(faces, len(v))
    v = topo.extend(v)  # holes are closed by fans (extra vertices) for slicing
    others = [a for a in range(3) if a != axis]
    sl = Slicer(topo, v[:, axis], v[:, others[0]], v[:, others[1]])
    levels = np.sort(lo + np.asarray(fractions) * length)
    sec = sl.slice(levels)
    out = []
    for k in range(len(levels)):
        cs = sec.comps(k)
        out.append((sec.stats[cs, PERIM], sec.stats[cs][:, CX:CZ + 1], sec.stats[cs, AREA],
                    levels[k], sec.stats[cs][:, XMIN:ZMAX + 1]))
    return out


def _feet_score(v, faces, axis, sign):
    """How many of the sections at 4, 8, 12 % from the ``sign`` end show two loops of a kind
    side by side (feet, shins): the two largest loops that are not inside another's box have
    perimeters within a factor 2."""
    lo, hi = v[:, axis].min(), v[:, axis].max()
    length = hi - lo
    fr = np.array([0.04, 0.08, 0.12])
    if sign < 0:  # measured from the top end
        fr = 1.0 - fr
    score = 0
    for per, cen, _a, _lvl, box in _sections(v, faces, axis, fr, length, lo):
        big = np.nonzero(per > 0.03 * length)[0]
        # loops that lie side by side, not one inside another's box (hair around a head,
        # eyes inside it, tights around a leg do not count)
        big = big[np.argsort(-per[big])]
        top = []
        for i in big:
            if not any(box[j, 0] <= cen[i, 0] <= box[j, 1] and box[j, 2] <= cen[i, 1] <= box[j, 3]
                       for j in top):
                top.append(i)
        if len(top) >= 2 and per[top[1]] >= 0.5 * per[top[0]]:  # two of a kind: feet, shins
            score += 1
    return score


def _detect_up(v, faces) -> tuple[int, int]:
    """(axis, sign) of the file's up direction."""
    ext = v.max(axis=0) - v.min(axis=0)
    order = np.argsort(-ext)
    cands = [int(order[0])]
    if ext[order[1]] > 0.9 * ext[order[0]]:
        cands.append(int(order[1]))
    best = None
    for ax in cands:
        up_feet = _feet_score(v, faces, ax, +1)    # feet at the low end => up is +
        down_feet = _feet_score(v, faces, ax, -1)  # feet at the high end => up is -
        score, sign = (up_feet, 1) if up_feet >= down_feet else (down_feet, -1)
        margin = abs(up_feet - down_feet)
        if best is None or (margin, score) > (best[2], best[3]):
            best = (ax, sign, margin, score)
    ax, sign, margin, _ = best
    if margin == 0:
        # no feet found at either end: the surface's area centroid lies above mid-height
        tri = v[faces]
        area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
        c = (tri.mean(axis=1) * area[:, None]).sum(axis=0) / max(area.sum(), 1e-30)
        mid = 0.5 * (v[:, ax].min() + v[:, ax].max())
        sign = 1 if c[ax] >= mid else -1
    return ax, sign


def _rotation(up_axis, up_sign, fwd_axis, fwd_sign) -> np.ndarray:
    """Proper rotation taking file axes to glTF axes: up -> +Y, forward -> +Z."""
    up = np.zeros(3)
    up[up_axis] = up_sign
    fwd = np.zeros(3)
    fwd[fwd_axis] = fwd_sign
    left = np.cross(up, fwd)  # becomes +X
    return np.stack([left, up, fwd])  # rows: new x, y, z in file coordinates


def _detect_forward(v, faces, up_axis, up_sign):
    """The file axis the body faces, from the feet (foot sections lie in front of the ankles)."""
    others = [a for a in range(3) if a != up_axis]
    lo, hi = v[:, up_axis].min(), v[:, up_axis].max()
    length = hi - lo
    fr = np.array([0.015, 0.10]) if up_sign > 0 else np.array([0.985, 0.90])
    secs = _sections(v, faces, up_axis, fr, length, lo)
    # _sections sorts levels ascending; map back to (foot, ankle)
    by_level = {round(float(s[3]), 9): s for s in secs}
    foot_lvl = round(float(np.sort(lo + fr * length)[0 if up_sign > 0 else 1]), 9)
    ankle_lvl = round(float(np.sort(lo + fr * length)[1 if up_sign > 0 else 0]), 9)
    foot, ankle = by_level.get(foot_lvl), by_level.get(ankle_lvl)

    def centre(sec):
        per, cen, area, _, _ = sec
        if not len(per):
            return None
        big = per > 0.03 * length
        if not big.any():
            return None
        w = area[big] + 1e-12
        return (cen[big] * w[:, None]).sum(axis=0) / w.sum()

    cf, ca = (centre(foot), centre(ankle)) if foot and ankle else (None, None)
    if cf is not None and ca is not None:
        d = cf - ca
        if np.hypot(*d) > 0.01 * length:
            i = int(np.argmax(np.abs(d)))
            return others[i], (1 if d[i] > 0 else -1), True
    # the file's own convention: a Y-up file faces +Z, a Z-up file faces -Y, an X-up file +Z
    if up_axis == 1:
        return 2, 1, False
    if up_axis == 2:
        return 1, -up_sign, False
    return 2, 1, False


# ----------------------------------------------------------------------------------------------
# the loader


def sniff_format(data: bytes) -> str | None:
    """The scan format the bytes look like (glb, ply, stl, obj), or None."""
    head = data[:512]
    if head[:4] == b"glTF":
        return "glb"
    if head[:3] == b"ply":
        return "ply"
    text = head.lstrip()
    if text[:5].lower() == b"solid" and b"facet" in data[:4096]:
        return "stl"
    if any(line.split()[:1] in ([b"v"], [b"f"], [b"o"], [b"g"], [b"mtllib"], [b"vn"], [b"vt"])
           for line in text.splitlines() if not line.startswith(b"#")):
        return "obj"
    if len(data) >= 84:   # binary STL: 80-byte header, triangle count, 50 bytes a triangle
        (n,) = struct.unpack("<I", data[80:84])
        if len(data) == 84 + 50 * n:
            return "stl"
    return None


def scan_format(source, data: bytes, name: str, format: str | None = None) -> str:
    """The format of a scan: ``format`` if given, else the file name's extension, else what
    the bytes look like. Raises :class:`InputError` when none of them is a scan format."""
    if format is not None:
        fmt = format.lower().lstrip(".")
        if fmt not in EXTENSIONS.values():
            raise InputError(f"{name}: unsupported scan format {format!r}; use obj, ply, stl "
                             "or glb", "format")
        return fmt
    suffix = Path(name).suffix.lower()
    if suffix in EXTENSIONS:
        return EXTENSIONS[suffix]
    if isinstance(source, (str, Path)) or suffix:
        raise InputError(f"{name}: unsupported file type {suffix or '(none)'!r}; use .obj, "
                         ".ply, .stl or .glb")
    fmt = sniff_format(data)
    if fmt is None:
        raise InputError(f"{name}: not a scan in a format catwalk reads (OBJ, PLY, STL, GLB)")
    return fmt


def load_scan(source, *, format: str | None = None, name: str | None = None) -> Scan:
    """Read a body scan (OBJ, PLY, STL, GLB) and bring it to metres, glTF axes, feet on y = 0.
    ``source``: a path, bytes or a binary file object; ``format``: the format when neither
    a file name nor the bytes tell it; ``name``: how messages name the scan."""
    if isinstance(source, (str, Path)):
        suffix = Path(source).suffix.lower()
        if format is None and suffix not in EXTENSIONS:
            raise InputError(f"{source}: unsupported file type {suffix or '(none)'!r}; "
                             "use .obj, .ply, .stl or .glb")
    data, path = read_source(source, "scan", max_bytes=MAX_BYTES)
    fmt = scan_format(source, data, path, format)
    path = name or path
    _precheck(data, path, fmt)
    v, f = _read(data, path, fmt)
    if len(f) > MAX_FACES:
        raise InputError(f"{path}: {len(f):,} faces; at most {MAX_FACES:,} are accepted")
    if f.min() < 0 or f.max() >= len(v):
        raise InputError(f"{path}: a face refers to a vertex that does not exist "
                         "(truncated or corrupt file)")
    if len(v) > MAX_VERTICES:
        raise InputError(f"{path}: {len(v):,} vertices; at most {MAX_VERTICES:,} are accepted")
    if not np.isfinite(v).all():
        bad = int(np.count_nonzero(~np.isfinite(v).all(axis=1)))
        raise InputError(f"{path}: {bad:,} vertices have NaN or infinite coordinates")
    far = float(np.abs(v).max())
    if far > MAX_COORDINATE:
        raise InputError(f"{path}: a coordinate is {far:.3g} file units from the origin: not a "
                         "body in any unit")
    used = _used(f, len(v))
    vu = v[used]
    ext = vu.max(axis=0) - vu.min(axis=0)
    if ext.max() <= 0 or ext.min() <= 1e-9 * max(ext.max(), 1e-300):
        raise InputError(f"{path}: degenerate geometry: zero extent along "
                         f"{AXES[int(np.argmin(ext))]} (flat or a single point)")
    tri = v[f]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    tiny = area <= 1e-12 * ext.max() ** 2
    if np.count_nonzero(tiny) > 0.5 * len(f):
        raise InputError(f"{path}: degenerate geometry: {np.count_nonzero(tiny):,} of "
                         f"{len(f):,} faces have zero area")
    # units from a plausible human height; glTF is in metres (its specification says so)
    height_file = float(ext.max())
    if fmt == "glb":
        if not HUMAN_HEIGHT[0] <= height_file <= HUMAN_HEIGHT[1]:
            raise InputError(
                f"{path}: not a human size: the largest extent is {height_file:.6g} m (glTF "
                f"files are in metres; a body is {HUMAN_HEIGHT[0]}–{HUMAN_HEIGHT[1]} m tall)")
    unit = None
    for name, s in UNITS[:1] if fmt == "glb" else UNITS:
        if HUMAN_HEIGHT[0] <= height_file * s <= HUMAN_HEIGHT[1]:
            unit = (name, s)
            break
    if unit is None:
        raise InputError(
            f"{path}: not a human size in any unit: the largest extent is {height_file:.6g} "
            f"file units, which is not {HUMAN_HEIGHT[0]}–{HUMAN_HEIGHT[1]} m in m, dm, cm or mm")
    units, scale = unit
    v = v * scale
    # weld coincident vertices (STL has none shared; OBJ may split at UV seams)
    v, f = _merge_vertices(v, f, tol=1e-6)
    if len(f) == 0:
        raise InputError(f"{path}: degenerate geometry: every face collapses")
    v, f = compact(v, f)    # drop unreferenced vertices: stray points are no surface
    holes, components, nonmanifold = _topology_report(f, len(v))
    up_axis, up_sign = _detect_up(v, f)
    fwd_axis, fwd_sign, detected = _detect_forward(v, f, up_axis, up_sign)
    R = _rotation(up_axis, up_sign, fwd_axis, fwd_sign)
    out = v @ R.T
    lo = out.min(axis=0)
    hi = out.max(axis=0)
    t = np.array([-(lo[0] + hi[0]) / 2, -lo[1], -(lo[2] + hi[2]) / 2])
    out = out + t
    T = np.eye(4)
    T[:3, :3] = R * scale
    T[:3, 3] = t
    return Scan(
        path=str(path), vertices=out, faces=f.astype(np.int32), units=units, scale=scale,
        up=("+" if up_sign > 0 else "-") + AXES[up_axis],
        forward=("+" if fwd_sign > 0 else "-") + AXES[fwd_axis],
        forward_detected=detected, transform=T,
        watertight=bool(holes == 0 and nonmanifold == 0 and components >= 1),
        holes=int(holes), components=int(components), nonmanifold_edges=int(nonmanifold),
        meta={"format": fmt, "file_extent": [float(a) for a in ext],
              },
    )
