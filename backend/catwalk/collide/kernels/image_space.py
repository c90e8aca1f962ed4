"""The image pass's kernel (:func:`image_pass`): each cloth point looked up in the front and back
depth maps at its pixel, the response to the nearer surface, and the points the maps cannot
answer marked for object space.

Its inputs, grouped (from Python as plain tuples in their fields' order, named again inside,
as the object pass's: :mod:`catwalk.collide.kernels.object_inputs`): :data:`ImageMaps` (the
maps and which slots to read), :data:`ImageConfig` (the options) and :data:`ImagePoints` (what
each point keeps of the pixels it read; the maps' layout: :mod:`.depth_maps`):

* ``pkey`` (P, :data:`PKEY_COLUMNS`) int64: the key of its 2×2 pixel block
  (:data:`KEY_BLOCK`) and those of the pixels and side its attributes came from, slot u's at
  ``KEY_ATTRS + u``;
* ``pdep`` (P, :data:`PDEP_COLUMNS`) float32: the block's depths, pixel q of slot u at
  ``DEP_FRONT + BLOCK·u + q`` (the front map) and ``DEP_BACK + BLOCK·u + q`` (the back map);
* ``patt`` (P, :data:`PATT_COLUMNS`) float32: the attributes (normal, velocity), slot u's at
  ``N_ATTRS·u`` (``ATTR_NORMAL``, ``ATTR_VELOCITY`` added);
* ``pwin`` (P,) int8: whether a pixel within :data:`EDGE_WINDOW` of its block is covered (−1:
  not looked at yet for this block; looked at only for blocks not fully covered).

The maps do not change during a frame and a point's pixel changes slowly, so each point keeps a
copy of what it read (``version`` numbers the maps' contents). Read in order, one point after
the other, the copies stay cheap where the maps' scattered pixels would miss the cache. (The
object pass's clearances count these pushes as the points' motion: it measures each point's
motion from where it last saw it.)
"""

from __future__ import annotations

import math
from collections import namedtuple

import numba
import numpy as np

from catwalk.collide.kernels.depth_maps import (
    ATTR_NORMAL,
    ATTR_VELOCITY,
    N_ATTRS,
    SIDE_BACK,
    SIDE_FRONT,
)
from catwalk.collide.kernels.response import Contact, near_plane, record_plane, respond
from catwalk.collide.kernels.stats import ST_BOXED, ST_CONTACT, ST_EDGE, ST_NARROW, ST_SKIPPED

EDGE_WINDOW = 2  # pixels round a point's block that count as near the torso's silhouette
KEY_BLOCK, KEY_ATTRS = 0, 1
PKEY_COLUMNS = 3
#: pixels in a block (2×2)
BLOCK = 4
DEP_FRONT, DEP_BACK = 0, 2 * BLOCK
PDEP_COLUMNS = 4 * BLOCK
PATT_COLUMNS = 2 * N_ATTRS

#: the maps a look-up reads: ``m`` (3×4) world → map (x col, y row, z = depth towards the front
#: camera), the depths ``D`` and attributes ``A`` (:mod:`.depth_maps`), the slots of the
#: previous (``s0``) and the current (``s1``) frame, and the ``version`` of their contents
ImageMaps = namedtuple("ImageMaps", "m D A s0 s1 version")
ImageConfig = namedtuple("ImageConfig", "thickness friction slack plane_band min_nz edge_nz "
                         "skip_far")
ImagePoints = namedtuple("ImagePoints", "pkey pdep patt pwin")

# what a look-up came to (:func:`_answer`)
_NOTHING, _EDGE, _HELD = 0, 1, 2


@numba.njit(cache=True, _nrt=False, nogil=True)
def image_pass(pos, vel, held, planes, edge, stats, alpha, box_lo, box_hi, maps, cfg, pts):
    """Image-space collision of the cloth points against front/back depth maps at time
    ``alpha`` between the previous and the current frame's maps (``maps``: :data:`ImageMaps`;
    ``cfg``: :data:`ImageConfig`; ``pts``: :data:`ImagePoints`), on one thread (a point's work
    writes only its own entries, but a look-up is cheap: handing slices of it to other threads
    cost more than it saved, docs/collide.md "Both cores"). Points outside the box
    [``box_lo``, ``box_hi``] are skipped (with ``skip_far``). Depths are bilinear over the
    covered pixels; a point's normal and body velocity are taken from the nearest covered
    pixel.

    ``edge`` (P,) bool: when not empty, points marked on entry are skipped (the caller
    sends them to object space), and the points the maps cannot answer well are marked
    there and left alone (not held, not moved) for the caller to collide in object space:
    those whose 2×2 pixel block is not fully covered in both slots but has a covered pixel
    within ``EDGE_WINDOW`` pixels (the silhouette, where the torso's surface turns away from
    both cameras: the crotch's underside, seen edge-on, is drawn in no pixel at all; and the
    open rim where a limb joins), and those whose surface turns too far from the camera
    (n·view < ``edge_nz``), where a depth difference is a poor measure of the distance.
    Empty ``edge``: the paper's image space, where such points are answered by the maps
    (the normal leaned towards the view axis at the silhouette).

    ``planes`` (P, PLANE_COLUMNS): each held point's contact plane
    (:func:`~.response.record_plane`), and the same for each point not held but within
    ``plane_band`` of touching, unless it has one (:func:`~.response.near_plane`). ``stats``:
    the counters (:mod:`.stats`)."""
    maps = ImageMaps(*maps)
    cfg = ImageConfig(*cfg)
    pts = ImagePoints(*pts)
    m = maps.m
    h = maps.D.shape[0]
    w = maps.D.shape[1]
    n_skip = 0
    n_box = 0
    n_narrow = 0
    n_contact = 0
    n_edge = 0
    use_edge = edge.shape[0] > 0
    for i in range(pos.shape[0]):
        if use_edge and edge[i]:
            n_edge += 1  # marked by the caller: left to object space
            continue
        px = pos[i, 0]
        py = pos[i, 1]
        pz = pos[i, 2]
        if cfg.skip_far and (px < box_lo[0] or px > box_hi[0] or py < box_lo[1] or
                             py > box_hi[1] or pz < box_lo[2] or pz > box_hi[2]):
            n_skip += 1
            continue
        n_box += 1
        x = m[0, 0] * px + m[0, 1] * py + m[0, 2] * pz + m[0, 3]
        y = m[1, 0] * px + m[1, 1] * py + m[1, 2] * pz + m[1, 3]
        z = m[2, 0] * px + m[2, 1] * py + m[2, 2] * pz + m[2, 3]
        if not (x >= 0.0 and x < w and y >= 0.0 and y < h):
            continue
        n_narrow += 1
        got = _answer(i, x, y, z, pos, vel, held, planes, edge, use_edge, alpha, maps, cfg, pts)
        if got == _EDGE:
            n_edge += 1
        elif got == _HELD:
            n_contact += 1
    stats[ST_SKIPPED] += n_skip
    stats[ST_BOXED] += n_box
    stats[ST_NARROW] += n_narrow
    stats[ST_CONTACT] += n_contact
    stats[ST_EDGE] += n_edge


@numba.njit(cache=True, _nrt=False, inline="always")
def _answer(i, x, y, z, pos, vel, held, planes, edge, use_edge, alpha, maps, cfg, pts):
    """Point i at map position (x, y) and depth z: the maps' answer — nothing (beyond reach,
    or no pixel covered), left to object space (``_EDGE``, marked in ``edge``), or in contact
    (``_HELD``: held, its plane recorded, pushed out within the thickness); near the surface,
    its plane (:func:`~.response.near_plane`)."""
    D = maps.D
    h = D.shape[0]
    w = D.shape[1]
    fx = x - 0.5
    fy = y - 0.5
    j0 = int(math.floor(fx))
    i0 = int(math.floor(fy))
    _read_block(i, i0, j0, maps, pts)
    ws0, zf0, zb0, q0, nc0, ws1, zf1, zb1, q1, nc1 = _blend_block(i, fx - j0, fy - i0, pts.pdep)
    if use_edge and (nc0 < BLOCK or nc1 < BLOCK):
        # at or near the silhouette (or the open rim where a limb joins): the surface
        # there turns away from both cameras (the crotch's underside is seen edge-on and
        # drawn in no pixel at all): object space answers
        if pts.pwin[i] < 0:
            pts.pwin[i] = _window_covered(D, i0, j0, maps.s0, maps.s1, h, w)
        if pts.pwin[i]:
            edge[i] = True
            return _EDGE
        return _NOTHING
    if ws0 > 0.0 and ws1 > 0.0:
        ka = 1.0 - alpha
        kb = alpha
    elif ws1 > 0.0:
        ka = 0.0
        kb = 1.0
    elif ws0 > 0.0:
        ka = 1.0
        kb = 0.0
    else:
        return _NOTHING
    zf = 0.0
    zb = 0.0
    if ka > 0.0:
        zf += ka * zf0 / ws0
        zb += ka * zb0 / ws0
    if kb > 0.0:
        zf += kb * zf1 / ws1
        zb += kb * zb1 / ws1
    # beyond reach along the view axis (at a slope n_z ≥ min_nz the gap is ≤ d / min_nz)
    reach = (cfg.thickness + cfg.slack) / cfg.min_nz
    if z >= zf + reach or z <= zb - reach:
        return _NOTHING
    front = (zf - z) <= (z - zb)
    side = SIDE_FRONT if front else SIDE_BACK
    # normal and velocity from the covered pixel of the block nearest the point
    pix0 = (i0 + (q0 >> 1)) * w + j0 + (q0 & 1) if (ka > 0.0 and q0 >= 0) else -1
    pix1 = (i0 + (q1 >> 1)) * w + j0 + (q1 & 1) if (kb > 0.0 and q1 >= 0) else -1
    _read_attrs(i, 0, pix0, side, maps, pts)
    _read_attrs(i, 1, pix1, side, maps, pts)
    nx, ny, nz, bvx, bvy, bvz = _blend_attrs(i, ka, kb, pts.patt)
    sgn = 1.0 if front else -1.0
    nx, ny, nz, ndc = _facing_normal(nx, ny, nz, sgn, maps.m, cfg.min_nz, cfg.edge_nz, use_edge)
    if ndc < cfg.edge_nz and use_edge:
        edge[i] = True
        return _EDGE
    # signed distance to the surface's tangent plane at the pixel (p − S)·n
    s = (z - zf) * ndc if front else (zb - z) * ndc
    hit = Contact(s, nx, ny, nz, bvx, bvy, bvz)
    if s >= cfg.thickness + cfg.slack:
        if s < cfg.thickness + cfg.slack + cfg.plane_band:
            near_plane(planes, i, pos[i, 0], pos[i, 1], pos[i, 2], hit, cfg.thickness,
                       cfg.friction)
        return _NOTHING
    held[i] = True
    record_plane(planes, i, pos[i, 0], pos[i, 1], pos[i, 2], hit, cfg.thickness, cfg.friction)
    if s < cfg.thickness:
        respond(pos, vel, i, hit, cfg.thickness, cfg.friction)
    return _HELD


@numba.njit(cache=True, _nrt=False, inline="always")
def _read_block(i, i0, j0, maps, pts):
    """Point i's copy of the depths of the 2×2 block at (i0, j0), both slots and sides
    (−inf/+inf off the map), unless it holds it already."""
    D = maps.D
    h = D.shape[0]
    w = D.shape[1]
    key = (maps.version << 40) | ((i0 + 1) << 20) | (j0 + 1)
    if pts.pkey[i, KEY_BLOCK] == key:
        return
    pdep = pts.pdep
    for q in range(BLOCK):
        ii = i0 + (q >> 1)
        jj = j0 + (q & 1)
        inside = ii >= 0 and ii < h and jj >= 0 and jj < w
        for u in range(2):
            sl = maps.s0 if u == 0 else maps.s1
            if inside:
                pdep[i, DEP_FRONT + BLOCK * u + q] = D[ii, jj, sl, SIDE_FRONT]
                pdep[i, DEP_BACK + BLOCK * u + q] = D[ii, jj, sl, SIDE_BACK]
            else:
                pdep[i, DEP_FRONT + BLOCK * u + q] = -np.inf
                pdep[i, DEP_BACK + BLOCK * u + q] = np.inf
    pts.pkey[i, KEY_BLOCK] = key
    pts.pwin[i] = -1  # not looked at yet for this block


@numba.njit(cache=True, _nrt=False, inline="always")
def _blend_block(i, tx, ty, pdep):
    """Per slot, point i's block at fractions (tx, ty) between its pixels: bilinear over the
    covered pixels (front and back both drawn: at the open rim where a limb joins, a pixel can
    hold a surface facing one camera and none facing the other, and an empty side's ±inf would
    put every point beyond reach) — the sum of the weights, the weighted front and back depths,
    the covered pixel of most weight (or −1) and the number covered. Returns those of slot 0,
    then slot 1."""
    w00 = (1.0 - tx) * (1.0 - ty)
    w01 = tx * (1.0 - ty)
    w10 = (1.0 - tx) * ty
    w11 = tx * ty
    ws0 = 0.0
    zf0 = 0.0
    zb0 = 0.0
    q0 = -1
    wq0 = -1.0
    nc0 = 0
    nc1 = 0
    ws1 = 0.0
    zf1 = 0.0
    zb1 = 0.0
    q1 = -1
    wq1 = -1.0
    for q in range(BLOCK):
        wq = w00 if q == 0 else (w01 if q == 1 else (w10 if q == 2 else w11))
        f = pdep[i, DEP_FRONT + q]
        if f > -np.inf and pdep[i, DEP_BACK + q] < np.inf:
            nc0 += 1
            ws0 += wq
            zf0 += wq * f
            zb0 += wq * pdep[i, DEP_BACK + q]
            if wq > wq0:
                wq0 = wq
                q0 = q
        f = pdep[i, DEP_FRONT + BLOCK + q]
        if f > -np.inf and pdep[i, DEP_BACK + BLOCK + q] < np.inf:
            nc1 += 1
            ws1 += wq
            zf1 += wq * f
            zb1 += wq * pdep[i, DEP_BACK + BLOCK + q]
            if wq > wq1:
                wq1 = wq
                q1 = q
    return ws0, zf0, zb0, q0, nc0, ws1, zf1, zb1, q1, nc1


@numba.njit(cache=True, _nrt=False, inline="always")
def _read_attrs(i, u, pix, side, maps, pts):
    """Point i's copy of the attributes of pixel ``pix`` (−1: none) on ``side`` of slot u
    (0: the previous frame's, 1: the current one's), unless it holds it already."""
    key = (maps.version << 30) | (side << 28) | (pix + 1)
    if pts.pkey[i, KEY_ATTRS + u] == key:
        return
    if pix >= 0:
        w = maps.D.shape[1]
        ii = pix // w
        jj = pix - ii * w
        sl = maps.s0 if u == 0 else maps.s1
        for c in range(N_ATTRS):
            pts.patt[i, N_ATTRS * u + c] = maps.A[ii, jj, side, sl, c]
    pts.pkey[i, KEY_ATTRS + u] = key


@numba.njit(cache=True, _nrt=False, inline="always")
def _blend_attrs(i, ka, kb, patt):
    """Point i's normal (not unit) and body velocity: its two slots' weighed ``ka``, ``kb``
    (a slot of weight 0 not read)."""
    nx = 0.0
    ny = 0.0
    nz = 0.0
    bvx = 0.0
    bvy = 0.0
    bvz = 0.0
    if ka > 0.0:
        nx += ka * patt[i, ATTR_NORMAL]
        ny += ka * patt[i, ATTR_NORMAL + 1]
        nz += ka * patt[i, ATTR_NORMAL + 2]
        bvx += ka * patt[i, ATTR_VELOCITY]
        bvy += ka * patt[i, ATTR_VELOCITY + 1]
        bvz += ka * patt[i, ATTR_VELOCITY + 2]
    if kb > 0.0:
        nx += kb * patt[i, N_ATTRS + ATTR_NORMAL]
        ny += kb * patt[i, N_ATTRS + ATTR_NORMAL + 1]
        nz += kb * patt[i, N_ATTRS + ATTR_NORMAL + 2]
        bvx += kb * patt[i, N_ATTRS + ATTR_VELOCITY]
        bvy += kb * patt[i, N_ATTRS + ATTR_VELOCITY + 1]
        bvz += kb * patt[i, N_ATTRS + ATTR_VELOCITY + 2]
    return nx, ny, nz, bvx, bvy, bvz


@numba.njit(cache=True, _nrt=False, inline="always")
def _facing_normal(nx, ny, nz, sgn, m, min_nz, edge_nz, use_edge):
    """The normal n made unit and its slope towards its camera (``sgn`` +1: the front one,
    −1: the back one) ``ndc`` (> 0 for a surface facing it); below ``min_nz`` (at the
    silhouette, or a bad normal) n leans towards the camera axis to that slope — unless the
    point is one the caller answers in object space (``ndc`` < ``edge_nz`` with ``use_edge``:
    left as it is). Returns (nx, ny, nz, ndc)."""
    cx = m[2, 0]
    cy = m[2, 1]
    cz = m[2, 2]
    nl = math.sqrt(nx * nx + ny * ny + nz * nz)
    if nl > 1e-12:
        nx /= nl
        ny /= nl
        nz /= nl
    ndc = sgn * (nx * cx + ny * cy + nz * cz)  # > 0 for a surface facing its camera
    if ndc < edge_nz and use_edge:
        return nx, ny, nz, ndc
    if ndc < min_nz:
        st = math.sqrt(1.0 - min_nz * min_nz)
        tx_ = nx - sgn * ndc * cx
        ty_ = ny - sgn * ndc * cy
        tz_ = nz - sgn * ndc * cz
        tl = math.sqrt(tx_ * tx_ + ty_ * ty_ + tz_ * tz_)
        if tl > 1e-12:
            nx = tx_ / tl * st + sgn * min_nz * cx
            ny = ty_ / tl * st + sgn * min_nz * cy
            nz = tz_ / tl * st + sgn * min_nz * cz
        else:
            nx = sgn * cx
            ny = sgn * cy
            nz = sgn * cz
        ndc = min_nz
    return nx, ny, nz, ndc


@numba.njit(cache=True, _nrt=False, inline="always")
def _window_covered(D, i0, j0, s0, s1, h, w):
    """1 if any pixel within ``EDGE_WINDOW`` of the 2×2 block at (i0, j0) is covered in
    either slot, on either side (under the crotch only surfaces facing away from the front
    camera are drawn: the front map is empty there, the back map is not), else 0."""
    for ii in range(max(i0 - EDGE_WINDOW, 0), min(i0 + 2 + EDGE_WINDOW, h)):
        for jj in range(max(j0 - EDGE_WINDOW, 0), min(j0 + 2 + EDGE_WINDOW, w)):
            if D[ii, jj, s0, SIDE_FRONT] > -np.inf or D[ii, jj, s1, SIDE_FRONT] > -np.inf or \
                    D[ii, jj, s0, SIDE_BACK] < np.inf or D[ii, jj, s1, SIDE_BACK] < np.inf:
                return 1
    return 0
