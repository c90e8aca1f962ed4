"""The image pass's kernel (:func:`image_pass`): each cloth point looked up in the front and back
depth maps at its pixel, the response to the nearer surface, and the points the maps cannot
answer marked for object space.

What each point keeps of the pixels it read (the maps' layout: :mod:`.depth_maps`):

* ``pkey`` (P, :data:`PKEY_COLUMNS`) int64: the key of its 2×2 pixel block
  (:data:`KEY_BLOCK`) and those of the pixels and side its attributes came from, slot u's at
  ``KEY_ATTRS + u``;
* ``pdep`` (P, :data:`PDEP_COLUMNS`) float32: the block's depths, pixel q of slot u at
  ``DEP_FRONT + BLOCK·u + q`` (the front map) and ``DEP_BACK + BLOCK·u + q`` (the back map);
* ``patt`` (P, :data:`PATT_COLUMNS`) float32: the attributes (normal, velocity), slot u's at
  ``N_ATTRS·u`` (``ATTR_NORMAL``, ``ATTR_VELOCITY`` added).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from catwalk.collide.kernels.depth_maps import (
    ATTR_NORMAL,
    ATTR_VELOCITY,
    N_ATTRS,
    SIDE_BACK,
    SIDE_FRONT,
)
from catwalk.collide.kernels.response import near_plane, record_plane, respond
from catwalk.collide.kernels.stats import ST_BOXED, ST_CONTACT, ST_EDGE, ST_NARROW, ST_SKIPPED

EDGE_WINDOW = 2  # pixels round a point's block that count as near the torso's silhouette
KEY_BLOCK, KEY_ATTRS = 0, 1
PKEY_COLUMNS = 3
#: pixels in a block (2×2)
BLOCK = 4
DEP_FRONT, DEP_BACK = 0, 2 * BLOCK
PDEP_COLUMNS = 4 * BLOCK
PATT_COLUMNS = 2 * N_ATTRS


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


@numba.njit(cache=True, _nrt=False, nogil=True)
def image_pass(pos, vel, alpha, m, D, A, s0, s1, version, box_lo, box_hi, thickness, friction,
               slack, plane_band, min_nz, skip_far, held, stats, pkey, pdep, patt, planes, edge,
               edge_nz, pwin):
    """Image-space collision of the cloth points against front/back depth maps at time
    ``alpha`` between the previous (slot ``s0``) and the current (slot ``s1``) frame's maps,
    on one thread (a point's work writes only its own entries, but a look-up is cheap:
    handing slices of it to other threads cost more than it saved, docs/collide.md "Both
    cores").

    ``m`` (3×4) world → map (x col, y row, z = depth towards the front camera). ``D``
    (H,W,2 slots,2 sides) float32 depth (:data:`~.depth_maps.SIDE_FRONT` = nearest,
    :data:`~.depth_maps.SIDE_BACK` = farthest; −inf/+inf where empty), bilinear over the
    covered pixels; ``A`` (H,W,2 sides,2 slots,N_ATTRS) float32 per-pixel normal and body
    velocity, taken from the nearest covered pixel.

    The maps do not change during a frame and a point's pixel changes slowly, so each point
    keeps a copy of what it read (``version`` numbers the maps' contents): ``pkey``, ``pdep``,
    ``patt`` (the module's docstring). Read in order, one point after the other, they stay
    cheap where the maps' scattered pixels would miss the cache.
    (The object pass's clearances count these pushes as the points' motion: it measures
    each point's motion from where it last saw it.)

    ``edge`` (P,) bool: when not empty, points marked on entry are skipped (the caller
    sends them to object space), and the points the maps cannot answer well are marked
    there and left alone (not held, not moved) for the caller to collide in object space:
    those whose 2×2 pixel block is not fully covered in both slots but has a covered pixel
    within ``EDGE_WINDOW`` pixels (the silhouette, where the torso's surface turns away from
    both cameras: the crotch's underside, seen edge-on, is drawn in no pixel at all; and the
    open rim where a limb joins), and those whose surface turns too far from the camera
    (n·view < ``edge_nz``), where a depth difference is a poor measure of the distance.
    ``pwin`` (P,) int8: each point's "covered pixel in the window" for its cached block
    (−1: not needed yet; looked at only for blocks not fully covered).
    Empty ``edge``: the paper's image space, where such points are answered by the maps
    (the normal leaned towards the view axis at the silhouette).

    ``planes`` (P,8): each held point's contact plane (:func:`record_plane`), and the same for
    each point not held but within ``plane_band`` of touching, unless it has one
    (:func:`near_plane`)."""
    h = D.shape[0]
    w = D.shape[1]
    cx = m[2, 0]
    cy = m[2, 1]
    cz = m[2, 2]
    reach = (thickness + slack) / min_nz
    vkey = version << 40
    akey = version << 30
    st = math.sqrt(1.0 - min_nz * min_nz)
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
        if skip_far and (px < box_lo[0] or px > box_hi[0] or py < box_lo[1] or
                         py > box_hi[1] or pz < box_lo[2] or pz > box_hi[2]):
            n_skip += 1
            continue
        n_box += 1
        x = m[0, 0] * px + m[0, 1] * py + m[0, 2] * pz + m[0, 3]
        y = m[1, 0] * px + m[1, 1] * py + m[1, 2] * pz + m[1, 3]
        z = cx * px + cy * py + cz * pz + m[2, 3]
        if not (x >= 0.0 and x < w and y >= 0.0 and y < h):
            continue
        n_narrow += 1
        fx = x - 0.5
        fy = y - 0.5
        j0 = int(math.floor(fx))
        i0 = int(math.floor(fy))
        tx = fx - j0
        ty = fy - i0
        key = vkey | ((i0 + 1) << 20) | (j0 + 1)
        if pkey[i, KEY_BLOCK] != key:
            # the 2×2 block's depths, both slots and sides (−inf/+inf off the map)
            for q in range(BLOCK):
                ii = i0 + (q >> 1)
                jj = j0 + (q & 1)
                inside = ii >= 0 and ii < h and jj >= 0 and jj < w
                for u in range(2):
                    sl = s0 if u == 0 else s1
                    if inside:
                        pdep[i, DEP_FRONT + BLOCK * u + q] = D[ii, jj, sl, SIDE_FRONT]
                        pdep[i, DEP_BACK + BLOCK * u + q] = D[ii, jj, sl, SIDE_BACK]
                    else:
                        pdep[i, DEP_FRONT + BLOCK * u + q] = -np.inf
                        pdep[i, DEP_BACK + BLOCK * u + q] = np.inf
            pkey[i, KEY_BLOCK] = key
            pwin[i] = -1  # not looked at yet for this block
        w00 = (1.0 - tx) * (1.0 - ty)
        w01 = tx * (1.0 - ty)
        w10 = (1.0 - tx) * ty
        w11 = tx * ty
        # per slot: bilinear over the covered pixels (front and back both drawn: at the open
        # rim where a limb joins, a pixel can hold a surface facing one camera and none
        # facing the other, and an empty side's ±inf would put every point beyond reach),
        # and the covered pixel of most weight
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
        if use_edge and (nc0 < BLOCK or nc1 < BLOCK):
            # at or near the silhouette (or the open rim where a limb joins): the surface
            # there turns away from both cameras (the crotch's underside is seen edge-on and
            # drawn in no pixel at all): object space answers
            if pwin[i] < 0:
                pwin[i] = _window_covered(D, i0, j0, s0, s1, h, w)
            if pwin[i]:
                edge[i] = True
                n_edge += 1
            continue
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
            continue
        zf = 0.0
        zb = 0.0
        if ka > 0.0:
            zf += ka * zf0 / ws0
            zb += ka * zb0 / ws0
        if kb > 0.0:
            zf += kb * zf1 / ws1
            zb += kb * zb1 / ws1
        # beyond reach along the view axis (at a slope n_z ≥ min_nz the gap is ≤ d / min_nz)
        if z >= zf + reach or z <= zb - reach:
            continue
        front = (zf - z) <= (z - zb)
        side = SIDE_FRONT if front else SIDE_BACK
        # normal and velocity from the covered pixel of the block nearest the point
        pix0 = (i0 + (q0 >> 1)) * w + j0 + (q0 & 1) if (ka > 0.0 and q0 >= 0) else -1
        pix1 = (i0 + (q1 >> 1)) * w + j0 + (q1 & 1) if (kb > 0.0 and q1 >= 0) else -1
        k0 = akey | (side << 28) | (pix0 + 1)
        k1 = akey | (side << 28) | (pix1 + 1)
        if pkey[i, KEY_ATTRS] != k0:
            if pix0 >= 0:
                ii = pix0 // w
                jj = pix0 - ii * w
                for c in range(N_ATTRS):
                    patt[i, c] = A[ii, jj, side, s0, c]
            pkey[i, KEY_ATTRS] = k0
        if pkey[i, KEY_ATTRS + 1] != k1:
            if pix1 >= 0:
                ii = pix1 // w
                jj = pix1 - ii * w
                for c in range(N_ATTRS):
                    patt[i, N_ATTRS + c] = A[ii, jj, side, s1, c]
            pkey[i, KEY_ATTRS + 1] = k1
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
        sgn = 1.0 if front else -1.0
        nl = math.sqrt(nx * nx + ny * ny + nz * nz)
        if nl > 1e-12:
            nx /= nl
            ny /= nl
            nz /= nl
        ndc = sgn * (nx * cx + ny * cy + nz * cz)  # > 0 for a surface facing its camera
        if ndc < edge_nz and use_edge:
            edge[i] = True
            n_edge += 1
            continue
        if ndc < min_nz:
            # at the silhouette (or a bad normal) lean the normal towards the camera axis
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
        # signed distance to the surface's tangent plane at the pixel (p − S)·n
        s = (z - zf) * ndc if front else (zb - z) * ndc
        if s >= thickness + slack:
            if s < thickness + slack + plane_band:
                near_plane(planes, i, pos[i, 0], pos[i, 1], pos[i, 2], nx, ny, nz, s,
                           thickness, bvx, bvy, bvz, friction)
            continue
        held[i] = True
        n_contact += 1
        record_plane(planes, i, pos[i, 0], pos[i, 1], pos[i, 2], nx, ny, nz, s, thickness, bvx,
                     bvy, bvz, friction)
        if s < thickness:
            respond(pos, vel, i, nx, ny, nz, s, thickness, bvx, bvy, bvz, friction)
    stats[ST_SKIPPED] += n_skip
    stats[ST_BOXED] += n_box
    stats[ST_NARROW] += n_narrow
    stats[ST_CONTACT] += n_contact
    stats[ST_EDGE] += n_edge
