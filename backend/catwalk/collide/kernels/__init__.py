"""The collider's numba kernels, one concept a module: the counters the passes keep
(:mod:`.stats`), the packed body and each point's copy of its closest triangle (:mod:`.record`),
the response and the contact planes (:mod:`.response`), a second surface facing the first and the
fold (:mod:`.second_surface`), the object pass (:mod:`.object_space`), the image pass's look-ups
(:mod:`.image_space`), the depth maps' drawing (:mod:`.depth_maps`), and the boxes and motion
bounds of vertex sets (:mod:`.boxes`). The hierarchy's own kernels are in
:mod:`catwalk.collide.bvh`.

The kernels are ``@numba.njit(cache=True, _nrt=False)`` over flat arrays (numba's runtime off: no
reference counting of array arguments on every call); they never allocate — workspaces come
from the collider. Numba caches a kernel by its own file: a change to a helper it inlines from
another file (``inline="always"``; the object pass inlines the record's, the response's and
:mod:`catwalk.collide.bvh`'s box helpers) needs a change to the kernel's file too, or clearing
``collide/kernels/__pycache__``, or the cached kernel keeps the old code.
"""
