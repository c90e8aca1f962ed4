"""CPU preview renderer: shaded orthographic images of triangle meshes (body, garment).

``render_meshes(meshes, view="front", size=(512, 768))`` → ``(H, W, 3) uint8``, where
``meshes`` is a list of ``(vertices (N,3), faces (M,3), rgb)`` in metres and glTF axes (+Y up,
the body faces +Z, feet on y = 0); ``rgb`` is one colour (3 floats in 0–1, or 0–255 ints) or
one colour per vertex (N,3). Views: ``front`` (camera on +Z looking −Z), ``side`` (from the
body's left, +X), ``back``, ``right`` or a yaw in degrees. Shading: smooth (per-vertex normal)
two-sided Lambert with a soft key light from the upper left of the camera, a weak fill and
ambient, 2× supersampled; a light grey background and, optionally, the floor (y = 0) with a soft
contact shadow. The rasteriser is :mod:`catwalk.geometry.raster`, shared with the collider.
"""

from __future__ import annotations

import os

import numba
import numpy as np
from PIL import Image

from catwalk.errors import InputError
from catwalk.fileio import atomic_path
from catwalk.geometry.raster import (
    Raster,
    camera_axes,
    ortho_view,
    raster_kernel,
    to_screen,
    vertex_normals,
    view_yaw,
)

BACKGROUND = (0.90, 0.90, 0.91)
FLOOR = (0.80, 0.80, 0.80)


def _colours(rgb, n: int) -> np.ndarray:
    c = np.asarray(rgb, dtype=np.float64)
    if c.shape == (3,):
        c = np.broadcast_to(c, (n, 3))
    elif c.shape != (n, 3):
        raise InputError(f"colour must be 3 values or one per vertex ({n}, 3), got {c.shape}")
    if np.issubdtype(np.asarray(rgb).dtype, np.integer) or c.max(initial=0.0) > 1.0:
        c = c / 255.0
    return np.clip(c, 0.0, 1.0)


def _gather(meshes):
    verts, faces, attrs = [], [], []
    offset = 0
    for item in meshes:
        try:
            v, f, rgb = item
        except (TypeError, ValueError):
            raise InputError("each mesh must be (vertices, faces, rgb)") from None
        v = np.asarray(v, dtype=np.float64)
        f = np.asarray(f, dtype=np.int64)
        if v.ndim != 2 or v.shape[1] != 3 or (f.size and (f.ndim != 2 or f.shape[1] != 3)):
            raise InputError(f"mesh arrays must be (N, 3) and (M, 3), got {v.shape}, {f.shape}")
        f = f.reshape(-1, 3)
        if f.size and (f.min() < 0 or f.max() >= len(v)):
            raise InputError("face index out of range")
        if not np.all(np.isfinite(v)):
            raise InputError("mesh has non-finite vertices")
        n = vertex_normals(v, f)
        attrs.append(np.hstack([n, _colours(rgb, len(v))]))
        verts.append(v)
        faces.append(f + offset)
        offset += len(v)
    if not verts:
        raise InputError("nothing to render")
    return np.vstack(verts), np.vstack(faces), np.vstack(attrs)


@numba.njit(cache=True, _nrt=False)
def _shade(attrs, tri, cam, key, fill, ambient, kd, kf, bg, img):
    h, w = tri.shape
    for i in range(h):
        for j in range(w):
            if tri[i, j] < 0:
                for q in range(3):
                    img[i, j, q] = bg[i, j, q]
                continue
            nx = attrs[i, j, 0]
            ny = attrs[i, j, 1]
            nz = attrs[i, j, 2]
            nn = np.sqrt(nx * nx + ny * ny + nz * nz)
            if nn > 0.0:
                nx /= nn
                ny /= nn
                nz /= nn
            if nx * cam[0] + ny * cam[1] + nz * cam[2] < 0.0:  # two-sided
                nx = -nx
                ny = -ny
                nz = -nz
            dk = max(nx * key[0] + ny * key[1] + nz * key[2], 0.0)
            # soft key: wrap lighting, so the terminator is gentle
            dk = 0.5 * dk + 0.5 * dk * dk + 0.15 * max(
                0.0, 1.0 - abs(nx * key[0] + ny * key[1] + nz * key[2]))
            df = max(nx * fill[0] + ny * fill[1] + nz * fill[2], 0.0)
            s = ambient + kd * dk + kf * df
            for q in range(3):
                img[i, j, q] = min(attrs[i, j, 3 + q] * s, 1.0)


@numba.njit(cache=True, _nrt=False)
def _background(colour, floor_colour, floor, y_floor, cx, half, ry, ss, bg):
    h, w, _ = bg.shape
    for i in range(h):
        shade = 1.02 - 0.06 * i / max(h - 1, 1)
        below = floor and i >= y_floor
        line = floor and (y_floor - 0.5 * ss) <= i < (y_floor + 0.5 * ss)
        for j in range(w):
            for q in range(3):
                bg[i, j, q] = floor_colour[q] if below else colour[q] * shade
            if floor:
                f = 1.0
                if half > 0.0:
                    d2 = ((j - cx) / max(half, 1.0)) ** 2 + ((i - y_floor) / ry) ** 2
                    if d2 < 9.0:
                        f = 1.0 - 0.35 * np.exp(-2.0 * d2)
                if line:
                    f *= 0.8
                for q in range(3):
                    bg[i, j, q] *= f


@numba.njit(cache=True, _nrt=False)
def _downsample_u8(img, ss, out):
    h, w, _ = out.shape
    inv = 1.0 / (ss * ss)
    for i in range(h):
        for j in range(w):
            for q in range(3):
                acc = 0.0
                for a in range(ss):
                    for b in range(ss):
                        acc += img[i * ss + a, j * ss + b, q]
                out[i, j, q] = np.uint8(min(max(acc * inv, 0.0), 1.0) * 255.0 + 0.5)


def render_meshes(meshes, view="front", size=(512, 768), *, margin=0.06, floor=True,
                  supersample=2, background=BACKGROUND, bbox=None) -> np.ndarray:
    """Render meshes to an ``(H, W, 3) uint8`` image (see the module docstring).

    ``bbox`` (lo, hi): the box to frame (default: the meshes' box, with the floor); pass the
    same box for every frame of an animation so the camera does not move.
    """
    v, f, attrs = _gather(meshes)
    w, h = int(size[0]), int(size[1])
    if w < 8 or h < 8:
        raise InputError(f"image too small: {size}")
    ss = int(supersample)
    if ss < 1 or ss > 4:
        raise InputError("supersample must be 1..4")
    if bbox is None:
        lo = v.min(axis=0)
        hi = v.max(axis=0)
        if floor:
            lo[1] = min(lo[1], 0.0)
    else:
        lo, hi = (np.asarray(b, dtype=np.float64) for b in bbox)
    yaw = view_yaw(view)
    cam = ortho_view(lo, hi, yaw, (w * ss, h * ss), margin=margin, square_pixels=True)
    sv = to_screen(cam.matrix, v)
    buf = Raster.empty(w * ss, h * ss, attrs.shape[1], "near")
    raster_kernel(sv, f, attrs, False, buf.depth, buf.attributes, buf.triangle)

    H, W = h * ss, w * ss
    y_floor, cx, half = -1.0, 0.0, 1.0
    if floor:
        # the floor y = 0 seen edge-on: the row of the world point (centre x, 0, centre z)
        c = 0.5 * (lo + hi)
        y_floor = float(to_screen(cam.matrix, [c[0], 0.0, c[2]])[0, 1])
        # soft contact shadow: an ellipse under the footprint of what is near the floor
        low = v[:, 1] < lo[1] + 0.15 * max(hi[1] - lo[1], 1e-9)
        if np.any(low):
            xs = sv[low, 0]
            cx, half = 0.5 * (xs.min() + xs.max()), 0.5 * (xs.max() - xs.min()) + 4 * ss
        else:
            half = 0.0
    bg = np.empty((H, W, 3))
    _background(np.asarray(background, dtype=np.float64), np.asarray(FLOOR), floor, y_floor,
                cx, half, max(0.02 * H, 2.0), ss, bg)
    r, u, c = camera_axes(yaw)
    key = -0.45 * r + 0.55 * u + 0.70 * c
    key /= np.linalg.norm(key)
    fill = 0.6 * r + 0.1 * u + 0.8 * c
    fill /= np.linalg.norm(fill)
    img = np.empty((H, W, 3))
    _shade(buf.attributes, buf.triangle, c, key, fill, 0.30, 0.70, 0.18, bg, img)
    out = np.empty((h, w, 3), np.uint8)
    _downsample_u8(img, ss, out)
    return out


IMAGE_FORMATS = {".png": "PNG", ".jpg": "JPEG", ".jpeg": "JPEG"}


def image_format(path, flag: str = "-o") -> str:
    """The image format (PNG or JPEG) a file name asks for by its extension; anything else
    raises :class:`InputError` naming ``flag``."""
    fmt = IMAGE_FORMATS.get(os.path.splitext(str(path))[1].lower())
    if fmt is None:
        raise InputError(f"{flag} {path}: images are written as .png, .jpg or .jpeg")
    return fmt


def save_image(image, path, flag: str | None = None) -> None:
    """Write an ``(H, W, 3)`` or ``(H, W)`` uint8 image, atomically, as PNG or JPEG by the
    file's extension (:func:`image_format`)."""
    _save(image, path, flag, image_format(path, flag or "image"))


def _image_array(image) -> np.ndarray:
    a = np.asarray(image)
    if a.dtype != np.uint8 or a.ndim not in (2, 3) or (a.ndim == 3 and a.shape[2] not in (3, 4)):
        raise InputError(f"image must be uint8 (H, W[, 3|4]), got {a.dtype} {a.shape}")
    return a


def save_png(image, path, flag: str | None = None) -> None:
    """Write an ``(H, W, 3)`` or ``(H, W)`` uint8 image as PNG, atomically."""
    _save(image, path, flag, "PNG")


def _save(image, path, flag: str | None, fmt: str) -> None:
    """``image`` written atomically (:func:`atomic_path`) as ``fmt``: PNG, or JPEG (no alpha,
    quality 92)."""
    a = _image_array(image)
    if fmt == "JPEG" and a.ndim == 3:
        a = a[..., :3]
    with atomic_path(path, flag) as tmp:
        Image.fromarray(a).save(tmp, format=fmt, **({"quality": 92} if fmt == "JPEG" else {}))
