"""catwalk.garment: the open garment format, its checker, importers and the catalogue.

- :mod:`~catwalk.garment.model`: :class:`Garment` (panels, sizes, seams, fabric, textures,
  placement hints), JSON read/write, :func:`cut_pieces` for the cloth builder;
- :mod:`~catwalk.garment.geometry`: line / Bézier / arc outlines, flattening, edits;
- :mod:`~catwalk.garment.check`: ``catwalk garment check``;
- :mod:`~catwalk.exchange.dxf`, :mod:`~catwalk.exchange.markup`: AAMA/ASTM and plain DXF import;
- :mod:`~catwalk.exchange.garmentcode`, :mod:`~catwalk.exchange.freesewing`: pattern importers;
- :mod:`~catwalk.catalogue.garments`: how ``garments/`` is built;
- :mod:`~catwalk.garment.place`: panels placed round a body from its landmarks.

See ``docs/garment-format.md``.
"""
