"""The object pass's inputs, grouped (:func:`catwalk.collide.kernels.object_space.object_pass`).

From Python the groups go to the kernel as plain tuples, in the order of their fields (numba
types a named tuple ≈ 6 µs slower a call, and a walk frame makes 30–240 calls); the kernel names
them again inside (``ObjectConfig(*cfg)``: no cost in compiled code), and its helpers read them
by field:

* :data:`ObjectCloth` ``cloth``: the cloth points' positions ``pos`` and velocities ``vel``
  (fixed in place), their previous positions ``prev``, and what the pass writes for each point
  it sees: ``held`` (P,) bool and its contact plane in ``planes`` (P, PLANE_COLUMNS);
* :data:`ObjectTime` ``now``: the substep's ``alpha``, the previous call's ``alpha_prev``, the
  ``frame`` number, the moving frame's travel ``ref`` over this frame, the collider's
  ``clock`` (:data:`CLK_TRAVEL` …) and the ``body_speed`` bound;
* :data:`ObjectBody` ``body``: the packed body ``vb``/``vp``
  (:mod:`catwalk.collide.kernels.record`), ``faces``, ``face_part``, the hierarchies' node
  boxes at both frames ``nb``, ``links``, ``tris``, ``roots``, ``lf``, and the active parts'
  pose at ``alpha``, ``nbl``/``vpl`` (:func:`catwalk.collide.bvh.blend_at`);
* :data:`ObjectConfig` ``cfg``: thickness, friction, contact slack, search radius, max depth,
  which skips are on (``skip_far``, ``use_cache``, ``use_clear``), ``reuse_tol``, ``second``,
  ``plane_band``, ``recheck``;
* :data:`ObjectPoints` ``pts``: what is kept per point between calls (the object pass's
  docstring);
* :data:`Workspace` ``ws``: a thread's hierarchy-walk ``stack``, the parts' ``reach``, the
  search's speed accumulators ``spd``, a record ``rec2`` and the counters ``stats``.
"""

from __future__ import annotations

from collections import namedtuple

#: the collider's clocks (``ObjectTime.clock`` (N_CLOCKS,), and each point's copy when it was
#: last seen, ``ObjectPoints.pclk`` (P, N_CLOCKS)): the moving frame's travel (CLK_TRAVEL, xyz),
#: the body's travel relative to it (CLK_BODY: an upper bound of how far any limb vertex moved),
#: the time (CLK_TIME: frame + alpha; < 0: never seen)
CLK_TRAVEL, CLK_BODY, CLK_TIME = 0, 3, 4
N_CLOCKS = 5

ObjectCloth = namedtuple("ObjectCloth", "pos vel prev held planes")
ObjectTime = namedtuple("ObjectTime", "alpha alpha_prev frame ref clock body_speed")
ObjectBody = namedtuple("ObjectBody", "vb vp faces face_part nb links tris roots lf nbl vpl")
ObjectConfig = namedtuple("ObjectConfig", "thickness friction slack search_radius max_depth "
                          "skip_far use_cache reuse_tol use_clear second plane_band recheck")
ObjectPoints = namedtuple("ObjectPoints", "cache_tri cache_p cache_c clear clear_rel rkey rec "
                          "pspeed pstamp last pclk csw crel cstamp ct2 cp2 cc2 left")
Workspace = namedtuple("Workspace", "stack reach spd rec2 stats")
#: the other parts' bounds kept per point (of :data:`ObjectPoints`: ``csw`` how near each
#: comes over frame ``cstamp``, ``crel`` the point's motion since)
OtherParts = namedtuple("OtherParts", "csw crel cstamp")
