"""The collider's per-substep numba kernels: the object-space pass (closest triangle in the
limbs' hierarchies, previous/current position against it) and the image-space pass (front/back
depth-map look-up), both with the same response (pushed out to the surface plus the cloth
thickness; normal velocity set to the body's, Coulomb friction on the tangential part).

Stats written by the passes (``stats`` int64 array, accumulated):
0 points that passed a part's box test, 1 narrow-phase searches (hierarchy walks or map
look-ups), 2 contacts, 3 closest-triangle results reused, 4 hierarchy nodes visited,
5 points skipped by the box tests, 6 points skipped by their clearance, 7 triangles tested
(closest point computed).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from catwalk.collide.bvh import box_dist2, closest_on_triangle, closest_triangle

ST_BOXED, ST_NARROW, ST_CONTACT, ST_REUSED, ST_NODES, ST_SKIPPED, ST_CLEAR, ST_TRIS = range(8)
N_STATS = 8
STAT_NAMES = ("boxed", "narrow", "contacts", "reused", "nodes", "skipped", "clearance_skips",
              "triangles_tested")


@numba.njit(cache=True, _nrt=False)
def respond(pos, vel, i, nx, ny, nz, s, thickness, bvx, bvy, bvz, friction):
    """Move point i along n by (thickness − s); make its normal velocity the body's, reduce
    the tangential relative velocity by Coulomb friction (μ·|Δv_n|)."""
    d = thickness - s
    pos[i, 0] += d * nx
    pos[i, 1] += d * ny
    pos[i, 2] += d * nz
    rx = vel[i, 0] - bvx
    ry = vel[i, 1] - bvy
    rz = vel[i, 2] - bvz
    vn = rx * nx + ry * ny + rz * nz
    if vn < 0.0:
        rx -= vn * nx
        ry -= vn * ny
        rz -= vn * nz
        tl = math.sqrt(rx * rx + ry * ry + rz * rz)
        dv = -friction * vn
        if tl <= dv:
            rx = 0.0
            ry = 0.0
            rz = 0.0
        elif tl > 0.0:
            f = 1.0 - dv / tl
            rx *= f
            ry *= f
            rz *= f
        vel[i, 0] = bvx + rx
        vel[i, 1] = bvy + ry
        vel[i, 2] = bvz + rz


@numba.njit(cache=True, _nrt=False)
def _signed(px, py, pz, vb, faces, t, alpha):
    """Signed distance of p to triangle t at time alpha: (p − q)·n_s with q the closest point
    and n_s the interpolated vertex normal there; returns (s, nx, ny, nz, bary v, bary w).
    ``vb`` (N,18): per vertex position, normal, velocity at the previous frame (0–2, 6–8,
    12–14) and the current one (3–5, 9–11, 15–17)."""
    ia = faces[t, 0]
    ib = faces[t, 1]
    ic = faces[t, 2]
    k = 1.0 - alpha
    ax = k * vb[ia, 0] + alpha * vb[ia, 3]
    ay = k * vb[ia, 1] + alpha * vb[ia, 4]
    az = k * vb[ia, 2] + alpha * vb[ia, 5]
    bx = k * vb[ib, 0] + alpha * vb[ib, 3]
    by = k * vb[ib, 1] + alpha * vb[ib, 4]
    bz = k * vb[ib, 2] + alpha * vb[ib, 5]
    cx = k * vb[ic, 0] + alpha * vb[ic, 3]
    cy = k * vb[ic, 1] + alpha * vb[ic, 4]
    cz = k * vb[ic, 2] + alpha * vb[ic, 5]
    v, w = closest_on_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz)
    u = 1.0 - v - w
    qx = ax + v * (bx - ax) + w * (cx - ax)
    qy = ay + v * (by - ay) + w * (cy - ay)
    qz = az + v * (bz - az) + w * (cz - az)
    nx = u * (k * vb[ia, 6] + alpha * vb[ia, 9]) + v * (k * vb[ib, 6] + alpha * vb[ib, 9]) + \
        w * (k * vb[ic, 6] + alpha * vb[ic, 9])
    ny = u * (k * vb[ia, 7] + alpha * vb[ia, 10]) + v * (k * vb[ib, 7] + alpha * vb[ib, 10]) + \
        w * (k * vb[ic, 7] + alpha * vb[ic, 10])
    nz = u * (k * vb[ia, 8] + alpha * vb[ia, 11]) + v * (k * vb[ib, 8] + alpha * vb[ib, 11]) + \
        w * (k * vb[ic, 8] + alpha * vb[ic, 11])
    nl = math.sqrt(nx * nx + ny * ny + nz * nz)
    if nl < 1e-12:  # degenerate: use the face normal
        nx = (by - ay) * (cz - az) - (bz - az) * (cy - ay)
        ny = (bz - az) * (cx - ax) - (bx - ax) * (cz - az)
        nz = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
        nl = math.sqrt(nx * nx + ny * ny + nz * nz) + 1e-300
    nx /= nl
    ny /= nl
    nz /= nl
    s = (px - qx) * nx + (py - qy) * ny + (pz - qz) * nz
    return s, nx, ny, nz, v, w


@numba.njit(cache=True, _nrt=False)
def pack_body(v0, v1, n0, n1, w0, w1, vb, vp):
    """Interleave the two frames' positions, normals, velocities per vertex into ``vb``
    (N,18), so that one vertex is three adjacent cache lines, not six scattered ones; and the
    positions alone into ``vp`` (N,6) float32, small enough to stay in cache during the
    hierarchy walks (which only look at positions)."""
    for i in range(v0.shape[0]):
        for q in range(3):
            vp[i, q] = v0[i, q]
            vp[i, 3 + q] = v1[i, q]
            vb[i, q] = v0[i, q]
            vb[i, 3 + q] = v1[i, q]
            vb[i, 6 + q] = n0[i, q]
            vb[i, 9 + q] = n1[i, q]
            vb[i, 12 + q] = w0[i, q]
            vb[i, 15 + q] = w1[i, q]


@numba.njit(cache=True, _nrt=False)
def object_pass(pos, vel, prev, alpha, alpha_prev, vb, vp, faces, face_part,
                bounds, links, tris, roots, part_active, cloth_lo, cloth_hi, thickness, friction,
                slack, search_radius, max_depth, skip_far, use_cache, reuse_tol, use_clear,
                body_step, cache_tri, cache_p, cache_c, clear, clear_rel, held, stats, stack,
                reach):
    """Object-space collision of every cloth point against the active parts' hierarchies.

    Per point: (1) clearance: while ``clear[i]`` (how much closer the point may come to the
    body's swept leaf boxes of this frame before it could touch; reset every frame) stays
    positive after subtracting the point's motion, or ``clear_rel[i]`` (how much closer it
    may come to the body as it was at the last search) stays positive after subtracting the
    point's motion and ``body_step`` (the farthest any active part's vertex moves in this
    substep), nothing else is done; (2) the cached
    closest triangle is reused while the point moved less than ``reuse_tol`` relative to it;
    (3) else the hierarchies are searched within ``search_radius`` + the point's motion;
    (4) signed distance to the closest triangle, collision and response."""
    n_parts = roots.shape[0]
    any_part = False
    for k in range(n_parts):
        reach[k] = False
        if not part_active[k]:
            continue
        r = roots[k]
        ok = True
        for q in range(3):
            if bounds[r, q] > cloth_hi[q] + search_radius or \
                    bounds[r, 3 + q] < cloth_lo[q] - search_radius:
                ok = False
        reach[k] = ok or not skip_far
        any_part = any_part or reach[k]
    if not any_part:
        stats[ST_SKIPPED] += pos.shape[0]
        return
    touch = thickness + slack
    b = 1.0 - alpha
    for i in range(pos.shape[0]):
        px = pos[i, 0]
        py = pos[i, 1]
        pz = pos[i, 2]
        dx = px - prev[i, 0]
        dy = py - prev[i, 1]
        dz = pz - prev[i, 2]
        move = math.sqrt(dx * dx + dy * dy + dz * dz)
        if use_clear:
            clear[i] -= move
            clear_rel[i] -= move + body_step
            if clear[i] > 0.0 or clear_rel[i] > 0.0:
                stats[ST_CLEAR] += 1
                continue
        r = search_radius + move
        best_d2 = r * r if skip_far else np.inf
        best_t = -1
        searched = False
        # reuse the closest triangle if the point barely moved relative to it
        t = cache_tri[i] if use_cache else -1
        if t >= 0 and part_active[face_part[t]]:
            ia = faces[t, 0]
            ib = faces[t, 1]
            ic = faces[t, 2]
            gx = (b * (vp[ia, 0] + vp[ib, 0] + vp[ic, 0])
                  + alpha * (vp[ia, 3] + vp[ib, 3] + vp[ic, 3])) / 3.0
            gy = (b * (vp[ia, 1] + vp[ib, 1] + vp[ic, 1])
                  + alpha * (vp[ia, 4] + vp[ib, 4] + vp[ic, 4])) / 3.0
            gz = (b * (vp[ia, 2] + vp[ib, 2] + vp[ic, 2])
                  + alpha * (vp[ia, 5] + vp[ib, 5] + vp[ic, 5])) / 3.0
            ex = (px - cache_p[i, 0]) - (gx - cache_c[i, 0])
            ey = (py - cache_p[i, 1]) - (gy - cache_c[i, 1])
            ez = (pz - cache_p[i, 2]) - (gz - cache_c[i, 2])
            if ex * ex + ey * ey + ez * ez < reuse_tol * reuse_tol:
                best_t = t
                stats[ST_REUSED] += 1
        if best_t < 0:
            boxed = False
            lower = best_d2  # squared distance bound to every part's swept leaves
            for k in range(n_parts):
                if not reach[k]:
                    continue
                rt = roots[k]
                if skip_far and box_dist2(px, py, pz, bounds, rt) >= best_d2:
                    continue
                boxed = True
                best_d2, best_t, nv, nt, ld2 = closest_triangle(
                    px, py, pz, vp, faces, alpha, bounds, links, tris, rt, best_d2, best_t,
                    stack)
                lower = min(lower, ld2)
                stats[ST_NODES] += nv
                stats[ST_TRIS] += nt
            searched = True
            if boxed:
                stats[ST_BOXED] += 1
                stats[ST_NARROW] += 1
            else:
                stats[ST_SKIPPED] += 1
            if use_clear and skip_far:
                # no swept leaf box of any part is nearer than √lower during this frame, and
                # no triangle nearer than √best_d2 now
                clear[i] = math.sqrt(lower) - touch
                if best_t < 0:
                    clear_rel[i] = math.sqrt(best_d2) - touch
            if best_t < 0:
                if use_cache:
                    cache_tri[i] = -1
                continue
            if use_cache:
                ia = faces[best_t, 0]
                ib = faces[best_t, 1]
                ic = faces[best_t, 2]
                cache_tri[i] = best_t
                for q in range(3):
                    cache_c[i, q] = (b * (vp[ia, q] + vp[ib, q] + vp[ic, q]) + alpha * (
                        vp[ia, 3 + q] + vp[ib, 3 + q] + vp[ic, 3 + q])) / 3.0
                cache_p[i, 0] = px
                cache_p[i, 1] = py
                cache_p[i, 2] = pz
        s, nx, ny, nz, bv, bw = _signed(px, py, pz, vb, faces, best_t, alpha)
        if s >= touch:
            if use_clear and searched and best_d2 < np.inf:
                # outside: no triangle nearer than √best_d2 now (a point inside has none)
                clear_rel[i] = math.sqrt(best_d2) - touch
            continue
        if s <= -max_depth:
            # deep: a collision only if the point crossed the surface during this substep
            sp, _, _, _, _, _ = _signed(prev[i, 0], prev[i, 1], prev[i, 2], vb, faces, best_t,
                                        alpha_prev)
            if sp < 0.0:
                continue
        held[i] = True
        stats[ST_CONTACT] += 1
        if use_clear:
            clear[i] = 0.0
        if s >= thickness:
            continue  # touching: held, nothing to fix
        bu = 1.0 - bv - bw
        ia = faces[best_t, 0]
        ib = faces[best_t, 1]
        ic = faces[best_t, 2]
        bvx = b * (bu * vb[ia, 12] + bv * vb[ib, 12] + bw * vb[ic, 12]) + \
            alpha * (bu * vb[ia, 15] + bv * vb[ib, 15] + bw * vb[ic, 15])
        bvy = b * (bu * vb[ia, 13] + bv * vb[ib, 13] + bw * vb[ic, 13]) + \
            alpha * (bu * vb[ia, 16] + bv * vb[ib, 16] + bw * vb[ic, 16])
        bvz = b * (bu * vb[ia, 14] + bv * vb[ib, 14] + bw * vb[ic, 14]) + \
            alpha * (bu * vb[ia, 17] + bv * vb[ib, 17] + bw * vb[ic, 17])
        respond(pos, vel, i, nx, ny, nz, s, thickness, bvx, bvy, bvz, friction)


@numba.njit(cache=True, _nrt=False)
def image_pass(pos, vel, alpha, m, D, A, s0, s1, box_lo, box_hi, thickness, friction, slack,
               min_nz, skip_far, held, stats, fw, iw, clear, clear_rel):
    """Image-space collision of every cloth point against front/back depth maps at time
    ``alpha`` between the previous (slot ``s0``) and the current (slot ``s1``) frame's maps.

    ``m`` (3×4) world → map (x col, y row, z = depth towards the front camera). Packed so one
    look-up touches few cache lines: ``D`` (H,W,2 slots,2 sides) float32 depth (side 0 front =
    nearest, 1 back = farthest; −inf/+inf where empty), bilinear over the covered pixels;
    ``A`` (H,W,2 sides,2 slots,6) float32 per-pixel normal (3) and body velocity (3), taken
    from the nearest covered pixel. ``clear``/``clear_rel``: the object pass's clearances
    (empty when there is none), reduced by every push made here."""
    h = D.shape[0]
    w = D.shape[1]
    # workspaces from the caller (this kernel runs without numba's runtime: no allocation)
    acc = fw[0:6]
    wt = fw[6:10]
    gs = fw[10:12]
    gf = fw[12:14]
    gb = fw[14:16]
    ww = fw[16:24].reshape((2, 4))
    ri = iw[0:4]
    ci = iw[4:8]
    okp = iw[8:12]
    cx = m[2, 0]
    cy = m[2, 1]
    cz = m[2, 2]
    reach = (thickness + slack) / min_nz
    for i in range(pos.shape[0]):
        px = pos[i, 0]
        py = pos[i, 1]
        pz = pos[i, 2]
        if skip_far and (px < box_lo[0] or px > box_hi[0] or py < box_lo[1] or
                         py > box_hi[1] or pz < box_lo[2] or pz > box_hi[2]):
            stats[ST_SKIPPED] += 1
            continue
        stats[ST_BOXED] += 1
        x = m[0, 0] * px + m[0, 1] * py + m[0, 2] * pz + m[0, 3]
        y = m[1, 0] * px + m[1, 1] * py + m[1, 2] * pz + m[1, 3]
        z = cx * px + cy * py + cz * pz + m[2, 3]
        if not (x >= 0.0 and x < w and y >= 0.0 and y < h):
            continue
        stats[ST_NARROW] += 1
        fx = x - 0.5
        fy = y - 0.5
        j0 = int(math.floor(fx))
        i0 = int(math.floor(fy))
        tx = fx - j0
        ty = fy - i0
        # bilinear weights of the 2×2 pixel block, per slot zeroed where not covered
        # (written out: numba calls cost more than this work)
        i1 = i0 + 1
        j1 = j0 + 1
        ok0 = i0 >= 0
        ok1 = i1 < h
        okl = j0 >= 0
        okr = j1 < w
        a0 = max(i0, 0)
        b0_ = max(j0, 0)
        a1 = min(i1, h - 1)
        b1_ = min(j1, w - 1)
        wt[0] = (1.0 - tx) * (1.0 - ty)
        wt[1] = tx * (1.0 - ty)
        wt[2] = (1.0 - tx) * ty
        wt[3] = tx * ty
        okp[0] = 1 if (ok0 and okl) else 0
        okp[1] = 1 if (ok0 and okr) else 0
        okp[2] = 1 if (ok1 and okl) else 0
        okp[3] = 1 if (ok1 and okr) else 0
        ri[0] = a0
        ri[1] = a0
        ri[2] = a1
        ri[3] = a1
        ci[0] = b0_
        ci[1] = b1_
        ci[2] = b0_
        ci[3] = b1_
        for u in range(2):
            sl = s0 if u == 0 else s1
            ws = 0.0
            fz = 0.0
            bz = 0.0
            for q in range(4):
                wq = 0.0
                if okp[q] != 0:
                    zf_ = D[ri[q], ci[q], sl, 0]
                    if zf_ > -np.inf:
                        wq = wt[q]
                        fz += wq * zf_
                        bz += wq * D[ri[q], ci[q], sl, 1]
                ww[u, q] = wq
                ws += wq
            gs[u] = ws
            if ws > 0.0:
                gf[u] = fz / ws
                gb[u] = bz / ws
                for q in range(4):
                    ww[u, q] /= ws
        if gs[0] > 0.0 and gs[1] > 0.0:
            ka = 1.0 - alpha
            kb = alpha
        elif gs[1] > 0.0:
            ka = 0.0
            kb = 1.0
        elif gs[0] > 0.0:
            ka = 1.0
            kb = 0.0
        else:
            continue
        zf = ka * gf[0] + kb * gf[1]
        zb = ka * gb[0] + kb * gb[1]
        # beyond reach along the view axis (at a slope n_z ≥ min_nz the gap is ≤ d / min_nz)
        if z >= zf + reach or z <= zb - reach:
            continue
        front = (zf - z) <= (z - zb)
        side = 0 if front else 1
        for q in range(6):
            acc[q] = 0.0
        # normal and velocity from the covered pixel of the block nearest the point (one
        # cache line for both slots; bilinear here would cost four times the memory traffic
        # for attributes that barely change across a pixel)
        for u in range(2):
            k = ka if u == 0 else kb
            if k <= 0.0:
                continue
            sl = s0 if u == 0 else s1
            qb = 0
            for q in range(1, 4):
                if ww[u, q] > ww[u, qb]:
                    qb = q
            for c in range(6):
                acc[c] += k * A[ri[qb], ci[qb], side, sl, c]
        nx = acc[0]
        ny = acc[1]
        nz = acc[2]
        sgn = 1.0 if front else -1.0
        nl = math.sqrt(nx * nx + ny * ny + nz * nz)
        if nl > 1e-12:
            nx /= nl
            ny /= nl
            nz /= nl
        ndc = sgn * (nx * cx + ny * cy + nz * cz)  # > 0 for a surface facing its camera
        if ndc < min_nz:
            # at the silhouette (or a bad normal) lean the normal towards the camera axis
            tx_ = nx - sgn * ndc * cx
            ty_ = ny - sgn * ndc * cy
            tz_ = nz - sgn * ndc * cz
            tl = math.sqrt(tx_ * tx_ + ty_ * ty_ + tz_ * tz_)
            st = math.sqrt(1.0 - min_nz * min_nz)
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
            continue
        held[i] = True
        stats[ST_CONTACT] += 1
        if s < thickness:
            respond(pos, vel, i, nx, ny, nz, s, thickness, acc[3], acc[4], acc[5], friction)
            if clear.shape[0] > 0:
                # the object pass's clearances did not see this push
                clear[i] -= thickness - s
                clear_rel[i] -= thickness - s


@numba.njit(cache=True, _nrt=False)
def gather(m, v, n, w, idx, sv, attrs):
    """Screen positions of vertices ``idx`` under ``m`` and their (normal, velocity)."""
    for k in range(idx.shape[0]):
        i = idx[k]
        x = v[i, 0]
        y = v[i, 1]
        z = v[i, 2]
        for r in range(3):
            sv[k, r] = m[r, 0] * x + m[r, 1] * y + m[r, 2] * z + m[r, 3]
            attrs[k, r] = n[i, r]
            attrs[k, 3 + r] = w[i, r]


@numba.njit(cache=True, _nrt=False)
def bounds(p, lo, hi):
    """Axis-aligned box of points ``p`` into ``lo``/``hi`` (taking the union with what is
    there already)."""
    for i in range(p.shape[0]):
        for q in range(3):
            x = p[i, q]
            if x < lo[q]:
                lo[q] = x
            if x > hi[q]:
                hi[q] = x


@numba.njit(cache=True, _nrt=False)
def bounds_of(p, idx, lo, hi):
    """Like :func:`bounds` over the rows ``idx`` of ``p``."""
    for k in range(idx.shape[0]):
        i = idx[k]
        for q in range(3):
            x = p[i, q]
            if x < lo[q]:
                lo[q] = x
            if x > hi[q]:
                hi[q] = x


@numba.njit(cache=True, _nrt=False)
def max_displacement(a, b, idx):
    """max over vertices idx of |a − b|∞ (did this part move?)."""
    best = 0.0
    for k in range(idx.shape[0]):
        i = idx[k]
        for q in range(3):
            d = abs(a[i, q] - b[i, q])
            if d > best:
                best = d
    return best
