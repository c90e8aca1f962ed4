"""Rendering a cloth to PNG with the project's CPU renderer (:mod:`catwalk.render.preview`)."""

from __future__ import annotations

import numpy as np

from catwalk.cloth.model import ClothModel
from catwalk.render.preview import render_meshes, save_png

CLOTH_RGB = (0.78, 0.30, 0.28)


def render_cloth(model: ClothModel, positions: np.ndarray, path, view="front", size=(480, 480),
                 floor: bool = False, extra_meshes=(), rgb=CLOTH_RGB) -> None:
    """Render the cloth's triangles (plus ``extra_meshes``: (vertices, faces, rgb)) to ``path``."""
    meshes = [(positions, model.triangles, rgb), *extra_meshes]
    save_png(render_meshes(meshes, view=view, size=size, floor=floor), path)
