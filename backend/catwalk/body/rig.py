"""The MakeHuman rig on a shaped body: joints, Blender rest frames, sparse skin weights, parts.

The rig files (``rigs/standard/rig.<name>.json``) place every bone's head and tail on the mesh
by vertex indices — ``CUBE`` (mean of the 8 vertices of a ``joint-*`` helper cube), ``VERTEX``
(one vertex) or ``MEAN`` (the mean of listed vertices) — so the joints follow the body's shape.
The rig lives in Blender space (metres, Z up, facing −Y): a bone's rest frame has its local Y
axis along head→tail and is rolled about it by ``roll`` after Blender's minimal-rotation matrix
(``vec_roll_to_mat3``, with its special case for bones pointing −Y, as the root does). Frames
are therefore computed in Blender axes and only then turned into glTF axes (+Y up, facing +Z):
``(x, y, z)_gltf = (x_b, z_b, −y_b)``.

Skin weights (``weights.<name>.json``, sparse ``bone -> [[vertex, w], …]``) are reduced to the
4 largest per body vertex and renormalised. Round each armpit they are first diffused
(``ARMPIT_RINGS`` edge rings either side of the seam between the torso and the arm, averaged
with their neighbours ``ARMPIT_SMOOTHING`` times): MakeHuman's own weights change from the
spine to the upper arm within a ring or two, and with the arms lowered from the A-pose to the
walk's linear blend skinning folds the armpit over itself — 10–15 triangles round the base
bodies' armpits turned inside out, the arm's skin crossing into the torso's, and cloth there
caught in a crease it cannot leave (docs/motion.md, "The rig"). The body part of a vertex is
the part whose bones carry the largest summed weight: torso + head 0, left arm 1, right arm 2, left
leg 3, right leg 4 (left = the body's own left = +X; an arm is the upper arm and below, a leg
the thigh and below; clavicles belong to the torso).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import scipy.sparse as sp

from catwalk.body.makehuman import (
    BODY_VERTEX_COUNT,
    MacroSliders,
    apply_targets,
    body_triangles,
    load_base_mesh,
    load_json,
    macro_weights,
    obj_to_gltf,
)
from catwalk.body.measure import measure_body
from catwalk.body.types import (
    PART_LEFT_ARM,
    PART_LEFT_LEG,
    PART_RIGHT_ARM,
    PART_RIGHT_LEG,
    PART_TORSO,
    Body,
    Skeleton,
)
from catwalk.errors import InputError
from catwalk.geometry.mesh import unique_edges, vertex_adjacency

RIGS = ("game_engine", "default", "default_no_toes", "cmu_mb")

# Blender (Z up, facing −Y) → glTF (Y up, facing +Z): a proper rotation (−90° about X).
BLENDER_TO_GLTF = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])
GLTF_TO_BLENDER = BLENDER_TO_GLTF.T

#: the armpit's skin weights are diffused over this many edge rings either side of the seam
#: between the torso and an arm, this many times (module docstring)
ARMPIT_RINGS = 4
ARMPIT_SMOOTHING = 60
#: how the skin weights were made, kept in a made body's meta (``"skin"``): a cached sample
#: body made otherwise is made again
SKIN_RECIPE = f"MakeHuman weights, armpits diffused {ARMPIT_RINGS} rings x {ARMPIT_SMOOTHING}"

_ARM_ROOTS = ("upperarm", "lowerarm", "hand", "thumb", "index", "middle", "ring", "pinky")
_LEG_ROOTS = ("thigh", "calf", "foot", "ball")


@lru_cache(maxsize=8)
def load_rig(rig: str = "game_engine") -> dict:
    if rig not in RIGS:
        raise InputError(f"unknown rig {rig!r}; choose one of {', '.join(RIGS)}")
    return load_json(f"rigs/standard/rig.{rig}.json")


@lru_cache(maxsize=8)
def load_weights(rig: str = "game_engine") -> dict:
    return load_json(f"rigs/standard/weights.{rig}.json")["weights"]


def bone_order(rig_data: dict) -> list[str]:
    """Bone names with every parent before its children (file order among siblings)."""
    names = list(rig_data)
    out: list[str] = []
    done: set[str] = set()

    def visit(n: str) -> None:
        if n in done:
            return
        p = rig_data[n].get("parent") or ""
        if p:
            visit(p)
        done.add(n)
        out.append(n)

    for n in names:
        visit(n)
    return out


def _point(spec: dict, verts: np.ndarray) -> np.ndarray:
    strategy = spec["strategy"]
    if strategy == "CUBE":
        idx = load_base_mesh().group_vertices[spec["cube_name"]]
        return verts[idx].mean(axis=0)
    if strategy == "VERTEX":
        return verts[int(spec["vertex_index"])]
    if strategy == "MEAN":
        return verts[np.asarray(spec["vertex_indices"], dtype=np.int64)].mean(axis=0)
    raise InputError(f"rig: unsupported joint strategy {strategy!r}")


def joint_positions(full_vertices: np.ndarray, rig: str = "game_engine"):
    """(names, heads (J,3), tails (J,3)) in the coordinates of ``full_vertices``."""
    data = load_rig(rig)
    names = bone_order(data)
    heads = np.array([_point(data[n]["head"], full_vertices) for n in names])
    tails = np.array([_point(data[n]["tail"], full_vertices) for n in names])
    return names, heads, tails


def _axis_angle_matrix(axis: np.ndarray, angle: float) -> np.ndarray:
    x, y, z = axis
    c, s = np.cos(angle), np.sin(angle)
    t = 1.0 - c
    return np.array([
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ])


def vec_roll_to_mat3(vec: np.ndarray, roll: float) -> np.ndarray:
    """Blender's bone rest rotation (armature.cc ``vec_roll_to_mat3_normalized``), row-major:
    column 1 is the bone's direction; columns 0 and 2 its X and Z axes after ``roll``."""
    nor = np.asarray(vec, dtype=np.float64)
    nor = nor / np.linalg.norm(nor)
    x, y, z = nor
    theta = 1.0 + y
    theta_alt = x * x + z * z
    b = np.zeros((3, 3))
    if theta > 1.0e-5 or ((x != 0.0 or z != 0.0) and theta > 1.0e-9):
        # columns: b[:, i] is Blender's bMatrix[i]
        b[0, 1], b[1, 0], b[1, 1], b[2, 1], b[1, 2] = x, -x, y, z, -z
        if theta > 1.0e-5:
            b[0, 0] = 1.0 - x * x / theta
            b[2, 2] = 1.0 - z * z / theta
            b[0, 2] = b[2, 0] = -x * z / theta
        else:
            b[0, 0] = (x + z) * (x - z) / -theta_alt
            b[2, 2] = -b[0, 0]
            b[0, 2] = b[2, 0] = 2.0 * x * z / theta_alt
    else:  # pointing straight down −Y: mirror about Z
        b = np.eye(3)
        b[0, 0] = b[1, 1] = -1.0
    return _axis_angle_matrix(nor, roll) @ b


def build_skeleton(full_vertices_m: np.ndarray, rig: str = "game_engine") -> Skeleton:
    """The rig's skeleton on a shaped full mesh (glTF metres): rest frames at the bone heads."""
    data = load_rig(rig)
    names, heads, tails = joint_positions(np.asarray(full_vertices_m, dtype=np.float64), rig)
    index = {n: i for i, n in enumerate(names)}
    parents = np.array([index[data[n]["parent"]] if data[n].get("parent") else -1
                        for n in names], dtype=np.int32)
    world = np.zeros((len(names), 4, 4))
    for j, n in enumerate(names):
        hb = GLTF_TO_BLENDER @ heads[j]
        tb = GLTF_TO_BLENDER @ tails[j]
        if np.linalg.norm(tb - hb) < 1e-9:
            raise InputError(f"rig: bone {n!r} has zero length on this body")
        rot_b = vec_roll_to_mat3(tb - hb, float(data[n].get("roll", 0.0)))
        world[j, :3, :3] = BLENDER_TO_GLTF @ rot_b
        world[j, :3, 3] = heads[j]
        world[j, 3, 3] = 1.0
    rest_local = np.empty_like(world)
    for j, p in enumerate(parents):
        rest_local[j] = world[j] if p < 0 else np.linalg.inv(world[p]) @ world[j]
    return Skeleton(names=names, parents=parents, rest_local=rest_local, tails=tails)


def part_of_bone(name: str) -> int:
    base, _, side = name.rpartition("_")
    root = name.split("_")[0]
    if side in ("l", "r"):
        if root in _ARM_ROOTS:
            return PART_LEFT_ARM if side == "l" else PART_RIGHT_ARM
        if root in _LEG_ROOTS:
            return PART_LEFT_LEG if side == "l" else PART_RIGHT_LEG
    return PART_TORSO


def skin_weights(names: list[str], rig: str = "game_engine",
                 n_vertices: int = BODY_VERTEX_COUNT, armpit_smoothing: int = ARMPIT_SMOOTHING):
    """(skin_joints (N,4) uint16, skin_weights (N,4) float32, parts (N,) int8);
    ``armpit_smoothing=0``: MakeHuman's weights as they are (module docstring)."""
    weights = load_weights(rig)
    index = {n: i for i, n in enumerate(names)}
    dense = np.zeros((n_vertices, len(names)), dtype=np.float64)
    for bone, rows in weights.items():
        if not rows or bone not in index:
            continue
        arr = np.asarray(rows, dtype=np.float64)
        vid = arr[:, 0].astype(np.int64)
        keep = vid < n_vertices
        np.add.at(dense[:, index[bone]], vid[keep], arr[keep, 1])
    if np.any(dense.sum(axis=1) <= 0):
        raise InputError(f"rig {rig!r}: some body vertices carry no skin weight")
    bone_part = np.array([part_of_bone(n) for n in names])
    if n_vertices == BODY_VERTEX_COUNT and armpit_smoothing > 0:
        dense = smooth_armpits(dense, _parts(dense, bone_part), body_triangles(),
                               times=armpit_smoothing)
    parts = _parts(dense, bone_part)
    top = np.argsort(-dense, axis=1, kind="stable")[:, :4]
    w = np.take_along_axis(dense, top, axis=1)
    w /= w.sum(axis=1, keepdims=True)
    # unused slots: weight 0 and joint 0 (glTF allows it)
    top = np.where(w > 0, top, 0)
    return top.astype(np.uint16), w.astype(np.float32), parts


def _parts(dense: np.ndarray, bone_part: np.ndarray) -> np.ndarray:
    """Each vertex's body part: the one whose bones carry the largest summed weight."""
    part_sum = np.stack([dense[:, bone_part == p].sum(axis=1) for p in range(5)], axis=1)
    return np.argmax(part_sum, axis=1).astype(np.int8)


def armpit_seam(faces: np.ndarray, parts: np.ndarray) -> np.ndarray:
    """(N,) bool: the vertices of edges that join the torso to an arm."""
    e = unique_edges(faces, len(parts))
    pa, pb = parts[e[:, 0]], parts[e[:, 1]]
    is_arm = (PART_LEFT_ARM, PART_RIGHT_ARM)
    seam = ((pa == PART_TORSO) & np.isin(pb, is_arm)) | ((pb == PART_TORSO) & np.isin(pa, is_arm))
    out = np.zeros(len(parts), bool)
    out[e[seam].ravel()] = True
    return out


def smooth_armpits(dense: np.ndarray, parts: np.ndarray, faces: np.ndarray,
                   rings: int = ARMPIT_RINGS, times: int = ARMPIT_SMOOTHING) -> np.ndarray:
    """Dense skin weights (N, J) diffused round the seams between the torso and the arms:
    every vertex within ``rings`` edges of an edge joining the torso to an arm is averaged
    with its neighbours (half its own weights, half their mean) ``times`` times, the rest
    held; each row still sums to 1."""
    n = len(dense)
    adj = vertex_adjacency(faces, n)
    region = armpit_seam(faces, parts)
    for _ in range(rings):
        region |= (adj @ region.astype(np.float64)) > 0
    idx = np.flatnonzero(region)
    degree = np.asarray(adj.sum(axis=1)).ravel()
    mean = (sp.diags(1.0 / np.maximum(degree, 1.0)) @ adj)[idx]
    out = dense.copy()
    for _ in range(times):
        out[idx] = 0.5 * out[idx] + 0.5 * (mean @ out)
    return out


def build_rig(full_vertices_m: np.ndarray, rig: str = "game_engine"):
    """Rig a shaped full MakeHuman mesh (19,158 vertices, glTF metres, feet on y = 0).

    Returns ``(skeleton, skin_joints (13380,4) uint16, skin_weights (13380,4) float32,
    parts (13380,) int8)``.
    """
    v = np.asarray(full_vertices_m, dtype=np.float64)
    n_full = load_base_mesh().vertices.shape[0]
    if v.shape != (n_full, 3):
        raise InputError(f"build_rig needs the full {n_full}-vertex mesh, got {v.shape}")
    skeleton = build_skeleton(v, rig)
    joints, weights, parts = skin_weights(skeleton.names, rig)
    return skeleton, joints, weights, parts


def default_positions_gltf(rig: str = "game_engine"):
    """The rig file's ``default_position`` heads and tails in glTF axes (metres, no shift)."""
    data = load_rig(rig)
    names = bone_order(data)
    heads = np.array([data[n]["head"]["default_position"] for n in names]) @ BLENDER_TO_GLTF.T
    tails = np.array([data[n]["tail"]["default_position"] for n in names]) @ BLENDER_TO_GLTF.T
    return names, heads, tails


def rigged_base_body(gender: float = 0.5, rig: str = "game_engine"):
    """The MakeHuman base body with average macro sliders (``gender`` 0 female … 1 male),
    rigged, in glTF metres with feet on y = 0: a quick rigged body for tests and benchmarks."""
    full = obj_to_gltf(apply_targets(macro_weights(MacroSliders(gender=gender))))
    shift = -full[:BODY_VERTEX_COUNT, 1].min()
    full[:, 1] += shift
    skeleton, joints, weights, parts = build_rig(full, rig)
    return Body(vertices=full[:BODY_VERTEX_COUNT].copy(), faces=load_base_mesh().body_triangles,
                parts=parts, skeleton=skeleton, skin_joints=joints, skin_weights=weights,
                meta={"vertical_shift": float(shift), "rig": rig, "gender_slider": gender})


def measured_base_body(gender: float = 0.0, rig: str = "game_engine"):
    """:func:`rigged_base_body` with its landmarks and measurements (≈ 1 s): a body that
    garments can be placed on, for tests and benchmarks."""
    body = rigged_base_body(gender, rig)
    sex = "female" if gender < 0.5 else "male"
    m = measure_body(body.vertices, body.faces, sex=sex)
    body.landmarks = {k: [float(x) for x in v] for k, v in m["landmarks"].items()}
    body.meta["measured"] = {k: float(v) for k, v in m.items() if isinstance(v, (int, float))}
    body.meta["sex"] = sex
    return body
