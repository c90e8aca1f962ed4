import pytest


@pytest.fixture(scope="session")
def mpfb2():
    from catwalk.assets import ensure_assets

    return ensure_assets()


@pytest.fixture(scope="session")
def bent_elbow():
    """``bent_elbow(body, frames=3, degrees=30.0, forward=0.0)``: a motion of ``body``'s rest
    pose whose left elbow bends ``degrees`` more each frame (about x), the root carried
    ``forward`` metres along z a frame (every bone alike); ``degrees=0``: no bend."""
    import numpy as np

    from catwalk.body.types import Motion
    from catwalk.geometry.quat import axis_angle, mat_to_quat, quat_to_mat

    def make(body, frames=3, degrees=30.0, forward=0.0):
        sk = body.skeleton
        q = np.repeat(mat_to_quat(sk.rest_local[:, :3, :3])[None], frames, axis=0)
        t = np.repeat(sk.rest_local[None, :, :3, 3], frames, axis=0).copy()
        root = int(np.flatnonzero(sk.parents < 0)[0])
        t[:, root, 2] += forward * np.arange(frames)
        elbow = sk.names.index("lowerarm_l")
        for k in range(frames):
            bend = axis_angle(np.array([1.0, 0.0, 0.0]), np.radians(degrees * k))
            q[k, elbow] = mat_to_quat(bend @ quat_to_mat(q[k, elbow]))
        return Motion(fps=30.0, rotations=q, translations=t, loop=False)

    return make
