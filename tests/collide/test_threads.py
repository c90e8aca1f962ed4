"""The object pass on several threads: the same answer as on one, bit for bit (each point's
work writes only that point's entries; the counters are summed); the image pass stays on the
calling thread."""

import numpy as np
import pytest

from catwalk.collide import make_collider
from catwalk.collide.scenes import dress, mannequin_walk
from catwalk.errors import InputError


@pytest.mark.parametrize("mode", ["object", "hybrid", "image"])
def test_threads_give_the_same_positions_velocities_and_planes(mode):
    body = mannequin_walk(n_frames=6, resolution=1.0)
    cloth = dress(body.vertices[0], body.faces, body.parts, n_points=1500)
    runs = []
    for threads in (1, 3):
        c = make_collider(mode, body.faces, body.parts, threads=threads)
        out = []
        x = cloth.positions(body.vertices[0], body.faces)
        for f in range(len(body.vertices)):
            c.update(body.vertices[f], body.velocities[f], substeps=4)
            target = cloth.positions(body.vertices[f], body.faces)
            for k in range(4):
                prev = x.copy()
                # towards the body's dress, jittered 1 mm (the same in both runs)
                x = prev + (k + 1) / 4 * (target - prev)
                x += np.random.default_rng(100 * f + k).normal(0, 1e-3, x.shape)
                v = np.zeros_like(x)
                held = c.resolve(x, v, prev)
                out.append((x.copy(), v.copy(), held.copy(), c.planes.copy()))
        # the threaded path ran — for the object passes: the image pass stays on the
        # calling thread whatever the threads
        assert (c._pool is not None) == (threads > 1 and mode != "image")
        runs.append((out, c.stats.copy()))
    (one, stats1), (three, stats3) = runs
    assert sum(h.sum() for _, _, h, _ in one) > 100   # the body holds cloth: a real test
    for a, b in zip(one, three, strict=True):
        for u, w in zip(a, b, strict=True):
            assert np.array_equal(u, w)
    assert np.array_equal(stats1, stats3)


def test_threads_are_checked():
    body = mannequin_walk(n_frames=1, resolution=0.5)
    with pytest.raises(InputError, match="threads"):
        make_collider("object", body.faces, body.parts, threads=0)


def test_a_failing_slice_raises_after_every_thread_stopped_and_the_next_call_works():
    body = mannequin_walk(n_frames=1, resolution=0.5)
    c = make_collider("object", body.faces, body.parts, threads=3)
    seen = []

    def points(start, stop, stack, reach, spd, rec2, stats):
        seen.append((start, stop))
        if start == 0:
            raise RuntimeError("slice failed")
        stats[0] += stop - start   # a counter, summed into the collider's

    with pytest.raises(RuntimeError, match="slice failed"):
        c._split(points, 1200)
    # raised only once every thread had stopped: all 12 slices taken, the 11 that did not
    # fail counted
    assert len(seen) == 12 and c.stats[0] == 1100
    seen.clear()
    c.stats[:] = 0

    def counts(start, stop, stack, reach, spd, rec2, stats):
        seen.append((start, stop))
        stats[0] += stop - start

    c._split(counts, 1200)
    assert sorted(seen)[0][0] == 0 and sorted(seen)[-1][1] == 1200 and len(seen) == 12
    assert c.stats[0] == 1200   # every thread's counters added, none lost or doubled


def test_the_settings_reach_the_collider():
    from catwalk.simulate import preset

    opts = preset("balanced").with_(threads=2, skips=False).collider_options()
    body = mannequin_walk(n_frames=1, resolution=0.5)
    c = make_collider("hybrid", body.faces, body.parts, **opts)
    assert c.threads == 2 and not any(vars(c.skips).values())
    with pytest.raises(InputError, match="skips must be true or false"):
        preset("balanced").with_(skips="no")
    # one skip off alone (a row of bench pareto): the others stay on
    one = preset("balanced").with_(skips_off=("clearance",)).collider_options()["skips"]
    assert not one.clearance and one.reuse_closest and one.far_points and one.still_torso
    with pytest.raises(InputError, match=r"skips_off must be a list of the collider's skips "
                       r"\(unreached_parts, still_torso, far_points, reuse_closest, clearance\), "
                       r"got \('sleep',\)"):
        preset("balanced").with_(skips_off=("sleep",))


def test_the_bench_flag_switches_skips_off_in_the_walks():
    import argparse

    from catwalk.bench import add_walk_settings, walk_settings
    from catwalk.simulate import preset

    p = argparse.ArgumentParser()
    add_walk_settings(p)
    walk = walk_settings(p.parse_args(["--skips-off", "clearance", "far_points"]))
    assert walk == {"skips_off": ("clearance", "far_points")}
    skips = preset("balanced").with_(**walk).collider_options(walking=True)["skips"]
    assert not skips.clearance and not skips.far_points and skips.reuse_closest
    assert walk_settings(p.parse_args([])) == {}


def test_the_plane_band_reaches_the_walks_collider_only():
    from catwalk.simulate import preset

    s = preset("balanced").with_(plane_band=0.01)
    body = mannequin_walk(n_frames=1, resolution=0.5)
    walking = make_collider("object", body.faces, body.parts,
                            **s.collider_options(walking=True))
    dressing = make_collider("object", body.faces, body.parts, **s.collider_options())
    assert walking.plane_band == 0.01 and dressing.plane_band == 0.0
    assert preset("balanced").plane_band == 0.0   # off by default (docs/tryon.md)
    for bad in (-0.001, 0.06, True):
        with pytest.raises(InputError, match="plane_band must be within 0–0.05 m"):
            preset("balanced").with_(plane_band=bad)
