"""``catwalk bench dress``: every catalogue garment, in every size, dressed on the sample body
its size was made for (the garment's ``fit``: e.g. ``M`` → ``female-M``), with the time and
the errors of each (issue 5's acceptance figures).

For each: wall seconds of the whole dressing (placement, sewing, welding, settling), whether
it settled, the widest seam still open (0 when every seam is welded), the deepest cloth point
inside the body (independent check, :mod:`catwalk.geometry.surface`), and the max strain of
the stretch/shear springs (with the fabric's limit τ and the 99th percentile beside it). A
garment that cannot be dressed is listed with its error. The kernels are loaded (compiled, on
a fresh install) by one untimed dressing before any is timed, so the first row's time is a
worker's, like the others.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np
from PIL import Image

from catwalk.catalogue.bodies import sample_body
from catwalk.catalogue.garments import catalogue_files
from catwalk.errors import CatwalkError
from catwalk.exchange.garment_json import load_garment
from catwalk.exchange.scene import garment_vertex_colours
from catwalk.geometry.surface import BodySurface, penetration
from catwalk.render.preview import render_meshes, save_png
from catwalk.simulate import dress, preset
from catwalk.simulate.tryon import static_frames
from catwalk.simulate.walking import strain_of


def run(garments=None, sizes=None, preset_name: str = "balanced", h: float | None = None,
        log=None, png_dir=None) -> list[dict]:
    settings = preset(preset_name).with_(h=h)
    files = catalogue_files()
    if garments:
        files = [f for f in files if f.stem in garments]
    out, bodies = [], {}
    warm = True
    for path in files:
        g = load_garment(path)
        for size in g.sizes:
            if sizes and size not in sizes:
                continue
            name = g.fit.get(size)
            if name is None:
                continue
            if name not in bodies:
                bodies[name] = sample_body(name)
            body = bodies[name]
            if warm:   # numba's kernels loaded (compiled on a fresh install), untimed
                warm = False
                try:
                    dress(body, g, size, settings=settings.with_(settle_seconds=0.1))
                except CatwalkError:
                    pass
            row = {"garment": path.stem, "size": size, "body": name}
            t0 = time.perf_counter()
            try:
                d = dress(body, g, size, settings=settings)
            except CatwalkError as exc:
                row.update({"seconds": round(time.perf_counter() - t0, 2), "converged": False,
                            "error": str(exc)})
            else:
                row["seconds"] = round(time.perf_counter() - t0, 2)
                x = d.state.positions
                pen = penetration(BodySurface(body.faces, len(body.vertices)), body.vertices, x)
                e = strain_of(d.model, x)
                row.update({
                    "converged": bool(d.stats["settled"]),
                    "max_seam_gap_mm": round(1e3 * d.stats["seam_gap_m"], 2),
                    "max_penetration_mm": round(1e3 * float(pen.max()), 2),
                    "max_strain": round(float(e.max()), 4),
                    "p99_strain": round(float(np.percentile(e, 99)), 4),
                    "tau": d.model.tau, "points": d.stats["points"],
                    "sewing_s": round(d.stats["sewing_s"], 2),
                    "settling_s": round(d.stats["settling_s"], 2)})
                if png_dir is not None:
                    row["png"] = _render(body, d, Path(png_dir) / f"{path.stem}-{size}.png")
            out.append(row)
            if log:
                log(row)
    return out


def _render(body, dressed, path: Path) -> str:
    """Front, side and back of the dressed body, textured as the .glb shows it."""
    frames = static_frames(dressed)
    images = [None if tex is None else
              np.asarray(Image.open(tex[0]).convert("RGBA"), dtype=np.float64) / 255.0
              for tex in frames.textures]
    meshes = [(body.vertices, body.faces, (0.80, 0.66, 0.58)),
              (frames.positions[0], frames.triangles, garment_vertex_colours(frames, images))]
    img = np.concatenate([render_meshes(meshes, view=v, size=(300, 450))
                          for v in ("front", "side", "back")], axis=1)
    path.parent.mkdir(parents=True, exist_ok=True)
    save_png(img, path)
    return str(path)


def format_table(rows: list[dict]) -> str:
    lines = ["| garment | size | body | s | converged | seam gap mm | penetration mm | "
             "max strain (p99, τ) |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['garment']} | {r['size']} | {r['body']} | {r['seconds']} | "
                         f"failed: {r['error']} | | | |")
            continue
        lines.append(f"| {r['garment']} | {r['size']} | {r['body']} | {r['seconds']} | "
                     f"{'yes' if r['converged'] else 'no'} | {r['max_seam_gap_mm']} | "
                     f"{r['max_penetration_mm']} | {r['max_strain']} ({r['p99_strain']}, "
                     f"{r['tau']}) |")
    return "\n".join(lines)


def main(args) -> int:
    def log(row):
        if not args.json:
            print(f"{row['garment']} {row['size']} on {row['body']}: {row['seconds']} s"
                  + (f" — {row['error']}" if "error" in row else ""), file=sys.stderr)

    rows = run(args.garments, args.sizes, args.preset, args.h, log, args.png_dir)
    print(json.dumps(rows, indent=2) if args.json else format_table(rows))
    return 0
