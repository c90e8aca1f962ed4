"""The figures of docs/cloth.md: ``python tools/figures/cloth.py docs/img``.

- ``cloth-order.png``: the processing order of the ordered strain-limit pass (like the paper's
  figure 2a): a small cloth with one static point, each point numbered in the order the pass
  visits it; and the same cloth with two pinned corners, where the fronts meet.
- ``cloth-hanging.png``: a paper-size cloth (cotton jersey) hanging from two corners held 40 %
  closer together than its width.
- ``cloth-drape.png``: Cusick drape of denim and of silk charmeuse.
- ``dress-fabrics.png``: the catalogue's dress in the lightest fabric (silk charmeuse) and the
  stiffest (denim), side by side.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

from catwalk.catalogue.bodies import sample_body
from catwalk.catalogue.garments import catalogue_files
from catwalk.cloth.builder import Panel, build_cloth, rectangle, vertical
from catwalk.cloth.drape import cusick_drape
from catwalk.cloth.scenes import paper_size_cloth
from catwalk.cloth.solvers.explicit.solver import Solver
from catwalk.cloth.state import State
from catwalk.exchange.garment_json import load_garment
from catwalk.render.cloth import render_cloth
from catwalk.render.preview import render_meshes
from catwalk.simulate import preset
from catwalk.simulate.dressing import dress


def _order_panel(pinned_uv, size=420, h=0.02, n=7, title=""):
    m = build_cloth([Panel(rectangle((n - 1) * h, (n - 1) * h),
                           placement=vertical())], h=h)
    st = State.from_model(m)
    for uv in pinned_uv:
        st.pinned[np.argmin(np.linalg.norm(m.uv - np.asarray(uv) * (n - 1) * h, axis=1))] = True
    pts, ptr, spr, oth, level, cross = Solver(m, "ordered").processing_order(st)
    rank = np.empty(m.n_points, int)
    rank[pts] = np.arange(m.n_points)
    img = Image.new("RGB", (size, size + 30), (250, 250, 250))
    d = ImageDraw.Draw(img)
    pad = 40
    scale = (size - 2 * pad) / ((n - 1) * h)

    def xy(i):
        u, v = m.uv[i]
        return pad + u * scale, size - pad - v * scale

    # springs to earlier points: grey; where two fronts meet: red
    for k in range(m.n_points):
        for j in range(ptr[k], ptr[k + 1]):
            col = (215, 60, 50) if cross[j] else (185, 185, 195)
            d.line([xy(pts[k]), xy(oth[j])], fill=col, width=3 if cross[j] else 1)
    for i in range(m.n_points):
        x, y = xy(i)
        r = 13
        if st.pinned[i]:
            d.rectangle([x - r, y - r, x + r, y + r], fill=(40, 40, 40))
            d.text((x - 8, y - 6), "Sp", fill=(255, 255, 255))
        else:
            shade = int(255 - 12 * level[i])
            d.ellipse([x - r, y - r, x + r, y + r], fill=(shade, shade, 255),
                      outline=(60, 60, 120))
            label = str(rank[i])
            d.text((x - 3.5 * len(label), y - 6), label, fill=(0, 0, 0))
    d.text((pad, size), title, fill=(0, 0, 0))
    return img


def order_figure(path) -> None:
    a = _order_panel([(0.0, 1.0)], title="one static point (Sp): order of the pass")
    b = _order_panel([(0.0, 1.0), (1.0, 1.0)],
                     title="two pins: the fronts meet (red: corrected both ways)")
    out = Image.new("RGB", (a.width + b.width, a.height), (250, 250, 250))
    out.paste(a, (0, 0))
    out.paste(b, (a.width, 0))
    out.save(path)


def hanging_figure(path) -> None:
    m, st = paper_size_cloth("cotton-jersey")
    rng = np.random.default_rng(1)  # a little out-of-plane roughness, so that it can buckle
    st.positions[:, 2] += rng.normal(0.0, 0.002, m.n_points)
    st.positions[st.pinned, 2] = 0.0
    sol = Solver(m, "ordered", extra_air=2.0)
    # move the pins 40 % closer together over one second (pinned points keep their velocity)
    st.velocities[st.pinned, 0] = -0.2 * st.positions[st.pinned, 0]
    sol.run(m, st, 1.0)
    st.velocities[st.pinned] = 0.0
    sol.run(m, st, 2.0)
    render_cloth(m, st.positions, path, view=25, size=(480, 480))


def drape_figure(path) -> None:
    tiles = []
    for fab in ("denim", "silk-charmeuse"):
        r = cusick_drape(fab, h=0.01, max_seconds=4.0)
        img = render_meshes([(r.state.positions, r.model.triangles, (0.78, 0.30, 0.28))],
                            view=30, size=(420, 300), floor=False)
        tile = Image.fromarray(img)
        ImageDraw.Draw(tile).text((10, 10), f"{fab}: DC = {r.dc:.2f} (h = {r.h} m)",
                                  fill=(0, 0, 0))
        tiles.append(tile)
    out = Image.new("RGB", (sum(t.width for t in tiles), tiles[0].height))
    x = 0
    for t in tiles:
        out.paste(t, (x, 0))
        x += t.width
    out.save(path)


def fabrics_figure(path, fabrics=("silk-charmeuse", "denim"), h: float = 0.015) -> None:
    """The catalogue's dress (M, on its sample body, balanced preset) in the lightest and the
    stiffest fabric side by side, front and side, in one plain colour (the catalogue's plaid
    hides folds)."""
    g = load_garment(next(p for p in catalogue_files() if p.stem == "dress"))
    body = sample_body(g.fit["M"])
    tiles = []
    for fab in fabrics:
        d = dress(body, g, "M", fab, preset("balanced").with_(h=h))
        meshes = [(body.vertices, body.faces, (0.80, 0.66, 0.58)),
                  (d.state.positions, d.model.triangles, (0.62, 0.16, 0.20))]
        img = np.concatenate([render_meshes(meshes, view=v, size=(300, 450))
                              for v in ("front", "side")], axis=1)
        tile = Image.fromarray(img)
        ImageDraw.Draw(tile).text((10, 10), f"{fab} (h = {h * 100:g} cm)", fill=(0, 0, 0))
        tiles.append(tile)
    out = Image.new("RGB", (sum(t.width for t in tiles), tiles[0].height), (255, 255, 255))
    x = 0
    for t in tiles:
        out.paste(t, (x, 0))
        x += t.width
    out.save(path)


def main(argv=None) -> int:
    folder = Path((argv or sys.argv[1:] or ["docs/img"])[0])
    folder.mkdir(parents=True, exist_ok=True)
    which = set((argv or sys.argv[1:])[1:]) or {"order", "hanging", "drape", "fabrics"}
    if "order" in which:
        order_figure(folder / "cloth-order.png")
    if "hanging" in which:
        hanging_figure(folder / "cloth-hanging.png")
    if "drape" in which:
        drape_figure(folder / "cloth-drape.png")
    if "fabrics" in which:
        fabrics_figure(folder / "dress-fabrics.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
