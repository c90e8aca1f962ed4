import json

import numpy as np
import pytest
from tryon_samples import box_body, motion, skirt, stripes_png

from catwalk.errors import InputError
from catwalk.exchange import gltf
from catwalk.exchange.scene import load_scene
from catwalk.exchange.tryon_glb import read_garments, write_tryon


@pytest.fixture
def tryon(tmp_path):
    tex = stripes_png(tmp_path / "stripes.png")
    gm = skirt(texture=tex, frames=5)
    path = tmp_path / "tryon.glb"
    write_tryon(path, box_body(), motion(12), [gm], extras={"job": "t1"})
    return path, gm


def test_tryon_glb_validates_with_one_clip_and_morph_targets(tryon):
    path, gm = tryon
    report = gltf.validate([path])[0]
    assert report["numErrors"] == 0, report["messages"]
    doc, _ = gltf.load_glb(path)
    assert [a.name for a in doc.animations] == ["walk"]
    assert [n.name for n in doc.nodes if n.name and n.name.startswith("garment:")] == \
        ["garment:skirt#0"]
    node = next(n for n in doc.nodes if n.name == "garment:skirt#0")   # one chunk
    assert node.matrix is None and node.translation is None and node.skin is None
    assert doc.nodes.index(node) in doc.scenes[0].nodes
    mesh = doc.meshes[node.mesh]
    assert len(mesh.primitives) == 2                           # one per panel
    assert all(len(p.targets) == 5 for p in mesh.primitives)   # one per frame
    assert all(set(t) == {"POSITION", "NORMAL"} for t in mesh.primitives[0].targets)
    assert mesh.extras["catwalk"]["frames"] == 5 and mesh.extras["catwalk"]["chunks"] == 1
    # the pattern's metres beside the texture coordinates: the fit map's rest shape
    pattern = gltf._read_accessor(doc, _, mesh.primitives[0].attributes.TEXCOORD_1)
    assert np.allclose(pattern, gm.uv[gm.panel == 0], atol=1e-6)
    # the front panel is textured (the PNG embedded), the back one coloured
    m0, m1 = (doc.materials[p.material] for p in mesh.primitives)
    assert m0.pbrMetallicRoughness.baseColorTexture.index == 0
    assert doc.images[0].mimeType == "image/png" and doc.images[0].bufferView is not None
    assert doc.samplers[0].wrapS == doc.samplers[0].wrapT == 10497
    assert m1.pbrMetallicRoughness.baseColorTexture is None
    assert m1.pbrMetallicRoughness.baseColorFactor == pytest.approx([0.2, 0.3, 0.8, 1.0])
    acc = doc.accessors[mesh.primitives[1].targets[3]["POSITION"]]
    assert acc.min is not None and acc.max is not None and acc.componentType == 5126
    assert doc.extras["catwalk"]["job"] == "t1"
    assert doc.extras["catwalk"]["format"] == "catwalk-tryon"
    json.dumps(doc.extras)


def test_weights_are_linear_keys_and_playback_interpolates_frames(tryon):
    path, gm = tryon
    doc, blob = gltf.load_glb(path)
    anim = doc.animations[0]
    node = next(i for i, n in enumerate(doc.nodes) if n.name == "garment:skirt#0")
    ch = [c for c in anim.channels if c.target.node == node]
    assert [c.target.path for c in ch] == ["weights"]     # one chunk: always shown
    s = anim.samplers[ch[0].sampler]
    assert s.interpolation == "LINEAR"
    times = gltf._read_accessor(doc, blob, s.input)
    w = gltf._read_accessor(doc, blob, s.output).reshape(len(times), 5)
    assert np.allclose(times, gm.times, atol=1e-7)
    assert np.array_equal(w, np.eye(5))

    def three_linear(t):   # THREE.LinearInterpolant, clamped at the ends
        return np.array([np.interp(t, times, w[:, k]) for k in range(5)])

    for t in (0.0, 0.02, 1 / 30, 0.05, 0.1334, 9.0):
        i, a = gm.frame_at(t)
        expect = np.zeros(5)
        expect[i] += 1 - a
        if a:
            expect[i + 1] += a
        assert np.allclose(three_linear(t), expect, atol=1e-6), t
        mixed = gm.positions[0] + np.tensordot(three_linear(t), gm.positions - gm.positions[0],
                                               axes=1)
        assert np.allclose(gm.positions_at(t), mixed, atol=1e-6)
    assert gm.frame_at(0.05) == (1, pytest.approx(0.5))


def test_long_try_ons_are_split_into_chunks_a_player_can_draw(tmp_path):
    """300 frames (10 s at 30 fps): meshes of at most 64 targets sharing a frame at each seam,
    one shown at a time (STEP scale keys), read back as one garment."""
    from catwalk.exchange.tryon_glb import CHUNK_TARGETS, chunk_spans

    assert chunk_spans(5) == [(0, 4)] and chunk_spans(64) == [(0, 63)]
    assert chunk_spans(65) == [(0, 63), (63, 64)]
    spans = chunk_spans(300)
    assert spans[0] == (0, 63) and spans[-1][1] == 299
    assert all(b - a + 1 <= CHUNK_TARGETS for a, b in spans)
    assert all(spans[k][1] == spans[k + 1][0] for k in range(len(spans) - 1))
    gm = skirt(frames=300, around=6, rows=2)
    path = tmp_path / "long.glb"
    write_tryon(path, box_body(), None, [gm], normals=False)
    report = gltf.validate([path])[0]
    assert report["numErrors"] == 0, report["messages"][:5]
    doc, blob = gltf.load_glb(path)
    nodes = [(i, n) for i, n in enumerate(doc.nodes) if n.name and n.name.startswith("garment:")]
    assert [n.name for _, n in nodes] == [f"garment:skirt#{k}" for k in range(len(spans))]
    anim = doc.animations[0]
    times = gm.times
    for k, (i, n) in enumerate(nodes):
        mesh = doc.meshes[n.mesh]
        assert len(mesh.primitives[0].targets) == spans[k][1] - spans[k][0] + 1 <= 64
        assert "NORMAL" not in mesh.primitives[0].targets[0]
        (scale,) = [c for c in anim.channels if c.target.node == i and c.target.path == "scale"]
        smp = anim.samplers[scale.sampler]
        assert smp.interpolation == "STEP"
        keys = gltf._read_accessor(doc, blob, smp.input)
        vals = gltf._read_accessor(doc, blob, smp.output)[:, 0]

        def shown(t, keys=keys, vals=vals):
            return vals[max(int(np.searchsorted(keys, t, side="right")) - 1, 0)] > 0

        a, b = spans[k]
        mid = 0.5 * (times[a] + times[b])
        assert shown(mid)
        for j, other in enumerate(spans):
            if j != k:
                assert not shown(0.5 * (times[other[0]] + times[other[1]])), (k, j)
    (back,) = read_garments(path)
    assert back.frames == 300
    assert np.abs(back.positions - gm.positions.astype(np.float32)).max() < 4e-7


def test_read_garments_round_trips(tryon):
    path, gm = tryon
    (back,) = read_garments(path)
    assert back.name == gm.name and back.panel_names == ["front", "back"]
    assert np.array_equal(back.panel, gm.panel) and np.array_equal(back.triangles, gm.triangles)
    assert np.allclose(back.times, gm.times, atol=1e-7)
    expect = gm.positions.astype(np.float32)
    assert back.positions.shape == expect.shape
    # base + displacement, both float32: within a couple of float32 ulps of a 1 m value
    assert np.abs(back.positions - expect).max() < 4e-7
    assert np.allclose(back.uv, gm.uv, atol=1e-6)
    assert back.textures[0][1] == (0.1, 0.1) and back.textures[1] is None
    assert back.colors[1] == pytest.approx((0.2, 0.3, 0.8, 1.0))
    # the body and its walk still read as before
    assert gltf.read_motion(path).frames == 12
    assert len(gltf.read_body(path).vertices) == len(box_body().vertices)


def test_scene_interpolates_frames_with_texture_colours(tryon):
    path, gm = tryon
    scene = load_scene(path)
    assert scene.duration == pytest.approx(11 / 30)
    names = [m[0] for m in scene.meshes_at(0.0)]
    assert names == ["body", "garment:skirt"]
    for t in (0.0, 0.05, 0.2):
        _, v, f, rgb = scene.meshes_at(t)[1]
        assert np.allclose(v, gm.positions_at(t), atol=1e-6)
        assert rgb.shape == (len(v), 3)
    front = gm.panel == 0
    # the front samples red and white stripes, the back is its flat colour
    assert np.allclose(rgb[~front], (0.2, 0.3, 0.8))
    cols = rgb[front]
    assert (cols[:, 1] < 0.3).any() and (cols[:, 1] > 0.9).any()


def test_bad_garments_are_input_errors(tmp_path):
    body = box_body()
    gm = skirt(frames=3)
    gm.times = np.array([0.0, 0.1, 0.1])
    with pytest.raises(InputError, match="strictly increasing"):
        write_tryon(tmp_path / "x.glb", body, None, [gm])
    gm = skirt(frames=3)
    gm.triangles = np.array([[0, 1, gm.positions.shape[1] - 1]])
    with pytest.raises(InputError, match="different panels"):
        write_tryon(tmp_path / "x.glb", body, None, [gm])
    gm = skirt(texture=tmp_path / "missing.png")
    with pytest.raises(InputError, match="no such file"):
        write_tryon(tmp_path / "x.glb", body, None, [gm])
    (tmp_path / "fake.png").write_text("not an image")
    gm = skirt(texture=tmp_path / "fake.png")
    with pytest.raises(InputError, match="neither PNG nor JPEG"):
        write_tryon(tmp_path / "x.glb", body, None, [gm])
    assert not (tmp_path / "x.glb").exists()


def test_static_body_gets_a_clip_for_the_garments(tmp_path):
    path = tmp_path / "s.glb"
    a, b = skirt(frames=3), skirt(frames=4)
    b.name = "garment:second"
    write_tryon(path, box_body(), None, [a, b])
    report = gltf.validate([path])[0]
    assert report["numErrors"] == 0, report["messages"]
    doc, _ = gltf.load_glb(path)
    assert all(set(t) == {"POSITION", "NORMAL"} for t in doc.meshes[1].primitives[0].targets)
    assert [x.name for x in doc.animations] == ["walk"]
    assert len(doc.animations[0].channels) == 2
    assert [g.frames for g in read_garments(path)] == [3, 4]
    assert load_scene(path).duration == pytest.approx(3 / 30)


def test_render_command_draws_the_garment_frames(tryon, tmp_path, capsys):
    from PIL import Image

    from catwalk.cli.main import main

    path, gm = tryon
    out = tmp_path / "f.png"
    assert main(["render", str(path), "--time", "0", "0.13", "--view", "back",
                 "--size", "64x96", "-o", str(out)]) == 0
    img = np.asarray(Image.open(out).convert("RGB")).astype(int)
    left, right = img[:, :64], img[:, 64:]
    blue = lambda a: ((a[..., 2] > a[..., 0] + 60) & (a[..., 2] > 100)).sum()  # noqa: E731
    assert blue(left) > 50 and blue(right) > blue(left)   # the back panel, flaring out
    # the clip lasts as long as its longest track: the body's walk here (11/30 s)
    assert main(["render", str(path), "--time", "0.5", "-o", str(out)]) == 2
    assert "past the end" in capsys.readouterr().err
