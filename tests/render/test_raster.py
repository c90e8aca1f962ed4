import numpy as np
import pytest

from catwalk.collide.shapes import sphere
from catwalk.errors import CatwalkError
from catwalk.geometry.raster import Raster, ortho_view, rasterize, to_screen, vertex_normals


def _sphere_raster(keep, radius=0.5, size=200):
    v, f = sphere((0.0, 0.0, 0.0), radius, n_around=128, n_rings=64)
    cam = ortho_view((-1, -1, -1), (1, 1, 1), "front", (size, size))
    return rasterize(cam.to_screen(v), f, size=(size, size), keep=keep), cam


def test_sphere_is_a_disc_of_the_right_radius():
    r, cam = _sphere_raster("near")
    assert cam.pixel == pytest.approx((0.01, 0.01))  # 2 m over 200 px
    covered = r.covered
    # radius 0.5 m = 50 px: the area of the disc, and no pixel centre beyond it
    radius_px = np.sqrt(covered.sum() / np.pi)
    assert radius_px == pytest.approx(50.0, abs=0.5)
    ii, jj = np.nonzero(covered)
    dist = np.hypot(ii + 0.5 - 100.0, jj + 0.5 - 100.0)
    assert dist.max() <= 50.0
    assert covered[100, 100] and covered[100, 52] and not covered[100, 48]


def test_depth_keeps_nearest_or_farthest():
    near, _ = _sphere_raster("near")
    far, _ = _sphere_raster("far")
    # z points towards the camera (+Z for the front view): near = +r, far = -r at the centre
    assert near.depth[100, 100] == pytest.approx(0.5, abs=2e-3)
    assert far.depth[100, 100] == pytest.approx(-0.5, abs=2e-3)
    assert np.all(near.depth[near.covered] >= far.depth[far.covered])
    assert np.all(np.isneginf(near.depth[~near.covered]))
    assert np.all(np.isposinf(far.depth[~far.covered]))
    # on a sphere the depth at a pixel follows sqrt(r² - d²) (inscribed mesh: a bit less)
    ii, jj = np.nonzero(near.covered)
    d = np.hypot((ii + 0.5 - 100) * 0.01, (jj + 0.5 - 100) * 0.01)
    expect = np.sqrt(np.maximum(0.25 - d**2, 0.0))
    err = expect - near.depth[ii, jj]
    assert err.min() > -1e-9 and np.percentile(err, 90) < 2e-3


def test_overlapping_triangles_depth_order_and_triangle_ids():
    # two big squares at z = 0.2 (tri 0,1) and z = -0.3 (tri 2,3), in screen space
    sq = np.array([[-5, -5], [45, -5], [45, 45], [-5, 45]], float)
    v = np.vstack([np.c_[sq, np.full(4, 0.2)], np.c_[sq, np.full(4, -0.3)]])
    f = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    for faces in (f, f[::-1]):  # order must not matter
        near = rasterize(v, faces, size=(40, 30), keep="near")
        far = rasterize(v, faces, size=(40, 30), keep="far")
        np.testing.assert_allclose(near.depth, 0.2, atol=1e-12)
        np.testing.assert_allclose(far.depth, -0.3, atol=1e-12)
        assert set(np.unique(faces[near.triangle][..., 0])) == {0}
        assert set(np.unique(faces[far.triangle][..., 0])) == {4}


def test_attribute_interpolation_is_exact_for_a_linear_function():
    rng = np.random.default_rng(1)
    v = np.c_[rng.uniform(0, 64, (3, 2)), rng.uniform(-1, 1, 3)]
    coef = np.array([[0.3, -1.2, 2.0], [1.5, 0.25, -4.0]])  # two attributes, a x + b y + c
    attrs = v[:, :2] @ coef[:, :2].T + coef[:, 2]
    r = rasterize(v, [[0, 1, 2]], attrs, size=(64, 64))
    ii, jj = np.nonzero(r.covered)
    assert len(ii) > 50
    px, py = jj + 0.5, ii + 0.5
    expect = np.stack([coef[k, 0] * px + coef[k, 1] * py + coef[k, 2] for k in range(2)], -1)
    np.testing.assert_allclose(r.attributes[ii, jj], expect, atol=1e-9)
    # depth is interpolated the same way: the triangle's plane
    a = np.c_[v[:, :2], np.ones(3)]
    plane = np.linalg.solve(a, v[:, 2])
    np.testing.assert_allclose(r.depth[ii, jj], plane[0] * px + plane[1] * py + plane[2],
                               atol=1e-9)


def test_shared_edges_leave_no_holes_and_buffers_are_reusable():
    # a 2x2 quad grid split into triangles covers its square completely
    v = np.array([[x, y, 0.0] for y in (2.0, 10.0, 18.0) for x in (2.0, 10.0, 18.0)])
    f = []
    for i in range(2):
        for j in range(2):
            a = i * 3 + j
            f += [[a, a + 1, a + 4], [a, a + 4, a + 3]]
    out = Raster.empty(20, 20, 0, "near")
    for _ in range(2):
        r = rasterize(v, f, out=out)
        assert r is out
        assert r.covered[2:18, 2:18].all() and r.covered.sum() == 16 * 16


def test_views_put_the_body_where_expected():
    lo, hi = (-0.5, 0.0, -0.3), (0.5, 1.8, 0.3)
    left_hand = np.array([[0.4, 1.0, 0.0]])  # the body's left is +X
    nose = np.array([[0.0, 1.6, 0.25]])  # the body faces +Z
    front = ortho_view(lo, hi, "front", (100, 200))
    back = ortho_view(lo, hi, "back", (100, 200))
    side = ortho_view(lo, hi, "side", (100, 200))
    assert front.pixel == pytest.approx((0.01, 0.01))  # square pixels: the width is tighter
    assert front.to_screen(left_hand)[0, 0] > 50 > back.to_screen(left_hand)[0, 0]
    assert side.to_screen(nose)[0, 0] < 50  # seen from the left, the face is on the left
    assert front.to_screen(nose)[0, 2] == pytest.approx(0.25)  # depth towards the camera
    assert back.to_screen(nose)[0, 2] == pytest.approx(-0.25)
    # feet low, head high, centred: 1.8 m = 180 px in 200 rows
    s = front.to_screen([[0, 0, 0], [0, 1.8, 0]])
    assert s[0, 1] == pytest.approx(190.0) and s[1, 1] == pytest.approx(10.0)
    yaw = ortho_view(lo, hi, 90.0, (100, 200))
    np.testing.assert_allclose(yaw.matrix, side.matrix)
    stretched = ortho_view(lo, hi, "front", (256, 256), square_pixels=False)
    s = stretched.to_screen([[-0.5, 0.0, 0], [0.5, 1.8, 0]])
    np.testing.assert_allclose(s[:, :2], [[0, 256], [256, 0]], atol=1e-9)
    np.testing.assert_allclose(to_screen(stretched.matrix, s * 0)[0], stretched.matrix[:, 3])


def test_vertex_normals_of_a_sphere_point_out():
    v, f = sphere((0.1, 0.2, 0.3), 0.4)
    n = vertex_normals(v, f)
    radial = (v - (0.1, 0.2, 0.3)) / 0.4
    assert np.min(np.sum(n * radial, axis=1)) > 0.99


def test_bad_input_is_a_catwalk_error():
    with pytest.raises(CatwalkError):
        rasterize(np.zeros((3, 2)), [[0, 1, 2]])
    with pytest.raises(CatwalkError):
        rasterize(np.zeros((3, 3)), [[0, 1, 3]])
    with pytest.raises(CatwalkError):
        rasterize(np.zeros((3, 3)), [[0, 1, 2]], keep="middle")
    with pytest.raises(CatwalkError):
        ortho_view((0, 0, 0), (1, 1, 1), "upside-down")


def test_culling_keeps_the_nearest_and_farthest_layers_of_a_closed_surface():
    from catwalk.geometry.raster import CULL_BACK, CULL_FRONT

    v, f = sphere((0.0, 0.0, 0.0), 0.5, n_around=64, n_rings=32)
    cam = ortho_view((-1, -1, -1), (1, 1, 1), "side", (100, 100))
    sv = cam.to_screen(v)
    near = rasterize(sv, f, size=(100, 100), keep="near")
    near_c = rasterize(sv, f, size=(100, 100), keep="near", cull=CULL_BACK)
    far = rasterize(sv, f, size=(100, 100), keep="far")
    far_c = rasterize(sv, f, size=(100, 100), keep="far", cull=CULL_FRONT)
    assert np.array_equal(near.covered, near_c.covered)
    np.testing.assert_allclose(near.depth[near.covered], near_c.depth[near.covered], atol=1e-12)
    np.testing.assert_allclose(far.depth[far.covered], far_c.depth[far.covered], atol=1e-12)
    # culled the wrong way round, the near map sees the back: the depths flip sign
    wrong = rasterize(sv, f, size=(100, 100), keep="near", cull=CULL_FRONT)
    assert np.all(wrong.depth[wrong.covered] < 0.0 + 1e-3)
