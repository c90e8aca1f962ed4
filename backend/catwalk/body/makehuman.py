"""The MakeHuman (hm08) base mesh and its targets, from the CC0 mpfb2 data.

Coordinates: the OBJ is in decimetres, +Y up, facing +Z (glTF axes, ×10). Vertices 0–13379 are
the watertight ``body`` group; the rest are helper geometry and joint cubes, which are kept
while a shape is evaluated (the rig's joints are defined on them) and dropped afterwards.

Targets are sparse ``index dx dy dz`` offsets in decimetres. :func:`macro_weights` mixes the
macro targets by MakeHuman's slider rules; :func:`apply_targets` sums weighted targets onto the
base mesh with one vectorised scatter-add per target.
"""

from __future__ import annotations

import gzip
import json
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from catwalk.assets import asset_path, ensure_assets

BODY_VERTEX_COUNT = 13380
RACES = ("african", "asian", "caucasian")


@dataclass(frozen=True)
class BaseMesh:
    vertices: np.ndarray       # (19158, 3) float64, decimetres, OBJ space
    quads: np.ndarray          # (Q, 4) int32 (triangles repeat their last index)
    quad_group: np.ndarray     # (Q,) int32 index into group_names
    group_names: tuple[str, ...]
    group_vertices: dict       # group name -> sorted unique vertex indices

    @property
    def body_triangles(self) -> np.ndarray:
        """(26756, 3) int32 triangles of the ``body`` group (vertex ids < 13380)."""
        return body_triangles()


@lru_cache(maxsize=1)
def load_base_mesh() -> BaseMesh:
    path = asset_path("3dobjs/base.obj")
    verts, quads, qgroup, names = [], [], [], []
    current = -1
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append(line.split()[1:4])
            elif line.startswith("f "):
                idx = [int(tok.split("/")[0]) - 1 for tok in line.split()[1:]]
                if len(idx) == 3:
                    idx.append(idx[2])
                quads.append(idx[:4])
                qgroup.append(current)
            elif line.startswith("g "):
                names.append(line[2:].strip())
                current = len(names) - 1
    vertices = np.asarray(verts, dtype=np.float64)
    quads_a = np.asarray(quads, dtype=np.int32)
    qgroup_a = np.asarray(qgroup, dtype=np.int32)
    groups = {}
    for gi, name in enumerate(names):
        groups[name] = np.unique(quads_a[qgroup_a == gi])
    return BaseMesh(vertices, quads_a, qgroup_a, tuple(names), groups)


@lru_cache(maxsize=1)
def body_triangles() -> np.ndarray:
    """The ``body`` group's quads split into triangles: (26756, 3) int32, ids < 13380."""
    base = load_base_mesh()
    q = base.quads[base.quad_group == base.group_names.index("body")]
    tris = np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]])
    tris = tris[tris[:, 1] != tris[:, 2]]
    if tris.max() >= BODY_VERTEX_COUNT:
        raise RuntimeError("the base mesh's body group uses helper vertices: wrong asset version")
    return np.ascontiguousarray(tris, dtype=np.int32)


@lru_cache(maxsize=4096)
def load_target(rel: str) -> tuple[np.ndarray, np.ndarray]:
    """A target as (indices int32, offsets float64 (k,3) in decimetres). ``rel`` is relative to
    ``targets/`` without the ``.target.gz`` suffix. Missing files raise; empty files are empty."""
    path = asset_path(f"targets/{rel}.target.gz")
    with gzip.open(path, "rt") as f:
        rows = [ln.split() for ln in f if ln.strip() and not ln.startswith("#")]
    if not rows:
        return np.zeros(0, np.int32), np.zeros((0, 3))
    arr = np.asarray(rows, dtype=np.float64)
    return arr[:, 0].astype(np.int32), arr[:, 1:4]


def target_exists(rel: str) -> bool:
    return (ensure_assets() / "targets" / f"{rel}.target.gz").is_file()


def _two_sided(v: float) -> tuple[float, float, float]:
    lo = max(0.0, 1.0 - 2.0 * v)
    hi = max(0.0, 2.0 * v - 1.0)
    return lo, 1.0 - lo - hi, hi


def _age_weights(age: float) -> dict[str, float]:
    if age < 0.5:
        young = max(0.0, (age - 0.1875) * 3.2)
        baby = max(0.0, 1.0 - age * 5.333)
        child = max(0.0, min(1.0, 5.333 * age) - young)
        return {"baby": baby, "child": child, "young": young, "old": 0.0}
    old = max(0.0, age * 2.0 - 1.0)
    return {"baby": 0.0, "child": 0.0, "young": 1.0 - old, "old": old}


@dataclass
class MacroSliders:
    """MakeHuman macro sliders, each in [0, 1] (0.5 = average; age 0.5 = 25 years)."""
    gender: float = 0.0          # 0 female, 1 male
    age: float = 0.5
    muscle: float = 0.5
    weight: float = 0.5
    height: float = 0.5
    proportions: float = 0.5
    cupsize: float = 0.5
    firmness: float = 0.5
    african: float = 1 / 3
    asian: float = 1 / 3
    caucasian: float = 1 / 3


def macro_weights(s: MacroSliders) -> dict[str, float]:
    """Target (relative path) -> weight, by MakeHuman's macro modifier rules."""
    gw = {"female": 1.0 - s.gender, "male": s.gender}
    aw = _age_weights(s.age)
    mlo, mav, mhi = _two_sided(s.muscle)
    mw = {"minmuscle": mlo, "averagemuscle": mav, "maxmuscle": mhi}
    wlo, wav, whi = _two_sided(s.weight)
    ww = {"minweight": wlo, "averageweight": wav, "maxweight": whi}
    hw = {"minheight": max(0.0, 1.0 - 2.0 * s.height), "maxheight": max(0.0, 2.0 * s.height - 1.0)}
    pw = {"uncommonproportions": max(0.0, 1.0 - 2.0 * s.proportions),
          "idealproportions": max(0.0, 2.0 * s.proportions - 1.0)}
    clo, cav, chi = _two_sided(s.cupsize)
    cw = {"mincup": clo, "averagecup": cav, "maxcup": chi}
    flo, fav, fhi = _two_sided(s.firmness)
    fw = {"minfirmness": flo, "averagefirmness": fav, "maxfirmness": fhi}
    rsum = s.african + s.asian + s.caucasian
    rw = {r: getattr(s, r) / rsum for r in RACES} if rsum > 0 else {r: 1 / 3 for r in RACES}

    out: dict[str, float] = {}

    def add(rel: str, w: float) -> None:
        if w > 1e-9 and target_exists(rel):
            out[rel] = out.get(rel, 0.0) + w

    for g, gv in gw.items():
        for a, av in aw.items():
            if gv * av <= 0:
                continue
            for r, rv in rw.items():
                add(f"macrodetails/{r}-{g}-{a}", rv * gv * av)
            for m, mv in mw.items():
                for w_, wv in ww.items():
                    base = gv * av * mv * wv
                    if base <= 0:
                        continue
                    add(f"macrodetails/universal-{g}-{a}-{m}-{w_}", base)
                    for h, hv in hw.items():
                        add(f"macrodetails/height/{g}-{a}-{m}-{w_}-{h}", base * hv)
                    for p, pv in pw.items():
                        add(f"macrodetails/proportions/{g}-{a}-{m}-{w_}-{p}", base * pv)
                    for c, cv in cw.items():
                        for fi, fv in fw.items():
                            add(f"breast/{g}-{a}-{m}-{w_}-{c}-{fi}", base * cv * fv)
    return out


def apply_targets(weights: dict[str, float], base: np.ndarray | None = None) -> np.ndarray:
    """Base vertices (decimetres) plus the weighted sum of the given targets."""
    v = (load_base_mesh().vertices if base is None else base).copy()
    for rel, w in weights.items():
        idx, d = load_target(rel)
        if idx.size:
            np.add.at(v, idx, w * d)
    return v


def modifier_weights(values: dict[str, float]) -> dict[str, float]:
    """Two-sided local modifiers, e.g. ``{"torso/measure-waist-circ": -0.3}`` → the ``-decr`` /
    ``-incr`` target weights (MakeHuman's convention: value in [-1, 1])."""
    out = {}
    for name, val in values.items():
        if val > 0:
            out[f"{name}-incr"] = float(val)
        elif val < 0:
            out[f"{name}-decr"] = float(-val)
    return out


@lru_cache(maxsize=1)
def mirror_pairs() -> np.ndarray:
    """(N, 2) int32 pairs (vertex, mirrored vertex) from hm08.mirror."""
    rows = []
    with open(asset_path("mesh_metadata/hm08.mirror")) as f:
        for ln in f:
            parts = ln.split()
            if len(parts) >= 2:
                rows.append((int(parts[0]), int(parts[1])))
    return np.asarray(rows, dtype=np.int32)


def load_json(rel: str):
    with open(asset_path(rel)) as f:
        return json.load(f)


def obj_to_gltf(v_dm: np.ndarray) -> np.ndarray:
    """OBJ decimetres (+Y up, facing +Z) → glTF metres (same axes)."""
    return np.asarray(v_dm, dtype=np.float64) * 0.1
