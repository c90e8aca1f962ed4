"""A garment's cutting pattern drawn flat: every piece of one size, laid out in rows, outline
and fill per panel type, its name beside it (PIL; for thumbnails and the catalogue's pages)."""

from __future__ import annotations

import io

from PIL import Image, ImageDraw

from catwalk.garment.model import Garment, cut_pieces

FILL = {"front": (214, 228, 245), "back": (232, 222, 244), "sleeve": (222, 240, 222),
        "skirt": (246, 232, 214), "leg": (246, 232, 214)}
OTHER = (236, 236, 236)
INK = (40, 48, 64)


GAP = 0.04   # metres between pieces


def _shelves(spans, width_m: float):
    """Pieces placed left to right in rows no wider than ``width_m``; (places, extent)."""
    placed, x, y, row_h = [], 0.0, 0.0, 0.0
    for sp in spans:
        if x > 0 and x + sp[0] > width_m:
            x, y, row_h = 0.0, y + row_h + GAP, 0.0
        placed.append((x, y))
        x += sp[0] + GAP
        row_h = max(row_h, sp[1])
    extent = (max(px + sp[0] for (px, _), sp in zip(placed, spans, strict=True)), y + row_h)
    return placed, extent


def pattern_png(garment: Garment, size: str | None = None,
                image_size: tuple[int, int] = (480, 360), margin: int = 12) -> bytes:
    """The pieces of ``garment`` in ``size`` (its default size) as a PNG."""
    pieces, _ = cut_pieces(garment, size)
    outlines = [p.flat.points - p.flat.points.min(axis=0) for p in pieces]
    spans = [o.max(axis=0) for o in outlines]
    w, h = image_size
    best = None
    for rows in range(1, len(spans) + 1):   # shelf packing; keep the largest scale
        placed, extent = _shelves(spans, (sum(sp[0] for sp in spans) + GAP * len(spans))
                                  / rows * 1.05)
        scale = min((w - 2 * margin) / extent[0], (h - 2 * margin) / extent[1])
        if best is None or scale > best[0]:
            best = (scale, placed)
    scale, placed = best
    img = Image.new("RGB", (w, h), (250, 250, 248))
    draw = ImageDraw.Draw(img)
    for piece, outline, (px, py), s in zip(pieces, outlines, placed, spans, strict=True):
        pts = [(margin + (px + u) * scale, h - margin - (py + v) * scale) for u, v in outline]
        draw.polygon(pts, fill=FILL.get(piece.panel.type, OTHER), outline=INK, width=2)
        cx = margin + (px + s[0] / 2) * scale
        cy = h - margin - (py + s[1] / 2) * scale
        draw.text((cx, cy), piece.name, fill=INK, anchor="mm")
    buf = io.BytesIO()
    img.save(buf, format="PNG")
    return buf.getvalue()
