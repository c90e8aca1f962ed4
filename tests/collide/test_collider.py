import numpy as np
import pytest
from scipy.ndimage import binary_dilation

from catwalk.collide import MODES, Skips, make_collider
from catwalk.collide.collider import NO_MASK, face_parts
from catwalk.collide.kernels.stats import STAT_NAMES
from catwalk.collide.object import ObjectCollider
from catwalk.collide.shapes import (
    Mannequin,
    capsule,
    figure10_pose,
    merge,
    notched_prism,
    notched_prism_depth,
    sphere,
    walk_pose,
)
from catwalk.errors import CatwalkError
from catwalk.geometry.raster import ortho_view, rasterize

T = 0.004  # default cloth thickness


def _inscribed(v, f, centre):
    """Distance from centre to the nearest face plane: the mesh's inscribed radius."""
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    return float(np.min(np.einsum("ij,ij->i", a - centre, n)))


def _shell(n, centre, r_lo, r_hi, seed=0):
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return np.asarray(centre) + d * rng.uniform(r_lo, r_hi, n)[:, None]


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("part", [0, 1])
def test_no_point_ends_inside_a_sphere(mode, part):
    centre = np.array([0.0, 1.2, 0.0])
    R = 0.15
    v, f = sphere(centre, R, 64, 32)
    c = make_collider(mode, f, np.full(len(v), part, np.int8))
    c.update(v)
    pos = _shell(2000, centre, R - 0.012, R + 0.03)
    before = pos.copy()
    vel = np.zeros_like(pos)
    held = c.resolve(pos, vel, before.copy())
    r_in = _inscribed(v, f, centre)
    dist = np.linalg.norm(pos - centre, axis=1)
    assert dist.min() >= r_in  # nothing inside the (tessellated) body
    was_inside = np.linalg.norm(before - centre, axis=1) < r_in
    assert was_inside.sum() > 300 and held[was_inside].all()
    # pushed out to the surface plus about the thickness
    assert np.median(dist[was_inside]) == pytest.approx(R + T, abs=0.002)
    # points well clear are untouched and not held
    far = np.linalg.norm(before - centre, axis=1) > R + 0.012
    assert np.array_equal(pos[far], before[far]) and not held[far].any()


@pytest.mark.parametrize("mode", MODES)
def test_no_point_ends_inside_a_capsule(mode):
    a, b, r = np.array([0.0, 0.9, 0.0]), np.array([0.0, 1.4, 0.0]), 0.06
    v, f = capsule(a, b, r, n_around=48, n_cap=10, n_body=20)
    c = make_collider(mode, f, np.full(len(v), 2, np.int8))  # a right arm
    c.update(v)
    rng = np.random.default_rng(3)
    y = rng.uniform(1.0, 1.3, 3000)
    ang = rng.uniform(0, 2 * np.pi, 3000)
    rad = rng.uniform(r - 0.01, r + 0.02, 3000)
    pos = np.c_[rad * np.cos(ang), y, rad * np.sin(ang)]
    c.resolve(pos, np.zeros_like(pos), pos.copy())
    axial = np.hypot(pos[:, 0], pos[:, 2])
    r_in = r * np.cos(np.pi / 48)
    assert axial.min() >= r_in


@pytest.mark.parametrize("mode", MODES)
def test_response_sets_normal_velocity_and_applies_coulomb_friction(mode):
    centre = np.array([0.0, 1.2, 0.0])
    v, f = sphere(centre, 0.15, 96, 48)
    part = 0 if mode != "object" else 3
    c = make_collider(mode, f, np.full(len(v), part, np.int8), friction=0.3)
    body_v = np.zeros_like(v)
    body_v[:, 0] = 0.5  # the body slides along +x at 0.5 m/s
    c.update(v, body_v)
    # a point on the front (normal +z), 2 mm inside, moving into the body
    pos = np.array([[0.0, 1.2, 0.148]])
    vel = np.array([[1.5, 0.0, -2.0]])
    held = c.resolve(pos, vel, pos.copy())
    assert held[0]
    assert pos[0, 2] == pytest.approx(0.15 + T, abs=5e-4)
    # normal velocity becomes the body's (0); relative tangential 1.0 m/s loses 0.3 · 2 m/s
    np.testing.assert_allclose(vel[0], [0.5 + 0.4, 0.0, 0.0], atol=0.02)


@pytest.mark.parametrize("mode", ["object", "hybrid"])
def test_a_limb_at_3_m_s_does_not_tunnel_through_cloth(mode):
    # an arm (capsule, radius 4 cm) sweeps through a sheet of free cloth points at 3 m/s;
    # frames at 30 fps move it 10 cm (more than its diameter); 10 substeps per frame
    r, fps, nsub, speed = 0.04, 30.0, 10, 3.0
    a0, b0 = np.array([0.0, 1.0, -0.2]), np.array([0.0, 1.3, -0.2])
    v_rest, f = capsule(a0, b0, r, n_around=32, n_cap=8, n_body=12)
    c = make_collider(mode, f, np.full(len(v_rest), 1, np.int8))
    xs, ys = np.meshgrid(np.linspace(-0.05, 0.05, 11), np.linspace(1.05, 1.25, 11))
    pos = np.c_[xs.ravel(), ys.ravel(), np.zeros(xs.size)]
    vel = np.zeros_like(pos)
    dt = 1.0 / (fps * nsub)
    n_frames = 6  # the arm's axis goes from z = -0.2 to +0.4
    body_vel = np.tile([0.0, 0.0, speed], (len(v_rest), 1))
    for k in range(n_frames + 1):
        shift = np.array([0.0, 0.0, speed * k / fps])
        c.update(v_rest + shift, body_vel)
        for s in range(1, nsub + 1 if k else 1):
            prev = pos.copy()
            pos += vel * dt
            c.resolve(pos, vel, prev, alpha=s / nsub)
            # after every substep: no point inside the arm at its position then
            z_axis = -0.2 + speed * ((k - 1) / fps + s * dt)
            axial = np.hypot(pos[:, 0], pos[:, 2] - z_axis)
            in_span = (pos[:, 1] > 1.0) & (pos[:, 1] < 1.3)
            assert np.all(axial[in_span] >= r * np.cos(np.pi / 32) - 1e-9)
    # the points in the arm's path were pushed ahead of it, none left behind
    z_end = -0.2 + speed * n_frames / fps
    hit = np.abs(pos[:, 0]) < 0.02
    assert np.all(pos[hit, 2] > z_end + 0.9 * r)


def test_body_motion_is_interpolated_between_frames():
    centre = np.array([0.0, 1.2, 0.0])
    R = 0.1
    v, f = sphere(centre, R, 48, 24)
    for mode in ("object", "image"):
        c = make_collider(mode, f, np.zeros(len(v), np.int8) + (1 if mode == "object" else 0))
        c.update(v)
        for _ in range(4):  # frame 0: four substeps, so the next frame counts in quarters
            p = np.array([[0.0, 1.2, 0.5]])
            c.resolve(p, np.zeros_like(p), p.copy())
        c.update(v + [0.0, 0.0, 0.1])  # the sphere moves 10 cm towards +z
        # at the first substep (alpha = 1/4) the sphere's front is at z = 0.125
        p = np.array([[0.0, 1.2, 0.12]])
        held = c.resolve(p, np.zeros_like(p), p.copy())
        assert held[0] and p[0, 2] == pytest.approx(0.125 + T, abs=1.5e-3)
        # at alpha = 2/4 its front is at 0.15: a point at 0.135 is inside again
        p = np.array([[0.0, 1.2, 0.135]])
        held = c.resolve(p, np.zeros_like(p), p.copy())
        assert held[0] and p[0, 2] == pytest.approx(0.15 + T, abs=1.5e-3)
        # an explicit alpha overrides the count
        p = np.array([[0.0, 1.2, 0.135]])
        held = c.resolve(p, np.zeros_like(p), p.copy(), alpha=0.0)
        assert not held[0] and p[0, 2] == 0.135


def _figure10_scene():
    """The paper's figure-10 case: a front panel over the torso, the right forearm in front."""
    m = Mannequin(1.0)
    v = m.vertices(figure10_pose())
    fp = face_parts(m.faces, m.parts)
    lo, hi = v.min(axis=0), v.max(axis=0)
    cam = ortho_view(lo, hi, "front", (160, 320), square_pixels=False)
    cam.matrix[2, 3] = 0.0  # depth = world z
    sv = cam.to_screen(v)
    torso = rasterize(sv, m.faces[fp == 0], size=(160, 320))
    arm_back = rasterize(sv, m.faces[fp == 2], size=(160, 320), keep="far")
    limbs = rasterize(sv, m.faces[fp > 0], size=(160, 320))
    near_limb = binary_dilation(limbs.covered, iterations=3)
    # the panel: 6 mm in front of the torso's front, on the chest and belly
    ii, jj = np.nonzero(torso.covered)
    x = (jj + 0.5 - cam.matrix[0, 3]) / cam.matrix[0, 0]
    y = (ii + 0.5 - cam.matrix[1, 3]) / cam.matrix[1, 1]
    keep = (y > 1.05) & (y < 1.40) & (np.abs(x) < 0.12)
    ii, jj, x, y = ii[keep], jj[keep], x[keep], y[keep]
    z = torso.depth[ii, jj] + 0.006
    gap = np.where(arm_back.covered[ii, jj], arm_back.depth[ii, jj] - z, np.inf)
    pts = np.c_[x, y, z]
    under_arm = (gap > 0.012) & np.isfinite(gap)   # forearm well in front of the panel
    clear = ~near_limb[ii, jj]                     # no limb in front, nor next to it
    return m, v, pts, under_arm, clear


def test_figure10_image_mode_shoves_cloth_in_front_of_the_arm_hybrid_does_not():
    m, v, pts, under_arm, clear = _figure10_scene()
    assert under_arm.sum() > 30 and clear.sum() > 100
    moved = {}
    for mode in ("image", "hybrid"):
        c = make_collider(mode, m.faces, m.parts)
        c.update(v)
        p = pts.copy()
        c.resolve(p, np.zeros_like(p), pts.copy())
        moved[mode] = np.linalg.norm(p - pts, axis=1)
        if mode == "image":
            # the paper's failure: the panel under the arm is shoved out to the arm's front
            # surface (centimetres: forwards, or up and down off the arm's rounded edges)
            assert np.median(moved[mode][under_arm]) > 0.03
            assert np.mean(moved[mode][under_arm] > 0.02) > 0.9
            assert np.median(p[under_arm, 2] - pts[under_arm, 2]) > 0.03
    # hybrid: the panel, 6 mm clear of the torso and well clear of the arm, stays where it is
    assert moved["hybrid"][under_arm | clear].max() < 1e-3
    # (only where the forearm itself touches the panel is anything moved, and by mm)
    assert np.mean(moved["hybrid"] > 1e-3) < 0.02 and moved["hybrid"].max() < 0.005
    # where no arm is in front, image mode leaves it alone too
    assert moved["image"][clear].max() < 1e-3


def test_object_and_hybrid_agree_on_the_torso():
    m = Mannequin(1.0)
    v = m.vertices(walk_pose(0.3))
    fp = face_parts(m.faces, m.parts)
    rng = np.random.default_rng(5)
    # points 0–3 mm inside the torso's front and back (above the pelvis capsule, which the
    # mannequin's torso capsule overlaps: a union of closed shapes, unlike a real body)
    tris = np.nonzero(fp == 0)[0]
    ctr = v[m.faces[tris]].mean(axis=1)
    nrm = np.cross(v[m.faces[tris, 1]] - v[m.faces[tris, 0]],
                   v[m.faces[tris, 2]] - v[m.faces[tris, 0]])
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    ok = (np.abs(nrm[:, 2]) > 0.6) & (ctr[:, 1] > 1.06) & (ctr[:, 1] < 1.3) & \
        (np.abs(ctr[:, 0]) < 0.09)
    pick = rng.choice(np.nonzero(ok)[0], 400)
    pts = ctr[pick] - nrm[pick] * rng.uniform(0.0, 0.003, (400, 1))
    out = {}
    for mode in ("object", "hybrid"):
        c = make_collider(mode, m.faces, m.parts)
        c.update(v)
        p = pts.copy()
        held = c.resolve(p, np.zeros_like(p), pts.copy())
        assert held.all()
        out[mode] = p
    diff = np.linalg.norm(out["object"] - out["hybrid"], axis=1)
    assert diff.max() < 1e-3


def test_skips_save_work_without_changing_results():
    m = Mannequin(1.0)
    v0 = m.vertices(figure10_pose())
    fp = face_parts(m.faces, m.parts)
    tris = np.nonzero((fp == 0) & (v0[m.faces].mean(axis=1)[:, 1] > 1.1))[0]
    rng = np.random.default_rng(2)
    pick = rng.choice(tris, 600)
    base = v0[m.faces[pick]].mean(axis=1)
    results = {}
    for on in (True, False):
        sk = Skips(on, on, on, on, on)
        c = make_collider("hybrid", m.faces, m.parts, skips=sk)
        p = base.copy()
        rng = np.random.default_rng(7)  # the same jitter for both runs
        for _frame in range(3):
            c.update(v0)  # the body stands still
            for _ in range(4):
                prev = p.copy()
                p += rng.normal(0, 2e-4, p.shape)
                c.resolve(p, np.zeros_like(p), prev)
        results[on] = (p, c)
    p_on, c_on = results[True]
    p_off, c_off = results[False]
    # a chest-only cloth never needs the legs; the maps are drawn once, then reused
    assert c_on.timings.parts_skipped > 0 and c_off.timings.parts_skipped == 0
    assert c_on.timings.maps_rendered == 1 and c_on.timings.maps_skipped == 2
    assert c_off.timings.maps_rendered == 3
    assert c_on.stats[3] > 0 and c_off.stats[3] == 0  # closest triangles reused
    # the same answer (the reused triangles are the closest ones or equivalent neighbours)
    assert np.linalg.norm(p_on - p_off, axis=1).max() < 2e-4


def test_depth_maps_front_and_back():
    centre = np.array([0.0, 1.0, 0.0])
    v, f = sphere(centre, 0.2, 64, 32)
    c = make_collider("hybrid", f, np.zeros(len(v), np.int8), map_size=(64, 64))
    c.update(v)
    front, back, covered, mat = c.depth_maps()
    assert front.shape == (64, 64) and covered[32, 32]
    assert front[32, 32] == pytest.approx(0.2, abs=3e-3)
    assert back[32, 32] == pytest.approx(-0.2, abs=3e-3)
    assert make_collider("object", f, np.zeros(len(v), np.int8)).depth_maps() is None


def test_a_point_where_the_maps_see_one_side_only_is_not_left_inside():
    """At the open rim where a limb joins the torso, a pixel can hold a surface facing the
    front camera and none facing the back one: such a pixel does not answer (hybrid sends the
    point to object space), rather than reading the empty side as "everything is outside"."""
    centre = np.array([0.0, 1.2, 0.0])
    R = 0.15
    v, f = sphere(centre, R, 64, 32)
    # a hole in the back on the +x side: there the maps have a front and no back
    fc = v[f].mean(axis=1) - centre
    f = f[~((fc[:, 2] < 0) & (fc[:, 0] > 0.06))]
    c = make_collider("hybrid", f, np.zeros(len(v), np.int8), map_size=(64, 64))
    c.update(v)
    d = _shell(4000, [0, 0, 0], 1.0, 1.0, seed=3)
    d = d[(d[:, 0] > 0.6) & (d[:, 0] < 0.8) & (d[:, 2] > 0.3)]
    pos = centre + d * (R - 0.005)   # 5 mm inside the front surface, before the hole
    assert len(pos) > 50
    c.resolve(pos, np.zeros_like(pos), pos.copy())
    assert np.linalg.norm(pos - centre, axis=1).min() >= _inscribed(v, f, centre)


def test_bad_input_is_a_catwalk_error():
    v, f = sphere((0, 1, 0), 0.1)
    parts = np.zeros(len(v), np.int8)
    with pytest.raises(CatwalkError):
        make_collider("gpu", f, parts)
    with pytest.raises(CatwalkError):
        make_collider("hybrid", f, parts[:-5])
    with pytest.raises(CatwalkError):
        make_collider("hybrid", f, parts + 7)
    with pytest.raises(CatwalkError):
        make_collider("hybrid", f, parts, thickness=-1)
    c = make_collider("hybrid", f, parts)
    p = np.zeros((3, 3))
    with pytest.raises(CatwalkError):
        c.resolve(p, p.copy(), p.copy())  # update() first
    with pytest.raises(CatwalkError):
        c.update(v[:-1])
    c.update(v)
    with pytest.raises(CatwalkError):
        c.resolve(p.astype(np.float32), p.copy(), p.copy())
    with pytest.raises(CatwalkError):
        c.resolve(p, p.copy(), p.copy(), alpha=2.0)


@pytest.mark.parametrize("mode", MODES)
def test_held_points_get_their_contact_plane(mode):
    centre = np.array([0.0, 1.2, 0.0])
    R = 0.15
    v, f = sphere(centre, R, 64, 32)
    c = make_collider(mode, f, np.zeros(len(v), np.int8))
    c.update(v)
    pos = _shell(2000, centre, R - 0.012, R + 0.03)
    held = c.resolve(pos, np.zeros_like(pos), pos.copy())
    p = c.planes
    assert p.shape == (len(pos), 8)
    nl = np.linalg.norm(p[:, :3], axis=1)
    assert held.sum() > 300
    assert np.allclose(nl[held], 1.0) and np.all(nl[~held] == 0.0)
    # the normal points out of the sphere; every held point is on its plane's outer side,
    # and the plane is the surface offset by the thickness (within the tessellation)
    radial = (pos[held] - centre) / np.linalg.norm(pos[held] - centre, axis=1)[:, None]
    assert np.einsum("ij,ij->i", p[held, :3], radial).min() > 0.9
    side = np.einsum("ij,ij->i", p[held, :3], pos[held]) - p[held, 3]
    assert side.min() >= -1e-9
    surface = p[held, 3] - np.einsum("ij,j->i", p[held, :3], centre)   # n·(q − centre)
    assert np.median(surface) == pytest.approx(R + T, abs=0.002)
    assert np.all(p[held, 4:7] == 0.0)   # a body standing still
    assert np.all(p[held, 7] == c.friction)


@pytest.mark.parametrize("mode", MODES)
def test_points_within_the_plane_band_get_a_plane_and_are_not_held(mode):
    """With ``plane_band`` the points not held but within it of the surface get the same
    kind of plane (the surface offset by the thickness: the solver keeps them behind it until
    the next resolve); those beyond it none; held points keep their own."""
    centre = np.array([0.0, 1.2, 0.0])
    R = 0.15
    band = 0.01
    v, f = sphere(centre, R, 64, 32)
    pos = _shell(2000, centre, R - 0.012, R + 0.04)
    plain = make_collider(mode, f, np.zeros(len(v), np.int8))
    banded = make_collider(mode, f, np.zeros(len(v), np.int8), plane_band=band)
    for c in (plain, banded):
        c.update(v)
    a, b = pos.copy(), pos.copy()
    held_a = plain.resolve(a, np.zeros_like(a), pos.copy())
    held_b = banded.resolve(b, np.zeros_like(b), pos.copy())
    # the band changes no point's answer, only which points get planes
    assert np.array_equal(held_a, held_b) and np.array_equal(a, b)
    assert np.array_equal(plain.planes[held_a], banded.planes[held_b])
    r = np.linalg.norm(pos - centre, axis=1)
    nl = np.linalg.norm(banded.planes[:, :3], axis=1)
    near = ~held_b & (r < R + T + band - 0.002)
    if mode != "object":
        # the depth maps see a point's distance along the cameras' axis: beside the
        # silhouette (the surface seen edge-on) a point within the band is not seen as near
        near &= np.abs(pos[:, 2] - centre[2]) > 0.6 * r
    far = r > R + T + band + 0.002
    assert near.sum() > 100 and far.sum() > 100
    assert np.allclose(nl[near], 1.0) and np.all(nl[far] == 0.0)
    assert np.all(np.linalg.norm(plain.planes[~held_a, :3], axis=1) == 0.0)
    # a near point's plane: the surface offset by the thickness, the point in front of it
    p = banded.planes[near]
    side = np.einsum("ij,ij->i", p[:, :3], pos[near]) - p[:, 3]
    assert side.min() > 0.0
    surface = p[:, 3] - np.einsum("ij,j->i", p[:, :3], centre)
    assert np.median(surface) == pytest.approx(R + T, abs=0.002)


def test_a_bad_plane_band_is_refused():
    v, f = sphere(np.zeros(3), 0.1, 16, 8)
    for bad in (-0.01, 0.2, float("nan")):
        with pytest.raises(CatwalkError, match="plane_band"):
            make_collider("object", f, np.zeros(len(v), np.int8), plane_band=bad)


def test_a_point_another_pass_had_is_not_judged_by_where_it_was_long_ago():
    """A point the object pass did not see for a while (the hybrid's edge and limb passes
    take turns) is judged from its previous positions: where the pass last saw it, long ago,
    is no crossing test and no search radius. The scene: an open sheet (one part, as a limb
    cut at its rim); the point seen in front of it, then, unseen, moved beside and behind its
    plane, 35 cm from its edge: nothing to answer there."""

    class TakingTurns(ObjectCollider):
        only = NO_MASK

        def _resolve(self, s, held):
            reach = self._object_pass.reach(self, s.lo, s.hi)
            self._pts = self._object_pass.run(self, s, held, reach & self.tree_parts,
                                              self._pts, self.only)

    v = np.array([[-0.15, 0.85, 0.0], [0.15, 0.85, 0.0], [0.15, 1.15, 0.0], [-0.15, 1.15, 0.0]])
    f = np.array([[0, 1, 2], [0, 2, 3]])          # normal +Z
    c = TakingTurns(f, np.zeros(4, np.int8))
    c.update(v)
    keeper = [0.0, 1.0, 0.01]                     # keeps the sheet in reach of the cloth's box
    pos = np.array([keeper, [0.0, 1.0, 0.3]])
    c.resolve(pos, np.zeros_like(pos), pos.copy(), alpha=0.5)
    c.only = np.array([True, False])              # point 1 goes to another pass
    for _ in range(3):
        c.update(v)
        c.resolve(pos, np.zeros_like(pos), pos.copy(), alpha=0.5)
    pos[1] = [0.5, 1.0, -0.05]                    # moved meanwhile: behind the plane, far
    c.only = NO_MASK
    c.update(v)
    after = pos.copy()
    held = c.resolve(after, np.zeros_like(pos), pos.copy(), alpha=0.5)
    assert not held[1] and np.array_equal(after[1], pos[1])
    # a point seen at the previous call that crossed the sheet is still pushed back out
    pos2 = np.array([keeper, [0.0, 1.0, 0.002]])
    c2 = ObjectCollider(f, np.zeros(4, np.int8))
    c2.update(v)
    c2.resolve(pos2, np.zeros_like(pos2), pos2.copy(), alpha=0.5)
    crossed = np.array([keeper, [0.0, 1.0, -0.03]])
    held = c2.resolve(crossed, np.zeros_like(crossed), pos2.copy(), alpha=1.0)
    assert held[1] and crossed[1, 2] >= T - 1e-9


@pytest.mark.parametrize("mode,torso", [("hybrid", False), ("hybrid", True),
                                        ("object", False)])
def test_the_frames_last_answer_puts_a_point_between_the_faces_of_a_fold(mode, torso):
    """Cloth in a narrow notch of one part (a fold of the body onto itself, as the skinned arm
    folds under the armpit): a point pushed off one face along its normal ends behind the
    facing one. The response that gives the frame kept (``final``: a walk's recorded frame)
    looks at the pushed points again and puts each one found behind a facing surface between
    the two; another response does not (the next one sees the point again). ``torso``: a
    torso ball 4.5 cm above (in hybrid the maps and the all-parts pass then take part, as on
    a body, and the second look is the all-parts pass's)."""

    v, f = notched_prism()
    parts = np.full(len(v), 1, np.int8)
    if torso:
        vb, fb = sphere((0.0, 0.12, 0.0), 0.04, 32, 16)
        v, f = merge([(v, f), (vb, fb)])
        parts = np.r_[parts, np.zeros(len(vb), np.int8)]
    rng = np.random.default_rng(5)
    n = 400
    beta = np.arctan2(0.005, 0.03)
    up = np.array([-np.sin(beta), np.cos(beta)])       # up the notch's left face
    out = np.array([np.cos(beta), np.sin(beta)])       # that face's normal, into the notch
    xy = (np.array([0.0, 0.02]) + rng.uniform(0.002, 0.012, n)[:, None] * up
          + rng.uniform(0.0002, 0.0015, n)[:, None] * out)
    start = np.c_[xy, rng.uniform(-0.03, 0.03, n)]
    start = start[notched_prism_depth(start) == 0.0]   # outside, near the left face
    n = len(start)
    assert n > 300
    depth = {}
    for final in (False, True):
        c = make_collider(mode, f, parts)
        c.update(v)
        pos = start.copy()
        held = c.resolve(pos, np.zeros_like(pos), start.copy(), alpha=1.0, final=final)
        assert held.all()
        depth[final] = notched_prism_depth(pos)
        folds = int(c.stats[STAT_NAMES.index("folds")])
        assert (folds > n // 2) if final else folds == 0
    assert (depth[False] > 0.001).sum() > n // 2         # pushed behind the facing face
    assert depth[True].max() == 0.0
