"""The collider modes by name: :data:`MODES` and :func:`make_collider`."""

from __future__ import annotations

from catwalk.collide.collider import Collider
from catwalk.collide.hybrid import HybridCollider
from catwalk.collide.image import ImageCollider
from catwalk.collide.object import ObjectCollider
from catwalk.errors import InputError

MODES = ("hybrid", "image", "object")
COLLIDERS: dict[str, type[Collider]] = {"hybrid": HybridCollider, "image": ImageCollider,
                                        "object": ObjectCollider}


def make_collider(mode, body_faces, parts, **options) -> Collider:
    """A collider in ``mode`` (``hybrid``: torso+head in depth maps, limbs in hierarchies;
    ``image``: the whole body in depth maps; ``object``: every part in hierarchies) for a body
    with faces (M,3) and per-vertex ``parts`` (N,) (0 torso+head, 1 left arm, 2 right arm,
    3 left leg, 4 right leg). Options: :class:`~catwalk.collide.collider.ColliderOptions`
    (thickness, friction, map_size, search_radius, max_depth, reuse_tol, leaf_size,
    second_surface, edge_normal_z, skips=Skips(...), threads, …) and the mode's class (hybrid:
    edge_fallback, limb_fallback); every mode takes every mode's options, those of another
    mode having no effect."""
    if mode not in MODES:
        raise InputError(f"collider mode must be one of {', '.join(MODES)}, not {mode!r}")
    cls = COLLIDERS[mode]
    others = {k for c in COLLIDERS.values() for k in c.MODE_OPTIONS} - set(cls.MODE_OPTIONS)
    return cls(body_faces, parts, **{k: v for k, v in options.items() if k not in others})
