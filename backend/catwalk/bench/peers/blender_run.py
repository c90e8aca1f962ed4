"""Blender's cloth as a peer of ``catwalk bench peers`` (run by Blender, not by catwalk).

    blender -b --factory-startup -t 1 --python blender_run.py -- SCENE.npz OUT.npz \
        [--quality Q] [--collision-quality C] [--distance M]

The scene (written by :mod:`catwalk.bench.peers`): the dressed garment (its positions are also
its rest shape), its masses, the walking body's vertices at every frame, the fabric. Here the
garment becomes a Blender mesh with the Cloth modifier and the body a mesh whose vertices are
played from a point cache (Mesh Cache modifier, PC2 file) with the Collision modifier after it,
so Blender sees the same deforming body. Frame by frame ``scene.frame_set`` advances the cloth
(``quality`` solver steps a frame, Blender's implicit integrator) and is timed; the garment's
evaluated vertices are read after each frame, outside the timing.

Material mapping. Blender's cloth keeps time in frames, not seconds (``cloth.c``: gravity is
the scene's × 0.001, air drag a force −0.01·air·v per vertex, a structural spring's constant
``tension / avg_spring_len``, an angular bending spring's ``bending · rest_length · 0.1``), so
with T the frame's duration (s) a constant k (N/m) is k·T² there and a damping c (N·s/m) c·T:
vertex mass m̄ = the garment's mean point mass (Blender's cloth has one mass for all vertices);
scene gravity (0, −9.81·T²·1000, 0) (the scene is in glTF axes, +Y up); tension = compression
= E·T²·l̄ (E the fabric's tensile stiffness per width, l̄ the mean edge length: a spring of mean
length is a strip of its width); shear = G·T²·l̄ (Blender makes shear springs on quads only,
none on this triangle mesh); bending = 10·B·T²/l̄² (a hinge of length l at angle θ between
triangles of height ≈ l̄ resists with B·l·θ/l̄²); tension/compression/shear damping = 2ζ√(E·m̄/2)
·T (the fabric's damping ratio ζ); air = 100·air·m̄·T (the fabric's drag per mass). Collision:
the cloth's ``distance_min`` and the body's outer thickness = catwalk's ``thickness``.
Then mass, stiffnesses and dampings are all multiplied by S = 0.3 kg / m̄ (the same motion):
with the garment's real 55 mg a vertex Blender's solver blew up (strain 10¹⁴); at Blender's
default vertex mass its constants land where its presets are (tension ≈ 8, bending ≈ 0.4).

Output OUT.npz: ``positions`` (F, P, 3) float32 (index 0: the initial state), ``frame_seconds``
(F − 1,), ``info`` (JSON: Blender's version, the settings used). Nothing of this file is
catwalk's code; it only drives Blender's public Python API.
"""

import json
import struct
import sys
import tempfile
import time
from pathlib import Path

import bpy
import numpy as np

BLENDER_VERTEX_MASS = 0.3   # kg: Blender's default (its presets are tuned around it)


def _args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    opts = {"quality": 5, "collision_quality": 2, "distance": None}
    files = []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("--quality", "--collision-quality"):
            opts[a[2:].replace("-", "_")] = int(argv[i + 1])
            i += 2
        elif a == "--distance":
            opts["distance"] = float(argv[i + 1])
            i += 2
        else:
            files.append(a)
            i += 1
    if len(files) != 2:
        raise SystemExit("usage: blender -b --python blender_run.py -- SCENE.npz OUT.npz "
                         "[--quality Q] [--collision-quality C] [--distance M]")
    return files[0], files[1], opts


def _mesh(name, verts, faces):
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts.tolist(), [], faces.tolist())
    me.validate(clean_customdata=False)
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def _write_pc2(path, frames):
    """A PC2 point cache: header, then float32 x y z per point per frame."""
    f, n = frames.shape[0], frames.shape[1]
    with open(path, "wb") as fh:
        fh.write(struct.pack("<12siiffi", b"POINTCACHE2\0", 1, n, 0.0, 1.0, f))
        fh.write(np.ascontiguousarray(frames, dtype="<f4").tobytes())


def _mean_edge(x0, tri) -> float:
    edges = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    edges = np.unique(np.sort(edges, axis=1), axis=0)
    return float(np.mean(np.linalg.norm(x0[edges[:, 0]] - x0[edges[:, 1]], axis=1)))


def _add_body(s, frames, distance, pc2):
    """The body: its rest mesh, played from a PC2 cache of every frame (written to ``pc2``),
    then collision."""
    body = _mesh("body", frames[0].astype(np.float64), s["body_faces"].astype(np.int64))
    _write_pc2(pc2, frames)
    cache = body.modifiers.new("walk", "MESH_CACHE")
    cache.cache_format = "PC2"
    cache.filepath = str(pc2)
    cache.frame_start = 1.0
    cache.interpolation = "LINEAR"
    body.modifiers.new("collision", "COLLISION")
    col = body.collision
    col.thickness_outer = distance
    col.cloth_friction = 5.0 * float(s["friction"]) / 0.5   # Blender's default 5 ~ mu 0.5
    col.use_culling = False
    return col


def _add_garment(s, x0, tri, lbar, frame_s, opts, distance):
    """The garment with the Cloth modifier, its constants mapped (module docstring)."""
    garment = _mesh("garment", x0, tri)
    cloth = garment.modifiers.new("cloth", "CLOTH")
    st = cloth.settings
    st.quality = opts["quality"]
    # everything × S (so the motion is the same): Blender's float solver in its own range
    m_real = float(np.mean(s["cloth_mass"]))
    scale = BLENDER_VERTEX_MASS / m_real
    t2, t1 = frame_s ** 2 * scale, frame_s * scale
    st.mass = m_real * scale
    st.bending_model = "ANGULAR"
    st.tension_stiffness = st.compression_stiffness = float(s["stretch"]) * t2 * lbar
    st.shear_stiffness = float(s["shear"]) * t2 * lbar
    st.bending_stiffness = 10.0 * float(s["bend"]) * t2 / lbar ** 2
    damp = 2.0 * float(s["damping"]) * np.sqrt(float(s["stretch"]) * m_real / 2.0) * t1
    st.tension_damping = st.compression_damping = st.shear_damping = damp
    st.air_damping = 100.0 * float(s["air"]) * m_real * t1
    cs = cloth.collision_settings
    cs.use_collision = True
    cs.use_self_collision = False
    cs.collision_quality = opts["collision_quality"]
    cs.distance_min = distance
    cloth.point_cache.frame_start, cloth.point_cache.frame_end = 1, len(s["body_frames"])
    return garment, cloth


def _play(sc, garment, x0, nf):
    """Advance frame by frame, timing each; the garment's vertices after each (untimed)."""
    n = len(x0)
    out = np.zeros((nf, n, 3), dtype=np.float32)
    out[0] = x0
    secs = np.zeros(nf - 1)
    co = np.empty(n * 3, dtype=np.float64)
    sc.frame_set(1)
    for f in range(2, nf + 1):
        t0 = time.perf_counter()
        sc.frame_set(f)
        secs[f - 2] = time.perf_counter() - t0
        ev = garment.evaluated_get(bpy.context.evaluated_depsgraph_get())
        ev.data.vertices.foreach_get("co", co)
        out[f - 1] = co.reshape(n, 3)
        if not np.all(np.isfinite(out[f - 1])):
            return out[:f], secs[:f - 1], f"non-finite positions at frame {f - 1}"
    return out, secs, None


def main():
    scene_path, out_path, opts = _args()
    s = np.load(scene_path)
    x0 = s["cloth_positions"].astype(np.float64)
    tri = s["cloth_triangles"].astype(np.int64)
    frames = s["body_frames"].astype(np.float32)
    nf = frames.shape[0]
    lbar = _mean_edge(x0, tri)
    distance = opts["distance"] or float(s["thickness"])

    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    frame_s = 1.0 / float(s["fps"])
    sc.gravity = (0.0, -9.81 * frame_s ** 2 * 1000.0, 0.0)
    sc.render.fps = int(round(float(s["fps"])))
    sc.render.fps_base = sc.render.fps / float(s["fps"])
    sc.frame_start, sc.frame_end = 1, nf
    with tempfile.TemporaryDirectory(prefix="catwalk-blender-") as tmp:
        col = _add_body(s, frames, distance, Path(tmp) / "body.pc2")
        garment, cloth = _add_garment(s, x0, tri, lbar, frame_s, opts, distance)
        out, secs, error = _play(sc, garment, x0, nf)
    st, cs = cloth.settings, cloth.collision_settings
    info = {"peer": "blender", "version": bpy.app.version_string, "solver": "implicit (cloth)",
            "quality": st.quality, "collision_quality": cs.collision_quality,
            "vertex_mass_kg": st.mass, "tension": st.tension_stiffness,
            "shear": st.shear_stiffness, "bending": st.bending_stiffness,
            "tension_damping": st.tension_damping, "air_damping": st.air_damping,
            "distance_min_m": cs.distance_min, "body_thickness_outer_m": col.thickness_outer,
            "mean_edge_m": lbar, "threads": "blender -t 1",
            "error": error}
    np.savez(out_path, positions=out, frame_seconds=secs, info=json.dumps(info))
    sys.exit(1 if error else 0)


main()
