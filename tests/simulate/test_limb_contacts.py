"""``catwalk bench paper``'s ``limb_contacts``: how much of the cloth touching a limb touches
skin that moves rigidly with one bone (the reach of a distance field per limb segment)."""

from types import SimpleNamespace

import numpy as np

from catwalk.bench.paper import limb_contacts
from catwalk.body.skinning import body_frames
from catwalk.geometry.raster import vertex_normals


def _cloth_off(body, motion, idx, off=0.005):
    """Points ``off`` outside the body's vertices ``idx`` at every frame of ``motion``."""
    pos = [v[idx] + off * vertex_normals(v.astype(np.float64), body.faces)[idx]
           for v in body_frames(body, motion)[0]]
    return SimpleNamespace(positions=np.array(pos, np.float32))


def test_cloth_on_one_bone_skin_is_on_rigid_skin_cloth_at_a_bent_elbow_is_not(dressable_body,
                                                                             bent_elbow):
    b = dressable_body
    motion = bent_elbow(b)
    w = b.skin_weights.max(axis=1)
    joint = b.skin_joints[np.arange(len(w)), np.argmax(b.skin_weights, axis=1)]
    fore = b.skeleton.names.index("lowerarm_l")
    # every vertex of every triangle round it on the forearm bone alone; and skin blended
    # across the elbow (the forearm's and the upper arm's)
    alone = np.ones(len(w), bool)
    np.logical_and.at(alone, b.faces.ravel(), np.repeat((w[b.faces] > 0.999).all(axis=1) &
                                                        (joint[b.faces] == fore).all(axis=1), 3))
    alone &= joint == fore
    order = np.argsort(-b.skin_weights, axis=1)
    second = b.skin_joints[np.arange(len(w)), order[:, 1]]
    upper = b.skeleton.names.index("upperarm_l")
    across = ((joint == fore) & (second == upper)) | ((joint == upper) & (second == fore))
    blended = np.flatnonzero(across & (w < 0.7))
    assert len(blended) > 20 and alone.sum() > 20
    r = limb_contacts(b, motion, _cloth_off(b, motion, np.flatnonzero(alone)[:40]))
    assert r["point_frames_touching_a_limb"] == 3 * 40
    assert r["touching_rigid_skin_share"] == 1.0
    assert 0.5 < r["limb_vertices_rigid_share"] < 1.0   # the elbow's blended skin strays
    # carried back to the rest pose by one bone's transform, a point keeps its distance
    rp = r["rest_pose_distance_error"]
    assert rp["point_frames"] == 3 * 40 and rp["max_mm"] < 0.05 and rp["within_1mm_share"] == 1
    r = limb_contacts(b, motion, _cloth_off(b, motion, blended[:40]))
    assert r["point_frames_touching_a_limb"] >= 0.9 * 3 * 40   # (a few nearest the torso)
    assert r["touching_rigid_skin_share"] < 0.5
    # through the blended transform of its nearest vertex the distance changes little for
    # most points, by up to a centimetre where the bent elbow's inside folds (60° here)
    rp = r["rest_pose_distance_error"]
    assert rp["point_frames"] == r["point_frames_touching_a_limb"]
    assert 0.0 < rp["p50_mm"] < 0.5 and rp["within_1mm_share"] > 0.8
    assert rp["p50_mm"] <= rp["p90_mm"] <= rp["p99_mm"] <= rp["max_mm"] and rp["max_mm"] > 2.0
