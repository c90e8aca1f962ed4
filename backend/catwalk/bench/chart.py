"""A benchmark's plot as a PNG (PIL): two axes, each linear or logarithmic, with ticks and
labels, and points, lines and text placed in data coordinates (``bench pareto``'s time against
error, ``bench drape``'s simulated against measured drape)."""

from __future__ import annotations

import math

from PIL import Image, ImageDraw

W, H, MARGIN = 900, 600, 70


class Chart:
    """A white canvas with axes over [x_lo, x_hi] × [y_lo, y_hi] (``log_x``: the x axis in
    powers of ten, its ticks at 1, 2, 5 × 10^k)."""

    def __init__(self, x_range, y_range, x_label: str, y_label: str, *, log_x: bool = False,
                 y_ticks: int = 5, x_ticks: int = 5):
        self.log_x = log_x
        self.x_lo, self.x_hi = (math.log10(v) for v in x_range) if log_x else x_range
        self.y_lo, self.y_hi = y_range
        self.img = Image.new("RGB", (W, H), "white")
        self.g = ImageDraw.Draw(self.img)
        g, m = self.g, MARGIN
        g.line([(m, H - m), (W - m, H - m)], fill="black")
        g.line([(m, m), (m, H - m)], fill="black")
        g.text((W / 2 - 80, H - m + 30), x_label, fill="black")
        g.text((8, m - 30), y_label, fill="black")
        for x in self._x_ticks(x_ticks):
            px, _ = self.xy(x, self.y_lo)
            g.line([(px, H - m), (px, H - m + 6)], fill="black")
            g.text((px - 10, H - m + 10), f"{x:g}", fill="black")
        for k in range(y_ticks + 1):
            y = self.y_lo + (self.y_hi - self.y_lo) * k / y_ticks
            _, py = self.xy(self.x_at_left(), y)
            g.line([(m - 6, py), (m, py)], fill="black")
            g.text((8, py - 6), f"{y:.{2 if self.y_hi - self.y_lo < 2 else 1}f}", fill="black")

    def _x_ticks(self, n: int) -> list[float]:
        if self.log_x:
            return [10 ** (k + math.log10(mult))
                    for k in range(math.floor(self.x_lo), math.ceil(self.x_hi) + 1)
                    for mult in (1, 2, 5)
                    if self.x_lo <= k + math.log10(mult) <= self.x_hi]
        return [self.x_lo + (self.x_hi - self.x_lo) * k / n for k in range(n + 1)]

    def x_at_left(self) -> float:
        return 10 ** self.x_lo if self.log_x else self.x_lo

    def xy(self, x: float, y: float) -> tuple[float, float]:
        """Pixel coordinates of the data point (x, y)."""
        t = math.log10(x) if self.log_x else x
        return (MARGIN + (t - self.x_lo) / (self.x_hi - self.x_lo) * (W - 2 * MARGIN),
                H - MARGIN - (y - self.y_lo) / (self.y_hi - self.y_lo) * (H - 2 * MARGIN))

    def line(self, points, color, width: int = 1) -> None:
        self.g.line([self.xy(x, y) for x, y in points], fill=color, width=width)

    def dot(self, x: float, y: float, color, radius: int = 4, filled: bool = True,
            square: bool = False) -> None:
        px, py = self.xy(x, y)
        box = [px - radius, py - radius, px + radius, py + radius]
        draw = self.g.rectangle if square else self.g.ellipse
        draw(box, fill=color if filled else None, outline=color, width=2)

    def text(self, x: float, y: float, s: str, color="black", dx: int = 8,
             dy: int = -14) -> None:
        px, py = self.xy(x, y)
        self.g.text((px + dx, py + dy), s, fill=color)

    def save(self, path) -> None:
        self.img.save(path)
