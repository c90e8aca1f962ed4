"""numba kernels of the cloth solver: forces (eq. 2), semi-implicit Euler (eq. 3), strain limits.

All kernels are single-threaded ``@numba.njit(cache=True)`` loops over flat arrays; the solver
(:mod:`catwalk.cloth.solver`) calls :func:`run_steps` once per step (or once for many steps when
no collider needs Python between them).
"""

from __future__ import annotations

import numba
import numpy as np

METHOD_NONE, METHOD_ORDERED, METHOD_VASSILEV, METHOD_PROVOT = 0, 1, 2, 3

STATUS_OK, STATUS_NONFINITE, STATUS_EXPLODED = 0, 1, 2


#: compressive strain over which stretch/shear stiffness blends from k down to compress·k
SOFT_BAND = 0.01



# The velocity strain limits correct at most this much closing speed per spring and step (m/s):
# a spring that starts far beyond its limit (panels placed on the body, a point pushed out by
# the collider, a seam pulling) is brought back over a few steps instead of in one, which would
# throw its points at (excess / dt) — tens of m/s. At rest the excess is far below this cap.
MAX_CORRECTION_SPEED = 2.0

# A seam spring pulls as if its gap were at most this long (m): partners placed far apart
# (a trouser inseam, a sleeve cap) approach at a bounded speed instead of being flung together.
SEAM_REACH = 0.01

# A stretch/shear spring's elastic force stops growing beyond this strain (its energy grows
# linearly): the strain limit keeps springs below τ ≤ 0.1 anyway, and a spring that something
# else stretched far (the collider pushing cloth out of a foot, a weld) would otherwise ring at
# its natural frequency with an amplitude of that stretch: tens of m/s with a stiff fabric.
STRAIN_FORCE_CAP = 0.25


@numba.njit(cache=True, error_model="numpy", inline="always")
def _compressed(e, rest, compress):
    """Spring force / k at a compression e < 0: the stiffness falls linearly from k to
    compress·k over a band of SOFT_BAND·rest (smooth, so the explicit scheme keeps its energy),
    then stays at compress·k."""
    d = SOFT_BAND * rest
    if e > -d:
        return e + (1.0 - compress) * e * e / (2.0 * d)
    return compress * e - (1.0 - compress) * 0.5 * d


@numba.njit(cache=True, error_model="numpy", inline="always")
def _compressed_energy(e, rest, compress):
    d = SOFT_BAND * rest
    if e > -d:
        return 0.5 * e * e + (1.0 - compress) * e * e * e / (6.0 * d)
    e0 = -d
    w0 = 0.5 * e0 * e0 + (1.0 - compress) * e0 * e0 * e0 / (6.0 * d)
    return w0 + 0.5 * compress * (e * e - e0 * e0) - (1.0 - compress) * 0.5 * d * (e - e0)


@numba.njit(cache=True, error_model="numpy")
def accumulate_forces(x, v, mass, sa, sb, rest, k, c, n_lim, compress, gravity, air, seam_a,
                      seam_b, seam_k, seam_c, f):
    """f = Σ springs (eq. 2 + damping along the spring) + seams + m·g − air·m·v.

    Stretch and shear springs (the first ``n_lim``) push back ``compress`` times as hard as they
    pull: woven and knitted fabrics buckle under almost no in-plane compression."""
    n = x.shape[0]
    for i in range(n):
        m = mass[i]
        f[i, 0] = m * (gravity[0] - air * v[i, 0])
        f[i, 1] = m * (gravity[1] - air * v[i, 1])
        f[i, 2] = m * (gravity[2] - air * v[i, 2])
    for s in range(sa.shape[0]):
        a = sa[s]
        b = sb[s]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        ll = np.sqrt(dx * dx + dy * dy + dz * dz)
        if ll < 1e-12:
            continue
        inv = 1.0 / ll
        dx *= inv
        dy *= inv
        dz *= inv
        rv = (v[b, 0] - v[a, 0]) * dx + (v[b, 1] - v[a, 1]) * dy + (v[b, 2] - v[a, 2]) * dz
        e = ll - rest[s]
        if s < n_lim:
            if e < 0.0:
                fs = k[s] * _compressed(e, rest[s], compress) + c[s] * rv
            else:
                fs = k[s] * min(e, STRAIN_FORCE_CAP * rest[s]) + c[s] * rv
        else:
            fs = k[s] * e + c[s] * rv
        f[a, 0] += fs * dx
        f[a, 1] += fs * dy
        f[a, 2] += fs * dz
        f[b, 0] -= fs * dx
        f[b, 1] -= fs * dy
        f[b, 2] -= fs * dz
    for s in range(seam_a.shape[0]):
        a = seam_a[s]
        b = seam_b[s]
        gx = x[b, 0] - x[a, 0]
        gy = x[b, 1] - x[a, 1]
        gz = x[b, 2] - x[a, 2]
        gl = np.sqrt(gx * gx + gy * gy + gz * gz)
        ks = seam_k if gl <= SEAM_REACH else seam_k * SEAM_REACH / gl
        fx = ks * gx + seam_c * (v[b, 0] - v[a, 0])
        fy = ks * gy + seam_c * (v[b, 1] - v[a, 1])
        fz = ks * gz + seam_c * (v[b, 2] - v[a, 2])
        f[a, 0] += fx
        f[a, 1] += fy
        f[a, 2] += fz
        f[b, 0] -= fx
        f[b, 1] -= fy
        f[b, 2] -= fz


@numba.njit(cache=True, error_model="numpy")
def integrate_velocities(v, f, w_int, dt, vmax):
    """v += dt·f/m for free points (eq. 3); returns (status, index of the first bad point)."""
    n = v.shape[0]
    status = 0
    bad = -1
    v2max = vmax * vmax
    for i in range(n):
        wi = w_int[i]
        if wi == 0.0:
            continue
        vx = v[i, 0] + dt * wi * f[i, 0]
        vy = v[i, 1] + dt * wi * f[i, 1]
        vz = v[i, 2] + dt * wi * f[i, 2]
        s = vx * vx + vy * vy + vz * vz
        if not (s <= v2max):  # catches NaN as well
            if status == 0:
                bad = i
                status = 1 if s != s else 2
        v[i, 0] = vx
        v[i, 1] = vy
        v[i, 2] = vz
    return status, bad


@numba.njit(cache=True, error_model="numpy")
def limit_unordered_velocity(x, v, w_lim, sa, sb, rest, n_lim, tau, dt):
    """Vassilev et al. 2001: for each stretch/shear spring in storage order, change the end points'
    velocities along the spring so that its length after the step is at most (1+τ)·rest; the
    change is shared by inverse mass (pinned and held points take none)."""
    inv_dt = 1.0 / dt
    for s in range(n_lim):
        a = sa[s]
        b = sb[s]
        wa = w_lim[a]
        wb = w_lim[b]
        wsum = wa + wb
        if wsum == 0.0:
            continue
        dx = (x[b, 0] + dt * v[b, 0]) - (x[a, 0] + dt * v[a, 0])
        dy = (x[b, 1] + dt * v[b, 1]) - (x[a, 1] + dt * v[a, 1])
        dz = (x[b, 2] + dt * v[b, 2]) - (x[a, 2] + dt * v[a, 2])
        ll = np.sqrt(dx * dx + dy * dy + dz * dz)
        lim = (1.0 + tau) * rest[s]
        if ll <= lim:
            continue
        g = min(ll - lim, MAX_CORRECTION_SPEED * dt) * inv_dt / (ll * wsum)
        v[a, 0] += wa * g * dx
        v[a, 1] += wa * g * dy
        v[a, 2] += wa * g * dz
        v[b, 0] -= wb * g * dx
        v[b, 1] -= wb * g * dy
        v[b, 2] -= wb * g * dz


@numba.njit(cache=True, error_model="numpy")
def limit_ordered_velocity(x, v, xp, w_lim, rest, tau, dt, ord_pts, ord_ptr, ord_spr, ord_oth,
                           ord_cross, sweeps, react, r, share):
    """The paper's pass: points in order from the high-tension centres outward; each point's
    velocity is changed along its springs to already-processed points (which are not moved
    again in this pass), so that none of those springs ends the step longer than (1+τ)·rest.

    ``xp`` receives the predicted positions x + dt·v. A point with several such springs takes
    the mean of their corrections, up to ``sweeps`` times (a point whose parents disagree — where
    the fronts from two centres meet — settles on a compromise instead of being thrown back and
    forth); with ``share``, what is still left over is then shared with the parents by inverse
    mass. The opposite impulse, × ``react``, goes to each parent's velocity *after* the position
    update (accumulated in ``r``), as Müller et al. 2012 do for follow-the-leader, so that
    momentum is kept over steps while this step's positions satisfy the limit.
    """
    inv_dt = 1.0 / dt
    n = x.shape[0]
    for i in range(n):
        xp[i, 0] = x[i, 0] + dt * v[i, 0]
        xp[i, 1] = x[i, 1] + dt * v[i, 1]
        xp[i, 2] = x[i, 2] + dt * v[i, 2]
    maxp = 1
    for k in range(ord_pts.shape[0]):
        maxp = max(maxp, ord_ptr[k + 1] - ord_ptr[k])
    qbuf = np.empty(maxp, dtype=np.int64)
    dbuf = np.empty((maxp, 3))
    for k in range(ord_pts.shape[0]):
        p = ord_pts[k]
        wp = w_lim[p]
        if wp == 0.0:
            continue
        j0 = ord_ptr[k]
        j1 = ord_ptr[k + 1]
        if j0 == j1:
            continue
        has_cross = False
        for j in range(j0, j1):
            if ord_cross[j]:
                has_cross = True
        for _sw in range(sweeps):
            cnt = 0
            nr = 0
            sx = 0.0
            sy = 0.0
            sz = 0.0
            for j in range(j0, j1):
                if ord_cross[j]:
                    continue
                q = ord_oth[j]
                dx = xp[p, 0] - xp[q, 0]
                dy = xp[p, 1] - xp[q, 1]
                dz = xp[p, 2] - xp[q, 2]
                ll = np.sqrt(dx * dx + dy * dy + dz * dz)
                lim = (1.0 + tau) * rest[ord_spr[j]]
                if ll <= lim:
                    continue
                g = min(ll - lim, MAX_CORRECTION_SPEED * dt) / ll
                sx += g * dx
                sy += g * dy
                sz += g * dz
                cnt += 1
                if react > 0.0 and w_lim[q] > 0.0:
                    qbuf[nr] = q
                    dbuf[nr, 0] = g * dx
                    dbuf[nr, 1] = g * dy
                    dbuf[nr, 2] = g * dz
                    nr += 1
            if cnt == 0:
                break
            inv = 1.0 / cnt
            xp[p, 0] -= sx * inv
            xp[p, 1] -= sy * inv
            xp[p, 2] -= sz * inv
            v[p, 0] -= sx * inv * inv_dt
            v[p, 1] -= sy * inv * inv_dt
            v[p, 2] -= sz * inv * inv_dt
            for t in range(nr):
                q = qbuf[t]
                gq = react * inv * inv_dt * w_lim[q] / wp
                r[q, 0] += gq * dbuf[t, 0]
                r[q, 1] += gq * dbuf[t, 1]
                r[q, 2] += gq * dbuf[t, 2]
        if share or has_cross:
            for j in range(j0, j1):
                if not (share or ord_cross[j]):
                    continue
                q = ord_oth[j]
                wq = w_lim[q]
                dx = xp[p, 0] - xp[q, 0]
                dy = xp[p, 1] - xp[q, 1]
                dz = xp[p, 2] - xp[q, 2]
                ll = np.sqrt(dx * dx + dy * dy + dz * dz)
                lim = (1.0 + tau) * rest[ord_spr[j]]
                if ll <= lim:
                    continue
                g = min(ll - lim, MAX_CORRECTION_SPEED * dt) / (ll * (wp + wq))
                gp = wp * g
                gq = wq * g
                xp[p, 0] -= gp * dx
                xp[p, 1] -= gp * dy
                xp[p, 2] -= gp * dz
                v[p, 0] -= gp * dx * inv_dt
                v[p, 1] -= gp * dy * inv_dt
                v[p, 2] -= gp * dz * inv_dt
                xp[q, 0] += gq * dx
                xp[q, 1] += gq * dy
                xp[q, 2] += gq * dz
                v[q, 0] += gq * dx * inv_dt
                v[q, 1] += gq * dy * inv_dt
                v[q, 2] += gq * dz * inv_dt


@numba.njit(cache=True, error_model="numpy")
def limit_provot_positions(x, v, w_lim, sa, sb, rest, n_lim, tau, dt, iterations):
    """Provot 1995: after the position update, move the end points of every over-long
    stretch/shear spring towards each other (shared by inverse mass), in storage order, repeated
    ``iterations`` times; the velocities take the same change / dt so that they stay consistent
    with the positions (semi-implicit Euler needs it to stay stable)."""
    inv_dt = 1.0 / dt
    for _it in range(iterations):
        changed = False
        for s in range(n_lim):
            a = sa[s]
            b = sb[s]
            wa = w_lim[a]
            wb = w_lim[b]
            wsum = wa + wb
            if wsum == 0.0:
                continue
            dx = x[b, 0] - x[a, 0]
            dy = x[b, 1] - x[a, 1]
            dz = x[b, 2] - x[a, 2]
            ll = np.sqrt(dx * dx + dy * dy + dz * dz)
            lim = (1.0 + tau) * rest[s]
            if ll <= lim:
                continue
            changed = True
            g = (ll - lim) / (ll * wsum)
            ga = wa * g
            gb = wb * g
            x[a, 0] += ga * dx
            x[a, 1] += ga * dy
            x[a, 2] += ga * dz
            x[b, 0] -= gb * dx
            x[b, 1] -= gb * dy
            x[b, 2] -= gb * dz
            v[a, 0] += ga * dx * inv_dt
            v[a, 1] += ga * dy * inv_dt
            v[a, 2] += ga * dz * inv_dt
            v[b, 0] -= gb * dx * inv_dt
            v[b, 1] -= gb * dy * inv_dt
            v[b, 2] -= gb * dz * inv_dt
        if not changed:
            break


@numba.njit(cache=True, error_model="numpy")
def run_steps(x, v, xprev, f, mass, w_int, w_lim, sa, sb, rest, k, c, n_lim, compress, gravity,
              air,
              seam_a, seam_b, seam_k, seam_c, dt, nsteps, method, tau, ord_pts, ord_ptr,
              ord_spr, ord_oth, ord_cross, sweeps, react, r, xp, share, passes, provot_iterations,
              vmax, out_bad):
    """``nsteps`` steps of forces + semi-implicit Euler + the chosen strain limit.

    Returns a status (0 ok, 1 non-finite, 2 a speed above ``vmax``) and writes the step and the
    point where it happened to ``out_bad``; on a bad status it stops before moving positions.
    """
    n = x.shape[0]
    for step in range(nsteps):
        accumulate_forces(x, v, mass, sa, sb, rest, k, c, n_lim, compress, gravity, air, seam_a,
                          seam_b, seam_k, seam_c, f)
        status, bad = integrate_velocities(v, f, w_int, dt, vmax)
        if status != 0:
            out_bad[0] = step
            out_bad[1] = bad
            return status
        if method == METHOD_ORDERED:
            if react > 0.0:
                r[:, :] = 0.0
            for _pass in range(passes):
                limit_ordered_velocity(x, v, xp, w_lim, rest, tau, dt, ord_pts, ord_ptr,
                                       ord_spr, ord_oth, ord_cross, sweeps, react, r, share)
        elif method == METHOD_VASSILEV:
            limit_unordered_velocity(x, v, w_lim, sa, sb, rest, n_lim, tau, dt)
        for i in range(n):
            for q in range(3):
                xprev[i, q] = x[i, q]
                x[i, q] += dt * v[i, q]
        if method == METHOD_ORDERED and react > 0.0:
            for i in range(n):
                for q in range(3):
                    v[i, q] += r[i, q]
        if method == METHOD_PROVOT:
            limit_provot_positions(x, v, w_lim, sa, sb, rest, n_lim, tau, dt, provot_iterations)
    for i in range(n):
        for q in range(3):
            if not np.isfinite(x[i, q]):
                out_bad[0] = nsteps - 1
                out_bad[1] = i
                return STATUS_NONFINITE
    return STATUS_OK


@numba.njit(cache=True, error_model="numpy")
def tension_order(n, adj_ptr, adj_spring, adj_other, centre, x):
    """Breadth-first order over the stretch/shear spring graph from the centres.

    Returns ``(ord_pts, ord_ptr, ord_spr, ord_oth, level, cross)``: every point in processing
    order (centres first), and for the k-th point the springs (``ord_spr[ord_ptr[k]:ord_ptr[k+1]]``)
    linking it to points that come before it, with those points (``ord_oth``); ``level`` is each
    point's breadth-first distance from the centres. Centres joined by springs form one cluster
    and every point belongs to the cluster it was reached from; ``cross`` marks springs to an
    earlier point of another cluster (where two fronts meet), which the pass corrects
    symmetrically. A connected piece with no centre is seeded at its point nearest its
    centroid.
    """
    rank = np.full(n, -1, dtype=np.int64)
    level = np.zeros(n, dtype=np.int64)
    queue = np.empty(n, dtype=np.int32)
    cluster = np.full(n, -1, dtype=np.int64)
    tail = 0
    ncl = 0
    for i in range(n):
        if centre[i] and cluster[i] < 0:
            # a cluster: centres joined by springs (the points held by one body part, ...)
            cluster[i] = ncl
            rank[i] = tail
            queue[tail] = i
            tail += 1
            h2 = tail - 1
            while h2 < tail:
                p = queue[h2]
                h2 += 1
                for j in range(adj_ptr[p], adj_ptr[p + 1]):
                    q = adj_other[j]
                    if centre[q] and cluster[q] < 0:
                        cluster[q] = ncl
                        rank[q] = tail
                        queue[tail] = q
                        tail += 1
            ncl += 1
    head = 0
    comp = np.empty(n, dtype=np.int32)
    seen = np.zeros(n, dtype=np.uint8)
    next_free = 0
    while True:
        while head < tail:
            p = queue[head]
            head += 1
            for j in range(adj_ptr[p], adj_ptr[p + 1]):
                q = adj_other[j]
                if rank[q] < 0:
                    rank[q] = tail
                    level[q] = level[p] + 1
                    cluster[q] = cluster[p]
                    queue[tail] = q
                    tail += 1
        if tail >= n:
            break
        while rank[next_free] >= 0:
            next_free += 1
        # collect the unreached piece containing next_free, seed it at its middle
        nc = 1
        comp[0] = next_free
        seen[next_free] = 1
        r = 0
        cx = 0.0
        cy = 0.0
        cz = 0.0
        while r < nc:
            p = comp[r]
            r += 1
            cx += x[p, 0]
            cy += x[p, 1]
            cz += x[p, 2]
            for j in range(adj_ptr[p], adj_ptr[p + 1]):
                q = adj_other[j]
                if rank[q] < 0 and seen[q] == 0:
                    seen[q] = 1
                    comp[nc] = q
                    nc += 1
        cx /= nc
        cy /= nc
        cz /= nc
        best = comp[0]
        bd = 1e300
        for r in range(nc):
            p = comp[r]
            d = (x[p, 0] - cx) ** 2 + (x[p, 1] - cy) ** 2 + (x[p, 2] - cz) ** 2
            if d < bd:
                bd = d
                best = p
        rank[best] = tail
        queue[tail] = best
        cluster[best] = ncl
        ncl += 1
        tail += 1
    ptr = np.zeros(n + 1, dtype=np.int32)
    for k in range(n):
        p = queue[k]
        cnt = 0
        for j in range(adj_ptr[p], adj_ptr[p + 1]):
            q = adj_other[j]
            if rank[q] < k:
                cnt += 1
        ptr[k + 1] = ptr[k] + cnt
    spr = np.empty(ptr[n], dtype=np.int32)
    oth = np.empty(ptr[n], dtype=np.int32)
    cross = np.zeros(ptr[n], dtype=np.uint8)
    for k in range(n):
        p = queue[k]
        o = ptr[k]
        for j in range(adj_ptr[p], adj_ptr[p + 1]):
            q = adj_other[j]
            if rank[q] < k:
                spr[o] = adj_spring[j]
                oth[o] = q
                cross[o] = cluster[q] != cluster[p] and not centre[q]
                o += 1
    return queue, ptr, spr, oth, level, cross


@numba.njit(cache=True, error_model="numpy")
def max_strain(x, sa, sb, rest, n_lim):
    """max over stretch/shear springs of |x_b − x_a| / rest − 1."""
    worst = -1.0
    for s in range(n_lim):
        a = sa[s]
        b = sb[s]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        e = np.sqrt(dx * dx + dy * dy + dz * dz) / rest[s] - 1.0
        if e > worst:
            worst = e
    return worst


@numba.njit(cache=True, error_model="numpy")
def spring_energy(x, sa, sb, rest, k, n_lim, compress):
    """Elastic energy of the springs (compressed stretch/shear springs at ``compress`` × k)."""
    e = 0.0
    for s in range(sa.shape[0]):
        a = sa[s]
        b = sb[s]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        d = np.sqrt(dx * dx + dy * dy + dz * dz) - rest[s]
        cap = STRAIN_FORCE_CAP * rest[s]
        if d < 0.0 and s < n_lim:
            e += k[s] * _compressed_energy(d, rest[s], compress)
        elif d > cap and s < n_lim:
            e += k[s] * cap * (d - 0.5 * cap)
        else:
            e += 0.5 * k[s] * d * d
    return e


@numba.njit(cache=True, error_model="numpy")
def shadow_area(x, z, tris, lo_x, lo_z, pixel, nx, nz):
    """Area covered by the triangles' projection on the XZ plane, by rasterising them on an
    ``nx`` × ``nz`` grid of square pixels (side ``pixel``) from (lo_x, lo_z); pixel centres."""
    cover = np.zeros((nz, nx), dtype=np.uint8)
    for t in range(tris.shape[0]):
        a = tris[t, 0]
        b = tris[t, 1]
        c = tris[t, 2]
        ax = (x[a] - lo_x) / pixel
        az = (z[a] - lo_z) / pixel
        bx = (x[b] - lo_x) / pixel
        bz = (z[b] - lo_z) / pixel
        cx = (x[c] - lo_x) / pixel
        cz = (z[c] - lo_z) / pixel
        area = (bx - ax) * (cz - az) - (bz - az) * (cx - ax)
        if area == 0.0:
            continue
        i0 = max(int(np.floor(min(ax, bx, cx))), 0)
        i1 = min(int(np.ceil(max(ax, bx, cx))), nx - 1)
        j0 = max(int(np.floor(min(az, bz, cz))), 0)
        j1 = min(int(np.ceil(max(az, bz, cz))), nz - 1)
        for j in range(j0, j1 + 1):
            pz = j + 0.5
            for i in range(i0, i1 + 1):
                px = i + 0.5
                w0 = (bx - px) * (cz - pz) - (bz - pz) * (cx - px)
                w1 = (cx - px) * (az - pz) - (cz - pz) * (ax - px)
                w2 = (ax - px) * (bz - pz) - (az - pz) * (bx - px)
                if area > 0:
                    if w0 >= 0 and w1 >= 0 and w2 >= 0:
                        cover[j, i] = 1
                elif w0 <= 0 and w1 <= 0 and w2 <= 0:
                    cover[j, i] = 1
    total = 0
    for j in range(nz):
        for i in range(nx):
            total += cover[j, i]
    return total * pixel * pixel
