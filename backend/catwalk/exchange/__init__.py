"""catwalk.exchange: every file format catwalk reads or writes, reader beside writer.

- :mod:`~catwalk.exchange.source`: turning a path, bytes or a file object into bytes;
- :mod:`~catwalk.exchange.gltf`: bodies (skinned mesh, rig, walk) as .glb, read and written,
  and :class:`~catwalk.exchange.gltf.GlbBuilder`;
- :mod:`~catwalk.exchange.tryon_glb`: the try-on .glb (body + morph-target garment frames);
- :mod:`~catwalk.exchange.scene`: a try-on .glb evaluated at any time (for rendering);
- :mod:`~catwalk.exchange.compress`: meshopt compression for the web (gltfpack);
- :mod:`~catwalk.exchange.scan`: body scans (OBJ, PLY, STL, GLB) in SI glTF axes;
- :mod:`~catwalk.exchange.garment_json`: the garment's own JSON format;
- :mod:`~catwalk.exchange.dxf`, :mod:`~catwalk.exchange.markup`: AAMA/ASTM and plain DXF
  cutting patterns and the markup that completes them;
- :mod:`~catwalk.exchange.garmentcode`, :mod:`~catwalk.exchange.freesewing`: pattern importers;
- :mod:`~catwalk.exchange.obj`, :mod:`~catwalk.exchange.inventor`: OBJ frame sequences and
  Open Inventor (.iv) for the static dressed body.

Readers take a path, bytes or a binary file object; the try-on writer also gives bytes.
"""
