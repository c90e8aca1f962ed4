"""The dressed body as Wavefront OBJ, one file per frame (for tools that do not read glTF).

Each ``frame_NNNN.obj`` holds the body (``o body``: ``v`` and ``f``) and each garment (``o
garment:dress``: ``v``, ``vt`` — pattern metres over the panel's texture size, v flipped as in
the .glb — and ``f v/vt``), one ``usemtl`` per panel; the shared ``tryon.mtl`` gives each panel
its colour (``Kd``) and texture (``map_Kd``, the image path relative to the directory).
"""

from __future__ import annotations

import io
import os
from pathlib import Path

import numpy as np

from catwalk.errors import InputError
from catwalk.fileio import atomic_path
from catwalk.garment.frames import GarmentFrames

SKIN_RGB = (0.80, 0.66, 0.58)


def _material_name(garment: str, panel: str) -> str:
    return f"{garment}/{panel}".replace(" ", "_")


def write_mtl(path: str | Path, garments: list[GarmentFrames]) -> None:
    path = Path(path)
    out = io.StringIO()
    out.write("# catwalk try-on materials\nnewmtl body\n")
    out.write("Kd {:.4f} {:.4f} {:.4f}\n".format(*SKIN_RGB))
    for gm in garments:
        for i, pname in enumerate(gm.panel_names):
            out.write(f"\nnewmtl {_material_name(gm.name, pname)}\n")
            tex = gm.textures[i]
            rgb = (1.0, 1.0, 1.0) if tex is not None else gm.colors[i][:3]
            out.write("Kd {:.4f} {:.4f} {:.4f}\n".format(*rgb))
            if gm.colors[i][3] < 1.0:
                out.write(f"d {gm.colors[i][3]:.4f}\n")
            if tex is not None:
                rel = os.path.relpath(Path(tex[0]).resolve(), path.parent.resolve())
                out.write(f"map_Kd {Path(rel).as_posix()}\n")
    with atomic_path(path) as tmp:
        tmp.write_text(out.getvalue())


def _rows(fmt: str, a: np.ndarray) -> str:
    if len(a) == 0:
        return ""
    buf = io.StringIO()
    np.savetxt(buf, a, fmt=fmt)
    return buf.getvalue()


def obj_text(body_vertices, body_faces, garments: list[GarmentFrames], frame: int,
             mtllib: str | None = "tryon.mtl") -> str:
    """One frame (index into each garment's frames) as OBJ text."""
    v = np.asarray(body_vertices, dtype=np.float64)
    f = np.asarray(body_faces, dtype=np.int64)
    parts = ["# catwalk try-on frame\n"]
    if mtllib:
        parts.append(f"mtllib {mtllib}\n")
    parts += ["o body\nusemtl body\n", _rows("v %.6f %.6f %.6f", v), _rows("f %d %d %d", f + 1)]
    nv, nt = len(v), 0
    for gm in garments:
        pos = np.asarray(gm.positions[frame], dtype=np.float64)
        tri = np.asarray(gm.triangles, dtype=np.int64)
        tri_panel = np.asarray(gm.panel)[tri[:, 0]]
        parts += [f"o {gm.name}\n", _rows("v %.6f %.6f %.6f", pos),
                  _rows("vt %.6f %.6f", gm.texcoords().astype(np.float64))]
        for i, pname in enumerate(gm.panel_names):
            t = tri[tri_panel == i]
            if len(t):
                parts.append(f"usemtl {_material_name(gm.name, pname)}\n")
                idx = np.repeat(t + 1, 2, axis=1)
                idx[:, 0::2] += nv
                idx[:, 1::2] += nt
                parts.append(_rows("f %d/%d %d/%d %d/%d", idx))
        nv += len(pos)
        nt += len(pos)
    return "".join(parts)


def write_obj_frames(directory: str | Path, body_faces, body_frames,
                     garments: list[GarmentFrames], *, prefix: str = "frame") -> list[Path]:
    """Write ``directory/{prefix}_NNNN.obj`` for every frame, and ``tryon.mtl``.

    ``body_frames``: (F, N, 3) body vertices at the garments' F frame times (the same F for
    every garment; e.g. ``Scene.body_vertices_at(t)`` for each ``t`` in ``times``), or one
    (N, 3) array for a body that does not move. Each file is written atomically. Returns the
    OBJ paths."""
    bf = np.asarray(body_frames, dtype=np.float64)
    for gm in garments:
        gm.check()
    counts = {gm.frames for gm in garments}
    if len(counts) > 1:
        raise InputError(f"garments have different frame counts: {sorted(counts)}")
    nframes = counts.pop() if counts else (bf.shape[0] if bf.ndim == 3 else 1)
    if bf.ndim == 2:
        bf = np.broadcast_to(bf, (nframes, *bf.shape))
    if bf.ndim != 3 or bf.shape[2] != 3 or bf.shape[0] != nframes:
        raise InputError(f"body frames must be ({nframes}, N, 3) or (N, 3), got {bf.shape}")
    faces = np.asarray(body_faces)
    if faces.ndim != 2 or faces.shape[1] != 3 or faces.min() < 0 or faces.max() >= bf.shape[1]:
        raise InputError("body faces must be (M, 3) indices into the body vertices")
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    write_mtl(directory / "tryon.mtl", garments)
    paths = []
    for k in range(nframes):
        p = directory / f"{prefix}_{k:04d}.obj"
        with atomic_path(p) as tmp:
            tmp.write_text(obj_text(bf[k], faces, garments, k))
        paths.append(p)
    return paths
