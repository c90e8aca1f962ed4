import numpy as np

from catwalk.collide import bvh as B
from catwalk.collide.bvh import (
    LINK_COUNT,
    LINK_LEFT,
    LINK_RIGHT,
    LINK_START,
    NB_COLUMNS,
    NB_FRAME,
    NB_HI0,
    NB_HI1,
    NB_LO0,
    NB_LO1,
    NB_SPEED,
    NL_CENTRE,
    NL_SPEED,
    VP_X0,
    VP_X1,
)
from catwalk.collide.collider import face_parts
from catwalk.collide.shapes import Mannequin, walk_pose


def _body():
    m = Mannequin(0.6)
    return m, face_parts(m.faces, m.parts)


def _leaf_refs(h, n):
    """Leaf n's triangle references."""
    return h.tris[h.links[n, LINK_START]:h.links[n, LINK_START] + h.links[n, LINK_COUNT]]


def _positions(v0, v1):
    """The two frames' positions packed as the kernels take them (``vp``)."""
    vp = np.zeros((len(v0), 6), np.float32)
    vp[:, VP_X0:VP_X0 + 3] = v0
    vp[:, VP_X1:VP_X1 + 3] = v1
    return vp


def test_every_triangle_is_in_a_leaf_of_its_part_and_duplication_is_bounded():
    m, fp = _body()
    parts = {p: np.nonzero(fp == p)[0] for p in range(1, 5)}
    h = B.build(m.rest, m.faces, parts, leaf_size=8)
    assert h.root[0] == h.end[0]  # no torso hierarchy asked for
    for p, ids in parts.items():
        nodes = np.arange(h.root[p], h.end[p])
        leaves = nodes[h.links[nodes, LINK_LEFT] < 0]
        got = np.concatenate([_leaf_refs(h, n) for n in leaves])
        assert set(got) == set(ids)
        # children come after their parent (pre-order), inside the part's range
        inner = nodes[h.links[nodes, LINK_LEFT] >= 0]
        kids = h.links[inner][:, [LINK_LEFT, LINK_RIGHT]]
        assert np.all(kids > inner[:, None])
        assert np.all(kids < h.end[p])
    assert 1.0 <= h.dup < 4.0  # triangles copied across split planes


def test_leaf_vertices_are_each_leafs_distinct_vertices_in_order():
    m, fp = _body()
    parts = {p: np.nonzero(fp == p)[0] for p in range(1, 5)}
    h = B.build(m.rest, m.faces, parts, leaf_size=8)
    start, lv = B.leaf_vertices(h, m.faces)
    assert start[0] == 0 and start[-1] == len(lv) and np.all(np.diff(start) >= 0)
    for n in range(h.n_nodes):
        got = lv[start[n]:start[n + 1]]
        if h.links[n, LINK_LEFT] >= 0:
            assert len(got) == 0
            continue
        assert np.array_equal(got, np.unique(m.faces[_leaf_refs(h, n)]))


def test_refit_boxes_contain_each_frames_triangles():
    m, fp = _body()
    parts = {p: np.nonzero(fp == p)[0] for p in range(1, 5)}
    h = B.build(m.rest, m.faces, parts)
    v0 = m.vertices(walk_pose(0.0))
    v1 = m.vertices(walk_pose(0.1))
    vp = _positions(v0, v1)
    lv_start, lv = B.leaf_vertices(h, m.faces)
    nb = np.zeros((h.n_nodes, NB_COLUMNS), np.float32)
    for p in parts:
        for col in (0, 1):
            B.refit_frame(vp, col, lv_start, lv, h.links, nb, h.root[p], h.end[p])
    for col, v in ((0, v0), (1, v1)):
        o = NB_FRAME * col
        lo, hi = nb[:, NB_LO0 + o:NB_LO0 + o + 3], nb[:, NB_HI0 + o:NB_HI0 + o + 3]
        for n in range(h.n_nodes):
            if h.links[n, LINK_LEFT] >= 0:
                kids = h.links[n, [LINK_LEFT, LINK_RIGHT]]
                assert np.all(lo[n] <= lo[kids].min(axis=0))
                assert np.all(hi[n] >= hi[kids].max(axis=0))
                continue
            t = _leaf_refs(h, n)
            pts = v[m.faces[t]].reshape(-1, 3).astype(np.float32)
            assert np.all(pts >= lo[n]) and np.all(pts <= hi[n])


def _brute(p, v, faces, ids):
    best = (np.inf, -1)
    for t in ids:
        a, b, c = v[faces[t]]
        vv, ww = B.closest_on_triangle(*p, *a, *b, *c)
        q = a + vv * (b - a) + ww * (c - a)
        d = float(np.sum((p - q) ** 2))
        if d < best[0]:
            best = (d, t)
    return best


def test_closest_on_triangle_regions():
    a, b, c = np.array([0.0, 0, 0]), np.array([1.0, 0, 0]), np.array([0.0, 1, 0])
    cases = {(0.2, 0.2, 1.0): (0.2, 0.2), (-1.0, -1.0, 0.0): (0.0, 0.0),
             (2.0, -0.5, 0.0): (1.0, 0.0), (-0.5, 3.0, 0.3): (0.0, 1.0),
             (0.5, -1.0, 0.0): (0.5, 0.0), (1.0, 1.0, 0.0): (0.5, 0.5)}
    for p, (vv, ww) in cases.items():
        got = B.closest_on_triangle(*p, *a, *b, *c)
        q = a + got[0] * (b - a) + got[1] * (c - a)
        np.testing.assert_allclose(q, a + vv * (b - a) + ww * (c - a), atol=1e-12)


def test_closest_triangle_t_matches_brute_force_and_box_distances_are_exact():
    """The walk the object pass uses (the nodes' table: two frames' node boxes blended, the
    boxes swept over the frame; a leaf's triangles read through their leaf-order vertex
    references) and its branch-free box distances."""
    m, fp = _body()
    arm = np.nonzero(fp == 1)[0]
    h = B.build(m.rest, m.faces, {1: arm})
    v0 = m.vertices(walk_pose(0.0))
    v1 = m.vertices(walk_pose(0.1))
    vp = _positions(v0, v1)
    lv_start, lv = B.leaf_vertices(h, m.faces)
    nb = np.zeros((h.n_nodes, NB_COLUMNS), np.float32)
    a, e = h.root[1], h.end[1]
    B.refit_frame(vp, 0, lv_start, lv, h.links, nb, a, e)
    B.refit_frame(vp, 1, lv_start, lv, h.links, nb, a, e)
    ref = np.zeros(3)
    B.node_speeds(vp, ref, lv_start, lv, h.links, nb, a, e)
    lf = np.ascontiguousarray(m.faces[h.tris], dtype=np.int32)
    rng = np.random.default_rng(1)
    stack = np.empty(B.STACK_SIZE, np.int64)
    spd = np.zeros(2)
    centre = v0[m.faces[arm]].reshape(-1, 3).mean(axis=0)
    w = vp.astype(np.float64)
    r = np.array([0.01, -0.02, 0.005])
    nbl = np.zeros((h.n_nodes, B.NODE_COLUMNS))
    vpl = np.zeros((len(vp), 3))
    vidx = np.unique(m.faces[arm])
    B.swept_boxes(nb, r, a, e, nbl)
    for _ in range(60):
        alpha = rng.random()
        B.blend_at(vp, nb, a, e, vidx, alpha, nbl, vpl)
        blended = (1 - alpha) * w[:, VP_X0:VP_X0 + 3] + alpha * w[:, VP_X1:VP_X1 + 3]
        np.testing.assert_allclose(vpl[vidx], blended[vidx], rtol=0, atol=1e-12)
        p = centre + rng.normal(0, 0.08, 3)
        d2, t, nodes, tested, frame_d2 = B.closest_triangle_t(
            *p, B.TreeAt(vpl, lf, nbl, h.links, h.tris), h.root[1], B.SearchTime(alpha, *r, 1.0),
            np.inf, -1, stack, spd)
        bd2, bt = _brute(p, blended, m.faces, arm)
        assert np.isclose(d2, bd2, rtol=1e-9, atol=1e-15) and t in set(arm)
        assert tested < len(arm) / 3
        for nd in rng.integers(a, e, 8):
            b = nb[nd].astype(np.float64)
            lo0, hi0 = b[NB_LO0:NB_LO0 + 3], b[NB_HI0:NB_HI0 + 3]
            lo1, hi1 = b[NB_LO1:NB_LO1 + 3], b[NB_HI1:NB_HI1 + 3]
            lo = (1 - alpha) * lo0 + alpha * lo1
            hi = (1 - alpha) * hi0 + alpha * hi1
            want = np.sum(np.maximum(np.maximum(lo - p, p - hi), 0.0) ** 2)
            assert np.isclose(B.box_d2(*p, nbl, nd), want, rtol=1e-12, atol=1e-18)
            # (the centre is summed in float32, as the node boxes are kept)
            np.testing.assert_allclose(nbl[nd, NL_CENTRE:NL_CENTRE + 3], 0.5 * (lo + hi),
                                       rtol=0, atol=1e-6)
            c = p - alpha * r
            lo = np.minimum(lo0, lo1 - r)
            hi = np.maximum(hi0, hi1 - r)
            want = np.sum(np.maximum(np.maximum(lo - c, c - hi), 0.0) ** 2)
            assert np.isclose(B.swept_d2(*c, nbl, nd), want, rtol=1e-12, atol=1e-18)
            assert nbl[nd, NL_SPEED] == nb[nd, NB_SPEED]
