"""The dressed body as Open Inventor 2.1 ASCII (.iv), as the paper's system saved it.

One ``Separator`` per object (the body, each garment), each with a ``Material``
(``diffuseColor``: one colour, or one per vertex with ``MaterialBinding PER_VERTEX_INDEXED``),
a ``Coordinate3`` and an ``IndexedFaceSet`` (faces as ``a, b, c, -1``), inside one root
``Separator`` with ``ShapeHints`` (counter-clockwise, two-sided lighting: cloth has no inside).
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from catwalk.errors import InputError
from catwalk.fileio import atomic_path

HEADER = "#Inventor V2.1 ascii\n"
SKIN_RGB = (0.80, 0.66, 0.58)


def _name(text: str) -> str:
    """An Inventor node name (DEF): letters, digits and _ only, not starting with a digit."""
    out = "".join(c if c.isalnum() or c == "_" else "_" for c in text)
    return out if out and not out[0].isdigit() else f"_{out}"


def _rows(fmt: str, a: np.ndarray) -> str:
    buf = io.StringIO()
    np.savetxt(buf, a, fmt=fmt, delimiter=" ", newline=",\n")
    return buf.getvalue().rstrip(",\n")


def _object(out: io.StringIO, name: str, vertices, faces, rgb) -> None:
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0 or not np.all(np.isfinite(v)):
        raise InputError(f"{name}: vertices must be finite (N, 3), got {v.shape}")
    if f.ndim != 2 or f.shape[1] != 3 or len(f) == 0 or f.min() < 0 or f.max() >= len(v):
        raise InputError(f"{name}: faces must be (M, 3) indices into its {len(v)} vertices")
    c = np.asarray(rgb, dtype=np.float64)
    if c.max(initial=0.0) > 1.0:
        c = c / 255.0
    out.write(f"  DEF {_name(name)} Separator {{\n    Info {{ string \"{name}\" }}\n")
    if c.shape == (len(v), 3):
        out.write("    MaterialBinding { value PER_VERTEX_INDEXED }\n")
        out.write(f"    Material {{ diffuseColor [\n{_rows('      %.4f %.4f %.4f', c)} ] }}\n")
    elif c.shape in ((3,), (4,)):
        out.write("    Material {{ diffuseColor {:.4f} {:.4f} {:.4f}".format(*c[:3]))
        if c.shape == (4,) and c[3] < 1.0:
            out.write(f" transparency {1.0 - c[3]:.4f}")
        out.write(" }\n")
    else:
        raise InputError(f"{name}: colour must be RGB(A) or one RGB per vertex, got {c.shape}")
    out.write(f"    Coordinate3 {{ point [\n{_rows('      %.6f %.6f %.6f', v)} ] }}\n")
    idx = np.hstack([f, np.full((len(f), 1), -1)])
    out.write(f"    IndexedFaceSet {{ coordIndex [\n{_rows('      %d, %d, %d, %d', idx)} ] }}\n")
    out.write("  }\n")


def write_inventor(path: str | Path, body_vertices, body_faces, garments_at_frame) -> None:
    """Write the body and ``garments_at_frame`` — ``(name, vertices, triangles, rgb)`` tuples as
    ``Scene.meshes_at(t)[1:]`` or ``GarmentFrames.mesh_at_frame(i)`` give them — as one .iv
    file (atomically)."""
    out = io.StringIO()
    out.write(HEADER + "# catwalk: the dressed body, one frame\n")
    out.write("Separator {\n  ShapeHints { vertexOrdering COUNTERCLOCKWISE "
              "shapeType UNKNOWN_SHAPE_TYPE }\n")
    _object(out, "body", body_vertices, body_faces, SKIN_RGB)
    for item in garments_at_frame:
        try:
            name, v, f, rgb = item
        except (TypeError, ValueError):
            raise InputError("each garment must be (name, vertices, triangles, rgb)") from None
        _object(out, name, v, f, rgb)
    out.write("}\n")
    with atomic_path(path) as tmp:
        tmp.write_text(out.getvalue())
