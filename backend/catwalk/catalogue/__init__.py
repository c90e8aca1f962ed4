"""The product's own samples: the sample bodies made from ``bodies/recipes.json``
(:mod:`~catwalk.catalogue.bodies`), the catalogue's garments built from their sources in
``garments/`` (:mod:`~catwalk.catalogue.garments`) and the lengths of the sample bodies that
the FreeSewing drafts are made for (:mod:`~catwalk.catalogue.lengths`). Above the file formats
(it reads and writes them), below the try-on."""
