"""The counters the passes keep (``stats`` int64 array, accumulated; named by
:data:`STAT_NAMES` in reports):

0 points that passed a part's box test, 1 narrow-phase searches (hierarchy walks or map
look-ups), 2 contacts, 3 closest-triangle results reused, 4 hierarchy nodes visited,
5 points skipped by the box tests, 6 points skipped by their clearance, 7 triangles tested
(closest point computed), 8 points the maps left to object space, 9 held points within the
thickness of a second part (:func:`catwalk.collide.kernels.second_surface.second_surface`),
10 of them pinched between two facing surfaces, 11 points put between the two faces of a fold
(:func:`catwalk.collide.kernels.second_surface.fold`), 12 points seen a second time in a
response (the frame kept's look again).
"""

from __future__ import annotations

(ST_BOXED, ST_NARROW, ST_CONTACT, ST_REUSED, ST_NODES, ST_SKIPPED, ST_CLEAR, ST_TRIS,
 ST_EDGE, ST_SECOND, ST_PINCH, ST_FOLD, ST_RECHECK) = range(13)
N_STATS = 13
STAT_NAMES = ("boxed", "narrow", "contacts", "reused", "nodes", "skipped", "clearance_skips",
              "triangles_tested", "edge_fallbacks", "second_surface", "pinched", "folds",
              "rechecked")
