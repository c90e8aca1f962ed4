"""Image mode (the paper's basic technique): the whole body in depth maps; fails when an arm is
in front of the torso (the paper's figure 10)."""

from __future__ import annotations

from catwalk.collide.collider import N_PARTS, NO_MASK, Collider, Substep
from catwalk.collide.image_pass import ImagePass


class ImageCollider(Collider):
    """Every part in the depth maps (:class:`~catwalk.collide.image_pass.ImagePass`); no
    hierarchy."""

    mode = "image"

    def __init__(self, body_faces, parts, **options):
        super().__init__(body_faces, parts, **options)
        self._use_parts(in_maps=range(N_PARTS), in_tree=())
        self._image_pass = ImagePass(self.faces, self._mapped_faces(), self._map_size,
                                     self._map_margin)

    def _resolve(self, s: Substep, held) -> None:
        self._image_pass.run(self, s, held, NO_MASK)
