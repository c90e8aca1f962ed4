"""Cloth–body collision: the paper's hybrid collider (§4), and its image-space and object-space
modes.

Interface (what the cloth solver relies on)::

    collider = make_collider(mode, body_faces, parts, thickness=0.004, friction=0.3, ...)
    for each body frame:
        collider.update(body_vertices, body_velocities)        # (N,3) world m, (N,3) m/s
        for each solver substep of that frame:
            ...velocity and position update...
            held = collider.resolve(positions, velocities, previous_positions)

* ``mode``: ``"hybrid"`` (the paper: torso+head in depth maps, each limb in its own
  hierarchy), ``"image"`` (the paper's basic technique: the whole body in depth maps; fails when
  an arm is in front of the torso, figure 10) or ``"object"`` (every part in hierarchies).
* ``body_faces`` (M,3) int; ``parts`` (N,) per-vertex labels: 0 torso+head, 1 left arm,
  2 right arm, 3 left leg, 4 right leg (a face belongs to the part most of its vertices have).
* ``update`` once per body frame. Between two frames the body moves linearly from the
  previous frame to this one; every ``resolve`` call is one substep at time ``alpha`` ∈ [0, 1]
  of that motion, counted automatically: the k-th call after ``update`` is at
  ``alpha = k / n``, with ``n`` = ``update(..., substeps=n)`` if given, else the number of
  ``resolve`` calls in the previous frame (constant for a fixed solver dt; on the very first
  frame the body is still, so it does not matter). ``resolve(..., alpha=a)`` overrides.
  So a fast limb is seen at every substep and cannot jump over the cloth.
* ``resolve(positions, velocities, previous_positions)``: float64 (P,3) arrays; positions and
  velocities (C-contiguous, writable) are fixed **in place**: a point found inside the body, or
  closer to it than the cloth ``thickness``, is moved out to the surface plus ``thickness``
  along the surface normal; the normal part of its velocity becomes the body's there (when it
  was moving into the body) and the tangential part relative to the body loses μ·|Δv_n|
  (Coulomb friction). Returns ``held`` (P,) bool: the points in contact at this substep
  (within ``thickness`` + ``contact_slack``, 0.5 mm) — the solver's tension centres for the
  ordered strain limit. The cloth solver (:mod:`catwalk.cloth.solvers.explicit.solver`) calls it
  exactly so. ``resolve(..., final=True)``: the answer is the frame the caller keeps (a walk's
  recorded frame): the object passes look once more at the points they pushed, each searched afresh
  (one pushed off a triangle may be behind another where the body folds onto itself).

Method:

* **Image space** (torso+head in ``hybrid``, everything in ``image``): two orthographic depth
  maps, front (nearest surface) and back (farthest), 256×256 by default, over the mapped parts'
  bounding box seen from +Z, drawn on the CPU by ``kernels.depth_maps.render_maps`` (the
  rasteriser of :mod:`catwalk.geometry.raster`, both faces at once, only where the cloth can
  reach) with
  per-pixel interpolated vertex normal and body velocity. A point is inside when its depth lies
  between the back and the front surfaces at its pixel (bilinear over covered pixels, linear in
  time between the previous and the current frame's maps); it goes to the nearer surface.
  In ``hybrid`` the points the maps cannot answer (at the torso's silhouette, where its
  surface turns away from both cameras: the flanks, under the crotch) go to object space
  against every part, the torso's own hierarchy included (``edge_fallback=False``: the paper's
  hybrid, the maps answer them too).
* **Object space** (limbs in ``hybrid``, everything in ``object``): :mod:`catwalk.collide.bvh`,
  a hierarchy per part halving boxes across their largest dimension (spanning triangles in both
  halves), refitted per frame: each node keeps its box at the previous and the current frame,
  blended at a substep's time (their union bounds the whole frame). Each nearby cloth point
  finds its closest triangle at the substep's time and takes its signed distance (p − q)·n
  (q the closest point, n the interpolated normal there); within thickness, or inside (and,
  when deeper than ``max_depth``, only if the previous position at the previous substep's time
  was outside: a crossing) ⇒ collision.
* Skips (:class:`~catwalk.collide.collider.Skips`, each switchable and measured by
  ``catwalk bench collide``): parts whose swept, dilated box cannot reach the cloth's box get no
  refit and no queries; depth maps are not re-rendered when the mapped parts did not move; points
  outside every part's box skip the narrow phase; a point's closest triangle is reused while it
  moved less than ``reuse_tol`` relative to that triangle and no other part came nearer
  (checked every time); a point known to be clear of the body is not searched again until its
  (and the body's) motion could have closed the gap. A point's motion is measured from where
  the collider last saw it (whatever moved it since: solver, position correction, anything),
  not from ``previous_positions``, so the skips hold for any motion of the body and the points
  (docs/collide.md, "What the skips rest on").

Structure: :func:`~catwalk.collide.modes.make_collider` returns the mode's class, each a
:class:`~catwalk.collide.collider.Collider` (the interface above, and what every mode shares:
input checks, the body's two frames and normals, the substep count, a pass split over threads,
the sharp vertices' push, the reports): :class:`~catwalk.collide.image.ImageCollider`,
:class:`~catwalk.collide.object.ObjectCollider` and
:class:`~catwalk.collide.hybrid.HybridCollider` (with its fallbacks). Each answers a substep's
points in its own ``_resolve`` with the passes it holds: an
:class:`~catwalk.collide.image_pass.ImagePass` (the depth maps) and an
:class:`~catwalk.collide.object_pass.ObjectPass` (the parts' hierarchies). A mode's own options
(hybrid's ``edge_fallback``, ``limb_fallback``) are taken by ``make_collider`` in every mode
and do nothing in the others.

Kernels are ``@numba.njit(cache=True, _nrt=False)`` over flat arrays (numba's runtime off: no
reference counting of array arguments on every call; they never allocate — workspaces come from
the collider). Costs and their measurement: ``docs/collide.md``, ``catwalk bench collide``.

Test bodies: :mod:`catwalk.collide.shapes` (sphere, capsule, a capsule mannequin with parts).
"""

from catwalk.collide.collider import Collider, Skips
from catwalk.collide.hybrid import HybridCollider
from catwalk.collide.image import ImageCollider
from catwalk.collide.modes import MODES, make_collider
from catwalk.collide.object import ObjectCollider

__all__ = ["MODES", "Collider", "HybridCollider", "ImageCollider", "ObjectCollider", "Skips",
           "make_collider"]
