"""The catalogue in ``garments/``: how every garment there is made (``catwalk garment
catalogue``).

- ``textures/*.png``: small tileable fabric textures drawn here (deterministic);
- ``<id>.json`` for every FreeSewing draft ``freesewing/drafts/<id>.json`` with its markup
  ``freesewing/markup/<id>.json`` (the drafts come from ``node freesewing/draft.mjs`` after
  ``npm ci`` in ``garments/freesewing``);
- ``gc-shirt.json`` and ``gc-dress-pencil.json`` from the GarmentCode specifications in
  ``garmentcode/`` (MIT), graded to S/M/L by uniform scaling with the bust girth of our sample
  bodies (the specification is taken as size M);

then every garment is checked; a garment that fails the check is not written.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from PIL import Image

from catwalk.config import get_config
from catwalk.errors import InputError
from catwalk.exchange.freesewing import load_freesewing
from catwalk.exchange.garment_json import save_garment
from catwalk.exchange.garmentcode import load_garmentcode
from catwalk.exchange.markup import apply_markup, load_markup
from catwalk.fileio import atomic_path
from catwalk.garment.check import require_valid
from catwalk.garment.model import Garment


def catalogue_dir() -> Path:
    """The catalogue's folder (``$CATWALK_CATALOGUE_DIR``, by default the repo's garments/)."""
    return get_config().catalogue_dir

# bust girths of bodies/recipes.json (female S/M/L), for grading GarmentCode's M by scaling
BUST = {"S": 0.90, "M": 0.98, "L": 1.06}


def _texture(name: str, size: int = 128) -> np.ndarray:
    """A tileable RGB texture (size × size) drawn from a few stripes and dots."""
    y, x = np.mgrid[0:size, 0:size] / size
    if name == "jersey-stripes":
        base = np.array([236, 236, 240])
        stripe = np.array([30, 50, 110])
        mask = (np.floor(y * 8) % 2 == 0)[..., None]
        img = np.where(mask, stripe, base)
    elif name == "dress-dots":
        base = np.array([150, 20, 45])
        dot = np.array([245, 230, 210])
        d = np.hypot((x * 4) % 1 - 0.5, (y * 4) % 1 - 0.5)
        img = np.where((d < 0.18)[..., None], dot, base)
    elif name == "suiting-check":
        base = np.array([70, 72, 80])
        line = np.array([150, 150, 160])
        mask = ((np.abs((x * 4) % 1 - 0.5) < 0.03) | (np.abs((y * 4) % 1 - 0.5) < 0.03))
        img = np.where(mask[..., None], line, base)
    elif name == "denim-twill":
        base = np.array([40, 60, 110])
        light = np.array([90, 115, 165])
        mask = ((np.floor((x + y) * 32) % 2) == 0)[..., None]
        img = np.where(mask, light, base)
    elif name == "shirt-oxford":
        base = np.array([200, 220, 245])
        light = np.array([245, 248, 252])
        mask = ((np.floor(x * 32) + np.floor(y * 32)) % 2 == 0)[..., None]
        img = np.where(mask, light, base)
    else:
        raise ValueError(name)
    return img.astype(np.uint8)


TEXTURES = ("jersey-stripes", "dress-dots", "suiting-check", "denim-twill", "shirt-oxford")


def write_textures(root: Path) -> list[str]:
    out = []
    for name in TEXTURES:
        path = root / "textures" / f"{name}.png"
        with atomic_path(path) as tmp:
            Image.fromarray(_texture(name)).save(tmp, format="PNG")
        out.append(f"textures/{name}.png")
    return out


def grade_by_scaling(g: Garment, base: str, factors: dict[str, float]) -> Garment:
    """New sizes made from size ``base`` by scaling every panel uniformly about its origin
    (seams keep their length ratios, so a valid base stays valid)."""
    sizes = list(factors)
    for p in g.panels:
        if p.copy_of is not None:
            continue
        src = p.shapes[base]
        # a uniform scale keeps the orientation, the vertex numbers and the labels
        p.shapes = {s: src.transformed(np.array([[f, 0.0, 0.0], [0.0, f, 0.0]]))
                    for s, f in factors.items()}
    g.sizes = sizes
    g.default_size = base if base in sizes else sizes[len(sizes) // 2]
    g.source = dict(g.source, grading=f"uniform scale of size {base}: "
                    + ", ".join(f"{s} ×{f:.4f}" for s, f in factors.items()))
    return g


def build_catalogue(root: str | Path | None = None, only: list[str] | None = None) -> list[str]:
    root = Path(root) if root else catalogue_dir()
    if not root.is_dir():
        raise InputError(f"{root}: no garments folder")
    lines = [f"textures: {', '.join(write_textures(root))}"]
    built: list[tuple[str, Garment]] = []
    drafts = sorted((root / "freesewing" / "drafts").glob("*.json"))
    for d in drafts:
        gid = d.stem
        if only and gid not in only:
            continue
        markup = root / "freesewing" / "markup" / f"{gid}.json"
        if not markup.is_file():
            lines.append(f"{gid}: skipped (no markup {markup.relative_to(root)})")
            continue
        g = load_freesewing(d)
        apply_markup(g, load_markup(markup), str(markup.relative_to(root)))
        g.source["draft"] = f"freesewing/drafts/{d.name}"
        g.source["markup"] = f"freesewing/markup/{markup.name}"
        built.append((gid, g))
    factors = {s: BUST[s] / BUST["M"] for s in ("S", "M", "L")}
    for spec, gid, gtype, tex, fabric in (
            ("shirt_mean", "gc-shirt", "shirt", "shirt-oxford", "m2"),
            ("dress_pencil", "gc-dress-pencil", "dress", "dress-dots", "cotton-jersey")):
        if only and gid not in only:
            continue
        path = root / "garmentcode" / f"{spec}_specification.json"
        g = load_garmentcode(path, name=f"{spec} (GarmentCode)", garment_type=gtype, size="M")
        g.fabric = fabric
        for p in g.panels:
            p.texture = {"image": f"textures/{tex}.png", "size": [0.08, 0.08]}
        g.source["garmentcode"] = f"garmentcode/{path.name}"
        g.fit = {s: f"female-{s}" for s in factors}
        built.append((gid, grade_by_scaling(g, "M", factors)))
    for gid, g in built:
        out = root / f"{gid}.json"
        rep = require_valid(g, root)
        save_garment(g, out)
        areas = {}
        for r in rep.panels:
            areas.setdefault(r["size"], 0.0)
            mult = 2.0 if r["fold"] else 1.0
            areas[r["size"]] += mult * r["area_m2"]
        lines.append(f"{out.name}: {g.type}, sizes {', '.join(g.sizes)}, {len(g.panels)} panels, "
                     f"{len(g.seams)} seams; fabric area "
                     + ", ".join(f"{s} {a:.3f} m²" for s, a in areas.items()))
    return lines


def catalogue_files(root: str | Path | None = None) -> list[Path]:
    """The garment files in the catalogue folder (a file that cannot be parsed is listed too,
    so that reading it reports what is wrong with it)."""
    root = Path(root) if root else catalogue_dir()
    out = []
    for p in sorted(root.glob("*.json")):
        try:
            data = json.loads(p.read_text())
        except (OSError, ValueError):
            out.append(p)
            continue
        if isinstance(data, dict) and data.get("format") == "catwalk-garment":
            out.append(p)
    return out
