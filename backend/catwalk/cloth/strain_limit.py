"""The strain limits (paper §3): the ordered velocity pass from the tension centres outward
(:func:`tension_order` makes its processing order), Vassilev et al.'s unordered pass and
Provot's iterated position correction, which keep every stretch and shear spring within
(1 + τ)·rest. Shared by every solver: the explicit step ends with one, the other integrators
use the ordered pass as their final clamp."""

from __future__ import annotations

from collections import namedtuple

import numba
import numpy as np

#: the ordered pass's processing order (:func:`tension_order`'s result, named): every point in
#: processing order, the CSR (``ptr``) of each point's springs to earlier points
#: (``springs``) and those points (``others``), each point's distance in springs from the
#: centres (``level``), and which springs join two fronts (``cross``)
ProcessingOrder = namedtuple("ProcessingOrder", "points ptr springs others level cross")

#: the strain-limit methods (``Solver(method=…)``)
METHOD_NONE, METHOD_ORDERED, METHOD_VASSILEV, METHOD_PROVOT = 0, 1, 2, 3


# The velocity strain limits correct at most this much closing speed per spring and step (m/s):
# a spring that starts far beyond its limit (panels placed on the body, a point pushed out by
# the collider, a seam pulling) is brought back over a few steps instead of in one, which would
# throw its points at (excess / dt) — tens of m/s. At rest the excess is far below this cap.
MAX_CORRECTION_SPEED = 2.0


@numba.njit(cache=True, error_model="numpy")
def mark_overstretched(XP, runs, n_runs_lim, rest, tau, dirty):
    """dirty[p] = 1 for both ends of every stretch/shear spring whose predicted length exceeds
    (1+τ)·rest (with a margin of 1e-9, so that no spring the exact test in the ordered pass
    would correct is missed), 0 for all other points."""
    dirty[:] = 0
    x0 = XP[0]
    x1 = XP[1]
    x2 = XP[2]
    c = (1.0 + tau) * (1.0 + tau) * (1.0 - 1e-9)
    maxl = 1
    for q in range(n_runs_lim):
        maxl = max(maxl, runs[q, 3])
    over = np.empty(maxl, dtype=np.uint8)
    for q in range(n_runs_lim):
        s0 = max(runs[q, 0], 0)
        a0 = max(runs[q, 1], 0)
        c0 = max(runs[q, 2], 0)
        nl = runs[q, 3]
        if nl == 1:
            dx = x0[c0] - x0[a0]
            dy = x1[c0] - x1[a0]
            dz = x2[c0] - x2[a0]
            r = rest[s0]
            if dx * dx + dy * dy + dz * dz > c * r * r:
                dirty[a0] = 1
                dirty[c0] = 1
            continue
        for t in range(nl):
            a = a0 + t
            b = c0 + t
            dx = x0[b] - x0[a]
            dy = x1[b] - x1[a]
            dz = x2[b] - x2[a]
            r = rest[s0 + t]
            over[t] = dx * dx + dy * dy + dz * dz > c * r * r
        for t in range(nl):
            dirty[a0 + t] |= over[t]
        for t in range(nl):
            dirty[c0 + t] |= over[t]


@numba.njit(cache=True, error_model="numpy", inline="always")
def _mark_neighbours(p, adj_ptr, adj_other, dirty):
    for j in range(adj_ptr[p], adj_ptr[p + 1]):
        dirty[adj_other[j]] = 1


@numba.njit(cache=True, error_model="numpy")
def limit_ordered_velocity(XP, V, w_lim, dt, ord_pts, ord_ptr, ord_oth, ord_cross, ord_lim,
                           ord_lim2, pt_cross, sweeps, react, R, share, dirty, adj_ptr, adj_other,
                           qbuf, dbuf):
    """The paper's pass: points in order from the high-tension centres outward; each point's
    velocity is changed along its springs to already-processed points (which are not moved
    again in this pass), so that none of those springs ends the step longer than (1+τ)·rest.

    ``XP`` holds the predicted positions x + dt·v (:func:`predict`) and is kept up to date. A
    point with several such springs takes the mean of their corrections, up to ``sweeps`` times
    (a point whose parents disagree — where the fronts from two centres meet — settles on a
    compromise instead of being thrown back and forth); with ``share``, what is still left over
    is then shared with the parents by inverse mass. The opposite impulse, × ``react``, goes to
    each parent's velocity *after* the position update (accumulated in ``R``), as Müller et al.
    2012 do for follow-the-leader, so that momentum is kept over steps while this step's
    positions satisfy the limit. ``ord_lim`` is (1+τ)·rest of each entry's spring and
    ``ord_lim2`` a bound a little below its square (a squared length up to it is surely within
    the limit); ``pt_cross`` marks the points with a spring across a cluster boundary
    (``ord_cross``).

    Only points marked in ``dirty`` are visited (:func:`mark_overstretched` marks the ends of
    the springs over the limit; a point that moves here marks its neighbours): any other point
    has no spring over the limit to a processed point and would be left as it is, so the result
    is that of visiting every point.
    """
    inv_dt = 1.0 / dt
    cap = MAX_CORRECTION_SPEED * dt
    xp0 = XP[0]
    xp1 = XP[1]
    xp2 = XP[2]
    v0 = V[0]
    v1 = V[1]
    v2 = V[2]
    for k in range(ord_pts.shape[0]):
        p = ord_pts[k]
        if dirty[p] == 0:
            continue
        wp = w_lim[p]
        if wp == 0.0:
            continue
        j0 = ord_ptr[k]
        j1 = ord_ptr[k + 1]
        if j0 == j1:
            continue
        moved = False
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
                dx = xp0[p] - xp0[q]
                dy = xp1[p] - xp1[q]
                dz = xp2[p] - xp2[q]
                l2 = dx * dx + dy * dy + dz * dz
                if l2 <= ord_lim2[j]:  # surely within the limit: no square root needed
                    continue
                ll = np.sqrt(l2)
                lim = ord_lim[j]
                if ll <= lim:
                    continue
                g = min(ll - lim, cap) / ll
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
            moved = True
            inv = 1.0 / cnt
            xp0[p] -= sx * inv
            xp1[p] -= sy * inv
            xp2[p] -= sz * inv
            v0[p] -= sx * inv * inv_dt
            v1[p] -= sy * inv * inv_dt
            v2[p] -= sz * inv * inv_dt
            for t in range(nr):
                q = qbuf[t]
                gq = react * inv * inv_dt * w_lim[q] / wp
                R[0, q] += gq * dbuf[t, 0]
                R[1, q] += gq * dbuf[t, 1]
                R[2, q] += gq * dbuf[t, 2]
        if share or pt_cross[k]:
            for j in range(j0, j1):
                if not (share or ord_cross[j]):
                    continue
                q = ord_oth[j]
                wq = w_lim[q]
                dx = xp0[p] - xp0[q]
                dy = xp1[p] - xp1[q]
                dz = xp2[p] - xp2[q]
                ll = np.sqrt(dx * dx + dy * dy + dz * dz)
                lim = ord_lim[j]
                if ll <= lim:
                    continue
                moved = True
                g = min(ll - lim, cap) / (ll * (wp + wq))
                gp = wp * g
                gq = wq * g
                xp0[p] -= gp * dx
                xp1[p] -= gp * dy
                xp2[p] -= gp * dz
                v0[p] -= gp * dx * inv_dt
                v1[p] -= gp * dy * inv_dt
                v2[p] -= gp * dz * inv_dt
                xp0[q] += gq * dx
                xp1[q] += gq * dy
                xp2[q] += gq * dz
                v0[q] += gq * dx * inv_dt
                v1[q] += gq * dy * inv_dt
                v2[q] += gq * dz * inv_dt
                _mark_neighbours(q, adj_ptr, adj_other, dirty)
        if moved:
            _mark_neighbours(p, adj_ptr, adj_other, dirty)


@numba.njit(cache=True, error_model="numpy")
def limit_unordered_velocity(X, V, w_lim, sa, sb, rest, n_lim, tau, dt):
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
        dx = (X[0, b] + dt * V[0, b]) - (X[0, a] + dt * V[0, a])
        dy = (X[1, b] + dt * V[1, b]) - (X[1, a] + dt * V[1, a])
        dz = (X[2, b] + dt * V[2, b]) - (X[2, a] + dt * V[2, a])
        ll = np.sqrt(dx * dx + dy * dy + dz * dz)
        lim = (1.0 + tau) * rest[s]
        if ll <= lim:
            continue
        g = min(ll - lim, MAX_CORRECTION_SPEED * dt) * inv_dt / (ll * wsum)
        V[0, a] += wa * g * dx
        V[1, a] += wa * g * dy
        V[2, a] += wa * g * dz
        V[0, b] -= wb * g * dx
        V[1, b] -= wb * g * dy
        V[2, b] -= wb * g * dz


@numba.njit(cache=True, error_model="numpy")
def limit_provot_positions(X, V, w_lim, sa, sb, rest, n_lim, tau, dt, iterations):
    """Provot 1995: after the position update, move the end points of every over-long
    stretch/shear spring towards each other (shared by inverse mass), in storage order, repeated
    ``iterations`` times; the velocities take the same change / dt so that they stay consistent
    with the positions (semi-implicit Euler needs it to stay stable).

    After the first round a spring is measured again only if an end moved since it was last
    measured (``moved``: when each point last moved, counted in spring visits): any other is
    as long as it was then, within its limit, and would be left as it is — the result is that
    of measuring every spring every round."""
    inv_dt = 1.0 / dt
    moved = np.zeros(X.shape[1], dtype=np.int64)
    for it in range(iterations):
        changed = False
        for s in range(n_lim):
            a = sa[s]
            b = sb[s]
            # this spring's visit in the previous round (negative in the first: measure)
            last = (it - 1) * n_lim + s
            if moved[a] <= last and moved[b] <= last:
                continue
            wa = w_lim[a]
            wb = w_lim[b]
            wsum = wa + wb
            if wsum == 0.0:
                continue
            dx = X[0, b] - X[0, a]
            dy = X[1, b] - X[1, a]
            dz = X[2, b] - X[2, a]
            ll = np.sqrt(dx * dx + dy * dy + dz * dz)
            lim = (1.0 + tau) * rest[s]
            if ll <= lim:
                continue
            changed = True
            g = (ll - lim) / (ll * wsum)
            ga = wa * g
            gb = wb * g
            X[0, a] += ga * dx
            X[1, a] += ga * dy
            X[2, a] += ga * dz
            X[0, b] -= gb * dx
            X[1, b] -= gb * dy
            X[2, b] -= gb * dz
            V[0, a] += ga * dx * inv_dt
            V[1, a] += ga * dy * inv_dt
            V[2, a] += ga * dz * inv_dt
            V[0, b] -= gb * dx * inv_dt
            V[1, b] -= gb * dy * inv_dt
            V[2, b] -= gb * dz * inv_dt
            # moved after this visit (the spring itself is measured again next round)
            moved[a] = it * n_lim + s + 1
            moved[b] = it * n_lim + s + 1
        if not changed:
            break


@numba.njit(cache=True, error_model="numpy")
def _order_buffers(ord_pts, ord_ptr):
    """Scratch for the ordered pass: room for the most springs any point has to earlier
    points."""
    maxp = 1
    for o in range(ord_pts.shape[0]):
        maxp = max(maxp, ord_ptr[o + 1] - ord_ptr[o])
    return np.empty(maxp, dtype=np.int64), np.empty((maxp, 3))


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
