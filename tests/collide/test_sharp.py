"""The body's side of the collision: a sharp body vertex (a bust point) that comes up through
the middle of a cloth triangle whose three points are all outside the body."""

import numpy as np
import pytest

from catwalk.collide import make_collider
from catwalk.collide.shapes import sphere
from catwalk.errors import CatwalkError

THICK = 0.004


def _scene():
    v, f = sphere(radius=0.1, n_around=96, n_rings=48)   # vertices 6.5 mm apart
    v = v.copy()
    tip = int(np.argmax(v[:, 2]))               # the +z pole
    v[tip] *= 1.1                               # a bump 1 cm high, 6.5 mm round
    # a flat cloth 6 mm over the sphere's pole: the bump's tip is 4 mm through it, at the
    # centroid of a triangle of a 3 cm grid (the nearest cloth point 1.4 cm from it, beyond
    # the bump: every cloth point is 7 mm or more outside the body)
    g = np.arange(-0.06, 0.0601, 0.03)
    xs, ys = np.meshgrid(g - 0.02, g - 0.01, indexing="ij")
    x = np.stack([xs.ravel(), ys.ravel(), np.full(xs.size, 0.106)], axis=1)
    n = len(g)
    tris = []
    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1
            tris += [(a, b, c), (a, c, d)]
    return v, f, tip, np.ascontiguousarray(x), np.array(tris)


def _cloth_height_over(x, tris, px, py):
    for t in tris:
        a, b, c = x[t]
        m = np.array([[b[0] - a[0], c[0] - a[0]], [b[1] - a[1], c[1] - a[1]]])
        u, w = np.linalg.solve(m, [px - a[0], py - a[1]])
        if u >= -1e-9 and w >= -1e-9 and u + w <= 1 + 1e-9:
            return a[2] + u * (b[2] - a[2]) + w * (c[2] - a[2])
    raise AssertionError("no triangle over the point")


@pytest.mark.parametrize("mode", ["object", "hybrid", "image"])
def test_a_sharp_vertex_through_a_cloth_triangle_pushes_it_out(mode):
    v, f, tip, x, tris = _scene()
    col = make_collider(mode, f, np.zeros(len(v), np.int8), thickness=THICK)
    col.update(v, np.zeros_like(v))
    before = x.copy()
    # the point-based resolve sees nothing: every cloth point is outside the body
    held = col.resolve(x, np.zeros_like(x), before, alpha=1.0)
    np.testing.assert_array_equal(x, before)
    assert not held.any()
    assert _cloth_height_over(x, tris, *v[tip, :2]) < v[tip, 2]      # the tip is through
    n = col.push_off_sharp(x, tris)
    assert n >= 1
    assert tip in col._sharp and len(col._sharp) < 10   # the bump, not the smooth sphere
    # the triangle over the tip is now the thickness out (the tip's normal is +z)
    assert _cloth_height_over(x, tris, *v[tip, :2]) - v[tip, 2] == pytest.approx(THICK, abs=2e-4)
    far = np.hypot(before[:, 0] - v[tip, 0], before[:, 1] - v[tip, 1]) > 0.025
    np.testing.assert_array_equal(x[far], before[far])
    assert col.push_off_sharp(x, tris) == 0             # done: nothing more to push
    assert col.timings.sharp_pushes == n


def test_push_off_sharp_bad_input():
    v, f, tip, x, tris = _scene()
    col = make_collider("object", f, np.zeros(len(v), np.int8))
    with pytest.raises(CatwalkError, match="update"):
        col.push_off_sharp(x, tris)
    col.update(v)
    with pytest.raises(CatwalkError, match="triangles"):
        col.push_off_sharp(x, tris + len(x))
    with pytest.raises(CatwalkError, match="float64"):
        col.push_off_sharp(x.astype(np.float32), tris)
    assert col.push_off_sharp(x, tris[:0]) == 0


def test_a_cloth_spread_over_kilometres_costs_no_more_memory():
    """The cloth-point grid is capped (a blown-up cloth must not allocate a huge grid)."""
    v, f, tip, x, tris = _scene()
    col = make_collider("object", f, np.zeros(len(v), np.int8), thickness=THICK)
    col.update(v)
    far = np.array([[5000.0, 5000.0, 5000.0], [-5000.0, -5000.0, -5000.0]])
    xx = np.ascontiguousarray(np.concatenate([x, far]))
    assert col.push_off_sharp(xx, tris) >= 1          # the triangle over the tip still found
    np.testing.assert_array_equal(xx[-2:], far)
