import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from tryon_samples import box_body

from catwalk.body.types import Motion
from catwalk.errors import InputError
from catwalk.exchange import gltf


def _box_body():
    body = box_body(subdivisions=2, split_parts=True)
    body.landmarks = {"waist": [0.0, 1.0, 0.0]}
    body.meta = {"sex": "test"}
    return body


def _motion(frames=12):
    rot = np.zeros((frames, 2, 4))
    rot[..., 3] = 1
    rot[:, 1] = Rotation.from_euler("x", np.linspace(0, 0.6, frames)[:, None]).as_quat()
    tr = np.tile([[0, 0.9, 0], [0, 0.5, 0]], (frames, 1, 1)).astype(float)
    tr[:, 0, 2] = np.linspace(0, 0.5, frames)
    return Motion(30.0, rot, tr)


def test_body_with_motion_round_trips_and_validates(tmp_path):
    body, motion = _box_body(), _motion()
    path = tmp_path / "b.glb"
    gltf.write_glb(path, body, motion)
    report = gltf.validate([path])[0]
    assert report["numErrors"] == 0, report["messages"]
    back = gltf.read_body(path)
    assert np.allclose(back.vertices, body.vertices, atol=1e-6)
    assert np.array_equal(back.faces, body.faces)
    assert np.array_equal(back.parts, body.parts)
    assert back.skeleton.names == ["hips", "chest"]
    assert np.allclose(back.skeleton.rest_world, body.skeleton.rest_world, atol=1e-6)
    assert back.landmarks == {"waist": [0.0, 1.0, 0.0]}
    m = gltf.read_motion(path)
    assert m.frames == motion.frames and m.fps == 30.0
    assert np.allclose(m.rotations, motion.rotations, atol=1e-6)
    assert np.allclose(m.translations, motion.translations, atol=1e-6)


def test_write_is_atomic_on_failure(tmp_path, monkeypatch):
    """A write that dies half-way leaves neither a partial file nor the old file damaged."""
    import pathlib

    body = _box_body()
    target = tmp_path / "x.glb"
    target.write_bytes(b"previous result")

    def dies_half_way(self, data):
        with open(self, "wb") as f:
            f.write(data[: len(data) // 2])
        raise OSError("disk full")

    monkeypatch.setattr(pathlib.Path, "write_bytes", dies_half_way)
    with pytest.raises(OSError, match="disk full"):
        gltf.write_glb(target, body, _motion())
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.glb"]
    assert target.read_bytes() == b"previous result"


def test_reading_garbage_is_a_clear_error(tmp_path):
    p = tmp_path / "junk.glb"
    p.write_bytes(b"glTF\x02\x00\x00\x00garbage")
    with pytest.raises(InputError, match="junk.glb"):
        gltf.read_body(p)
    with pytest.raises(InputError, match="no such file"):
        gltf.read_body(tmp_path / "missing.glb")


def test_a_json_chunk_beyond_the_json_limit_is_refused_before_it_is_parsed():
    """Found by `make fuzz`: a try-on .glb whose JSON chunk was 128 MiB (accessors repeated
    ×5,000) took over 5 s to parse; a glTF's JSON describes, the geometry is in the binary, so
    a JSON chunk over the readers' JSON limit is refused by its header."""
    import struct

    from catwalk.exchange.source import MAX_JSON_BYTES

    n = MAX_JSON_BYTES + 4
    data = b"glTF" + struct.pack("<II", 2, 20 + n) + struct.pack("<I", n) + b"JSON" + b" " * n
    with pytest.raises(InputError, match="its JSON chunk is 67,108,868 bytes"):
        gltf.load_glb(data)
