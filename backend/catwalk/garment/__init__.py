"""catwalk.garment: the open garment format, its checker, importers and the catalogue.

- :mod:`~catwalk.garment.model`: :class:`Garment` (panels, sizes, seams, fabric, textures,
  placement hints), JSON read/write, :func:`cut_pieces` for the cloth builder;
- :mod:`~catwalk.garment.geometry`: line / Bézier / arc outlines, flattening, edits;
- :mod:`~catwalk.garment.check`: ``catwalk garment check``;
- :mod:`~catwalk.garment.dxf`, :mod:`~catwalk.garment.markup`: AAMA/ASTM and plain DXF import;
- :mod:`~catwalk.garment.garmentcode`, :mod:`~catwalk.garment.freesewing`: pattern importers;
- :mod:`~catwalk.garment.catalogue`: how ``garments/`` is built;
- :mod:`~catwalk.garment.place`: panels placed round a body from its landmarks.

See ``docs/garment-format.md``.
"""
