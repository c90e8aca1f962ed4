import re

import numpy as np
import pytest
from tryon_samples import box_body, skirt, stripes_png

from catwalk.errors import InputError
from catwalk.exchange.inventor import write_inventor
from catwalk.exchange.obj import write_obj_frames


def test_obj_frames_hold_body_and_garment_objects(tmp_path):
    body = box_body()
    gm = skirt(stripes_png(tmp_path / "stripes.png"), frames=3)
    frames = np.stack([body.vertices + [0, 0, 0.1 * k] for k in range(3)])
    paths = write_obj_frames(tmp_path / "obj", body.faces, frames, [gm])
    assert [p.name for p in paths] == ["frame_0000.obj", "frame_0001.obj", "frame_0002.obj"]
    assert not [p for p in (tmp_path / "obj").iterdir() if p.name.startswith(".")]
    text = paths[2].read_text()
    lines = text.splitlines()
    nb, ng = len(body.vertices), gm.positions.shape[1]
    assert [x for x in lines if x.startswith("o ")] == ["o body", "o garment:skirt"]
    v = np.array([x.split()[1:] for x in lines if x.startswith("v ")], float)
    assert len(v) == nb + ng
    assert np.allclose(v[:nb], frames[2], atol=1e-6)
    assert np.allclose(v[nb:], gm.positions[2], atol=1e-6)
    assert sum(x.startswith("vt ") for x in lines) == ng
    faces = [x.split()[1:] for x in lines if x.startswith("f ")]
    assert len(faces) == len(body.faces) + len(gm.triangles)
    gfaces = np.array([[int(c.split("/")[0]) for c in f] for f in faces[len(body.faces):]])
    assert np.array_equal(np.sort(gfaces - 1 - nb, axis=0), np.sort(gm.triangles, axis=0))
    assert [x for x in lines if x.startswith("usemtl")] == [
        "usemtl body", "usemtl garment:skirt/front", "usemtl garment:skirt/back"]
    mtl = (tmp_path / "obj" / "tryon.mtl").read_text()
    assert "map_Kd ../stripes.png" in mtl and "Kd 0.2000 0.3000 0.8000" in mtl


def test_obj_frames_reject_mismatched_frames(tmp_path):
    body = box_body()
    with pytest.raises(InputError, match="body frames"):
        write_obj_frames(tmp_path, body.faces, np.stack([body.vertices] * 2), [skirt(frames=3)])


def test_inventor_file_parses_back(tmp_path):
    body = box_body()
    gm = skirt(frames=2)
    path = tmp_path / "dressed.iv"
    write_inventor(path, body.vertices, body.faces, [gm.mesh_at_frame(1)])
    text = path.read_text()
    assert text.startswith("#Inventor V2.1 ascii\n")
    assert text.count("{") == text.count("}") and text.count("[") == text.count("]")
    blocks = re.findall(r"point \[(.*?)\]", text, re.S)
    points = [np.array(re.findall(r"-?\d+\.\d+", b), float).reshape(-1, 3) for b in blocks]
    assert [len(p) for p in points] == [len(body.vertices), gm.positions.shape[1]]
    assert np.allclose(points[1], gm.positions[1], atol=1e-6)
    faces = re.findall(r"coordIndex \[(.*?)\]", text, re.S)
    idx = [np.array(re.findall(r"-?\d+", b), int).reshape(-1, 4) for b in faces]
    assert [len(i) for i in idx] == [len(body.faces), len(gm.triangles)]
    assert np.all(idx[1][:, 3] == -1) and np.array_equal(idx[1][:, :3], gm.triangles)
    assert text.count("Material {") == 2 and "PER_VERTEX_INDEXED" in text
    assert "DEF garment_skirt Separator" in text


def test_inventor_bad_mesh(tmp_path):
    body = box_body()
    with pytest.raises(InputError, match="faces"):
        write_inventor(tmp_path / "x.iv", body.vertices, body.faces + 10_000, [])
    assert not (tmp_path / "x.iv").exists()
