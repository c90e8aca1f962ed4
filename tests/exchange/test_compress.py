import pytest
from tryon_samples import box_body, motion, skirt, stripes_png

from catwalk.errors import InputError
from catwalk.exchange import gltf
from catwalk.exchange.compress import compress_glb
from catwalk.exchange.tryon_glb import write_tryon


def test_compressed_tryon_validates_and_keeps_morph_animation(tmp_path):
    src, dst = tmp_path / "t.glb", tmp_path / "t.min.glb"
    write_tryon(src, box_body(), motion(12), [skirt(stripes_png(tmp_path / "s.png"), frames=6,
                                                     around=24, rows=8)])
    info = compress_glb(src, dst)
    assert info["output_bytes"] < info["input_bytes"] and info["ratio"] > 1.5
    report = gltf.validate([dst])[0]
    assert report["numErrors"] == 0, report["messages"]
    doc = gltf.load_glb(dst)[0]
    assert "EXT_meshopt_compression" in doc.extensionsUsed
    garment = next(n for n in doc.nodes if n.name == "garment:skirt#0")   # kept by -kn
    mesh_nodes = [doc.nodes[c] for c in garment.children or []] or [garment]
    prims = [p for n in mesh_nodes if n.mesh is not None for p in doc.meshes[n.mesh].primitives]
    assert len(prims) == 2 and all(len(p.targets) == 6 for p in prims)
    assert all(p.attributes.TEXCOORD_1 is not None for p in prims)   # -kv: the fit map's
    assert doc.accessors[prims[0].attributes.TEXCOORD_1].componentType == 5126   # -vtf
    (clip,) = doc.animations
    weights = [c for c in clip.channels if c.target.path == "weights"]
    assert len(weights) == 1
    s = clip.samplers[weights[0].sampler]
    assert s.interpolation == "LINEAR"
    assert doc.accessors[s.input].count == 6            # -af 0: the frame times, not resampled
    assert doc.accessors[s.output].count == 36
    assert doc.accessors[s.input].max[0] == pytest.approx(5 / 30, abs=1e-6)


def test_compress_bad_input(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        compress_glb(tmp_path / "none.glb", tmp_path / "out.glb")
