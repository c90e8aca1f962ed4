"""catwalk.cloth — Provot's mass-spring cloth with the paper's ordered strain limit.

- :mod:`~catwalk.cloth.builder`: 2D panels (+ seams) → :class:`~catwalk.cloth.model.ClothModel`
- :mod:`~catwalk.cloth.model`: ClothModel (static arrays) and State (positions, velocities)
- :mod:`~catwalk.cloth.solvers.explicit.solver`: Solver.step(model, state, collider, dt), explicit
(eq. 2–4)
- :mod:`~catwalk.cloth.fabrics`: fabric presets and measured fabrics → spring constants
- :mod:`~catwalk.cloth.analytic`: disc / plane / sphere colliders; :mod:`~catwalk.cloth.drape`:
  the Cusick drape test
"""

from catwalk.cloth.builder import Panel, Seam, build_cloth
from catwalk.cloth.fabrics import PRESETS, Fabric, get_fabric
from catwalk.cloth.model import ClothModel
from catwalk.cloth.solvers import ClothExplosionError
from catwalk.cloth.solvers.explicit.solver import Solver
from catwalk.cloth.state import State

__all__ = ["Panel", "Seam", "build_cloth", "PRESETS", "Fabric", "get_fabric", "ClothModel",
           "State", "ClothExplosionError", "Solver"]
