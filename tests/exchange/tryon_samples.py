"""Small bodies and garments for the try-on export tests."""

import numpy as np
from scipy.spatial.transform import Rotation

from catwalk.body.types import Body, Motion, Skeleton
from catwalk.garment.frames import GarmentFrames


def box_body(subdivisions: int = 1, split_parts: bool = False) -> Body:
    """A 0.3 × 1.6 × 0.2 m box on the floor with a two-joint rig (the top third on "chest");
    ``split_parts`` labels the +x side as part 1 (else every vertex is torso)."""
    import trimesh

    m = trimesh.creation.box(extents=(0.3, 1.6, 0.2))
    for _ in range(subdivisions):
        m = m.subdivide()
    v = np.asarray(m.vertices) + [0, 0.8, 0]
    rl = np.stack([np.eye(4)] * 2)
    rl[0][:3, 3] = [0, 0.9, 0]
    rl[1][:3, 3] = [0, 0.5, 0]
    sk = Skeleton(names=["hips", "chest"], parents=np.array([-1, 0]), rest_local=rl)
    n = len(v)
    sj = np.zeros((n, 4), np.uint16)
    sj[:, 0] = v[:, 1] > 1.2
    sw = np.zeros((n, 4), np.float32)
    sw[:, 0] = 1
    parts = (v[:, 0] > 0.1).astype(np.int8) if split_parts else np.zeros(n, np.int8)
    return Body(v, np.asarray(m.faces, np.int32), parts, sk, sj, sw)


def motion(frames=12, fps=30.0) -> Motion:
    rot = np.zeros((frames, 2, 4))
    rot[..., 3] = 1
    rot[:, 1] = Rotation.from_euler("x", np.linspace(0, 0.6, frames)[:, None]).as_quat()
    tr = np.tile([[0, 0.9, 0], [0, 0.5, 0]], (frames, 1, 1)).astype(float)
    tr[:, 0, 2] = np.linspace(0, 0.2, frames)
    return Motion(fps, rot, tr)


def skirt(texture=None, frames=5, fps=30.0, around=12, rows=4, radius=0.25) -> GarmentFrames:
    """Two panels (front, back), each a grid half-way round a cylinder at the hips; the hem
    flares more every frame. ``texture``: an image path for the front panel."""
    pts, uv, panel, tris = [], [], [], []
    for p in range(2):
        start = len(pts)
        for r in range(rows):
            for a in range(around + 1):
                th = np.pi * (p + a / around - 0.5)
                pts.append((th, 1.0 - 0.1 * r))
                uv.append((radius * th, -0.1 * r))
                panel.append(p)
        for r in range(rows - 1):
            for a in range(around):
                i = start + r * (around + 1) + a
                j = i + around + 1
                tris += [(i, j, i + 1), (i + 1, j, j + 1)]
    th, y = np.array(pts).T
    drop = 1.0 - y
    positions = []
    for f in range(frames):
        rr = radius + drop * (0.1 + 0.3 * f / max(frames - 1, 1))
        positions.append(np.stack([rr * np.sin(th), y, rr * np.cos(th)], axis=1))
    return GarmentFrames(
        name="garment:skirt", triangles=np.array(tris), uv=np.array(uv),
        panel=np.array(panel), panel_names=["front", "back"],
        textures=[None if texture is None else (str(texture), (0.1, 0.1)), None],
        colors=[(1.0, 1.0, 1.0, 1.0), (0.2, 0.3, 0.8, 1.0)],
        times=np.arange(frames) / fps, positions=np.array(positions))


def stripes_png(path, size=32):
    from PIL import Image

    a = np.zeros((size, size, 3), np.uint8)
    a[:, : size // 2] = (220, 30, 30)
    a[:, size // 2:] = (250, 250, 250)
    Image.fromarray(a).save(path)
    return path
