"""MakeHuman default bodies (glTF metres, feet on y = 0) for the measurement tests."""

import numpy as np
import pytest


def make_body(gender: float) -> np.ndarray:
    from catwalk.body.makehuman import (
        BODY_VERTEX_COUNT,
        MacroSliders,
        apply_targets,
        macro_weights,
        obj_to_gltf,
    )

    v = obj_to_gltf(apply_targets(macro_weights(MacroSliders(gender=gender))))[:BODY_VERTEX_COUNT]
    v = v.copy()
    v[:, 1] -= v[:, 1].min()
    return v


@pytest.fixture(scope="session")
def body_faces(mpfb2):
    from catwalk.body.makehuman import load_base_mesh

    return load_base_mesh().body_triangles


@pytest.fixture(scope="session")
def bodies(mpfb2):
    """{'female': V, 'male': V, 'neutral': V}."""
    return {"female": make_body(0.0), "male": make_body(1.0), "neutral": make_body(0.5)}


@pytest.fixture(scope="session")
def measured(bodies, body_faces):
    from catwalk.body.measure import measure_body

    return {
        "female": measure_body(bodies["female"], body_faces, sex="female"),
        "male": measure_body(bodies["male"], body_faces, sex="male"),
        "neutral": measure_body(bodies["neutral"], body_faces),
    }


@pytest.fixture(scope="session")
def quad_flipped_faces(mpfb2):
    """The body group triangulated along the other diagonal of every quad."""
    from catwalk.body.makehuman import load_base_mesh

    base = load_base_mesh()
    q = base.quads[base.quad_group == base.group_names.index("body")]
    is_tri = q[:, 2] == q[:, 3]
    quads = q[~is_tri]
    tris = np.concatenate([quads[:, [0, 1, 3]], quads[:, [1, 2, 3]], q[is_tri][:, :3]])
    return np.ascontiguousarray(tris, dtype=np.int32)
