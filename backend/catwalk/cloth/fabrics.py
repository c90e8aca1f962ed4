"""Fabrics: measured properties and their mapping to spring constants.

A :class:`Fabric` carries continuum properties per unit width / area, in SI, with the pattern's
grain line (warp) along the pattern's +y axis and the weft along +x:

- ``density`` (kg/m²): mass per area;
- ``stretch_warp``, ``stretch_weft`` (N/m): tensile stiffness per unit width (force per width
  per unit strain, the KES-FB1 / FAST-3 extension stiffness);
- ``shear`` (N/m): in-plane shear stiffness per unit width (force per width per radian; KES
  ``G`` in gf/(cm·deg) × 56.2 gives N/m);
- ``bend_warp``, ``bend_weft`` (N·m): bending rigidity per unit width (KES ``B`` in
  gf·cm²/cm × 9.81e-5 gives N·m); ``bend_warp`` resists curvature along the warp;
- ``compression``: stretch and shear springs resist compression with this fraction of their
  tensile stiffness (fabrics buckle almost freely; Choi & Ko 2002 make the same point);
- ``damping`` (dimensionless damping ratio of each spring), ``air`` (1/s, air drag rate:
  f = −air·m·v), ``friction`` (Coulomb coefficient against the body), ``tau`` (strain limit of
  stretch and shear springs: they never exceed (1+τ)·rest).

:func:`spring_constants` maps them to Provot springs so that the same fabric behaves the same at
any grid spacing h (docs/cloth.md derives it):

- stretch spring of rest length L standing for a strip of width h: k = (E(θ) − G)·min(h/L, 1)
  (the two diagonal shear springs of a cell add G of tensile stiffness, so it is taken off;
  short outline edges are not made stiffer than grid springs);
- shear (diagonal) spring: k = G (two diagonals of an h×h cell give the cell shear energy ½Gγ²h²);
- bend spring [i]–[i+2] (rest 2h): its shortening under curvature κ is h³κ²/3, so its energy
  density is k·h⁴κ⁴/18 per unit area; k = 9·B / (κ₀²·h⁴) makes it equal to the continuum ½Bκ²
  at the reference curvature κ₀ = ``BEND_REFERENCE_CURVATURE`` and independent of h at every κ.
"""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np

from catwalk.config import REPO_DIR
from catwalk.errors import CatwalkError, InputError

#: κ₀ (1/m): the curvature at which a bend spring's energy matches the continuum ½Bκ²
#: (a fold of 4 cm radius, typical of the drape test and garment folds).
BEND_REFERENCE_CURVATURE = 25.0

# 1 gf·cm²/cm (KES bending rigidity B) in N·m, and 1 gf/(cm·deg) (KES shear G) in N/m.
KES_B_TO_SI = 9.80665e-3 * 1e-4 / 1e-2
KES_G_TO_SI = 9.80665e-3 / 1e-2 / (np.pi / 180.0)


@dataclass(frozen=True)
class Fabric:
    id: str
    name: str
    density: float
    stretch_warp: float
    stretch_weft: float
    shear: float
    bend_warp: float
    bend_weft: float
    damping: float = 0.05
    air: float = 0.3
    friction: float = 0.4
    tau: float = 0.05
    compression: float = 0.05
    source: str = ""

    def validate(self) -> Fabric:
        for field in ("density", "stretch_warp", "stretch_weft", "shear", "bend_warp",
                      "bend_weft"):
            val = getattr(self, field)
            if not (np.isfinite(val) and val > 0):
                raise InputError(f"fabric {self.id!r}: {field} must be a positive number, "
                                   f"got {val!r}")
        for field in ("damping", "air", "friction"):
            val = getattr(self, field)
            if not (np.isfinite(val) and val >= 0):
                raise InputError(f"fabric {self.id!r}: {field} must be ≥ 0, got {val!r}")
        if not (0.0 <= self.compression <= 1.0):
            raise InputError(f"fabric {self.id!r}: compression must be in [0, 1], "
                               f"got {self.compression!r}")
        if not (0.0 < self.tau < 1.0):
            raise InputError(f"fabric {self.id!r}: strain limit tau must be in (0, 1), "
                               f"got {self.tau!r}")
        return self

    def with_(self, **changes) -> Fabric:
        """A copy with some properties changed (``fabric.with_(bend_warp=1e-5)``)."""
        return replace(self, **changes).validate()

    def as_dict(self) -> dict:
        return asdict(self)


def stretch_stiffness(fabric: Fabric, cos2: np.ndarray) -> np.ndarray:
    """E(θ) for springs whose direction makes cos²θ with the pattern's x axis (weft)."""
    return fabric.stretch_weft * cos2 + fabric.stretch_warp * (1.0 - cos2)


def bend_rigidity(fabric: Fabric, cos2: np.ndarray) -> np.ndarray:
    """B(θ) for bend springs along a direction with cos²θ to the weft (x) axis."""
    return fabric.bend_weft * cos2 + fabric.bend_warp * (1.0 - cos2)


def spring_constants(fabric: Fabric, kind: np.ndarray, direction: np.ndarray,
                     rest: np.ndarray, h: float) -> np.ndarray:
    """Spring constants (N/m) for springs of ``kind`` (0 stretch, 1 shear, 2 bend) with 2D rest
    ``direction`` (unit or not) and ``rest`` length, at grid spacing ``h``."""
    d = np.asarray(direction, dtype=np.float64)
    nrm = np.maximum(np.linalg.norm(d, axis=1), 1e-300)
    cos2 = (d[:, 0] / nrm) ** 2
    k = np.empty(len(kind))
    st = kind == 0
    e = stretch_stiffness(fabric, cos2[st])
    k[st] = np.maximum(e - fabric.shear, 0.5 * e) * np.minimum(h / rest[st], 1.0)
    sh = kind == 1
    k[sh] = fabric.shear
    bd = kind == 2
    # the spacing a bend spring spans twice; outline bend springs shorter than the grid's
    # (points crowded at a dart tip or a tight curve) are not made stiffer than a grid one,
    # which would shrink the stable time step by the fourth power of the crowding
    half = np.maximum(0.5 * rest[bd], h)
    k[bd] = 9.0 * bend_rigidity(fabric, cos2[bd]) / (BEND_REFERENCE_CURVATURE ** 2 * half ** 4)
    return k


# --- presets ---------------------------------------------------------------------------------
# Representative values inside the ranges that KES-F / FAST measurements report for each class
# of fabric; docs/cloth.md gives the sources and which digits are the authors' choices.

PRESETS: dict[str, Fabric] = {
    f.id: f.validate()
    for f in (
        Fabric("cotton-jersey", "cotton single jersey (knit), ~180 g/m²", density=0.18,
               stretch_warp=120.0, stretch_weft=60.0, shear=10.0,
               bend_warp=2.0e-6, bend_weft=1.2e-6, damping=0.05, air=0.3, friction=0.5,
               tau=0.10,
               source="mass: typical 150–200 g/m² single jersey; B, G: knit range of KES-FB "
                      "surveys (Kawabata 1980; Kuijpers, Luible-Bär & Gong 2020)"),
        Fabric("denim", "cotton denim 3/1 twill, ~12 oz/yd² (407 g/m²)", density=0.407,
               stretch_warp=2000.0, stretch_weft=1200.0, shear=170.0,
               bend_warp=3.0e-5, bend_weft=2.0e-5, damping=0.05, air=0.3, friction=0.6,
               tau=0.03,
               source="mass: 12 oz/yd² = 407 g/m²; B ≈ 0.2–0.3 gf·cm²/cm and G ≈ 3 "
                      "gf/(cm·deg): heavy cotton twill range (Kawabata 1980; Kuijpers, "
                      "Luible-Bär & Gong 2020)"),
        Fabric("silk-charmeuse", "silk charmeuse, 19 momme (82 g/m²)", density=0.082,
               stretch_warp=350.0, stretch_weft=250.0, shear=15.0,
               bend_warp=6.0e-7, bend_weft=4.0e-7, damping=0.05, air=0.5, friction=0.2,
               tau=0.05,
               source="mass: 19 momme × 4.34 g/m²; B ≈ 0.005 gf·cm²/cm, G ≈ 0.3 gf/(cm·deg): "
                      "light silk range (Kawabata 1980; Kuijpers, Luible-Bär & Gong 2020)"),
        Fabric("wool-suiting", "worsted wool suiting, ~250 g/m²", density=0.25,
               stretch_warp=700.0, stretch_weft=550.0, shear=35.0,
               bend_warp=8.0e-6, bend_weft=6.0e-6, damping=0.05, air=0.3, friction=0.4,
               tau=0.04,
               source="mass: 230–270 g/m² suiting; B ≈ 0.08 gf·cm²/cm, G ≈ 0.6 gf/(cm·deg): "
                      "worsted suiting range of FAST/KES studies (De Boos & Tester 1994 SiroFAST "
                      "report; Kawabata 1980)"),
    )
}

DEFAULT_FABRIC = "cotton-jersey"

PETRAK_SOURCE = ("Petrak et al., Sustainability 2025, 17, 1388 (CC-BY 4.0): KES-FB derived "
                 "simulator inputs, via garments/fabrics/petrak2025-woven.json")


# The same six rows as garments/fabrics/petrak2025-woven.json (CC-BY 4.0, Petrak et al.
# 2025), kept here so that an installed package without the repository still has them.
_PETRAK_ROWS = [
    {"id": "m1", "name": "polyester twill 3/1", "mass": 0.1352, "bending_warp": 1.95e-6,
     "bending_weft": 0.61e-6, "stretch_warp": 477, "stretch_weft": 459, "shear": 41},
    {"id": "m2", "name": "polyester plain weave", "mass": 0.0837, "bending_warp": 0.85e-6,
     "bending_weft": 0.33e-6, "stretch_warp": 472, "stretch_weft": 374, "shear": 46},
    {"id": "m3", "name": "wool/polyester/elastane twill", "mass": 0.1787, "bending_warp": 2.14e-6,
     "bending_weft": 2.00e-6, "stretch_warp": 450, "stretch_weft": 440, "shear": 50},
    {"id": "m4", "name": "polyester/viscose/elastane twill", "mass": 0.2861,
     "bending_warp": 2.97e-6, "bending_weft": 2.40e-6, "stretch_warp": 403, "stretch_weft": 402,
     "shear": 61},
    {"id": "m5", "name": "polyester/elastane plain weave", "mass": 0.2420, "bending_warp": 3.22e-6,
     "bending_weft": 3.88e-6, "stretch_warp": 407, "stretch_weft": 415, "shear": 57},
    {"id": "m6", "name": "cotton/polyester/elastane twill", "mass": 0.2534,
     "bending_warp": 7.43e-6, "bending_weft": 3.70e-6, "stretch_warp": 474, "stretch_weft": 405,
     "shear": 126},
]


#: the measured fabrics as committed, beside their licence (garments/fabrics/README.md)
PETRAK_FILE = REPO_DIR / "garments" / "fabrics" / "petrak2025-woven.json"


def _petrak_path() -> Path | None:
    if PETRAK_FILE.is_file():
        return PETRAK_FILE
    for base in (REPO_DIR, *REPO_DIR.parents):
        for cand in (base / "shared" / "data" / "fabrics" / "petrak2025-woven.json",
                     base.parent / "shared" / "data" / "fabrics" / "petrak2025-woven.json"):
            if cand.is_file():
                return cand
    return None


def load_petrak(path: str | Path | None = None) -> dict[str, Fabric]:
    """The six measured woven fabrics of Petrak et al. 2025 as :class:`Fabric` (ids m1…m6)."""
    p = Path(path) if path is not None else _petrak_path()
    if p is None:
        rows, p = _PETRAK_ROWS, "built-in copy of petrak2025-woven.json"
    else:
        if not p.is_file():
            raise InputError(f"{p}: no such fabric table")
        try:
            rows = json.loads(p.read_text())["fabrics"]
        except (OSError, ValueError, KeyError, TypeError) as exc:
            raise InputError(f"{p}: not a fabric table ({exc})") from None
    out = {}
    for r in rows:
        try:
            f = Fabric(str(r["id"]), str(r["name"]), density=float(r["mass"]),
                       stretch_warp=float(r["stretch_warp"]),
                       stretch_weft=float(r["stretch_weft"]), shear=float(r["shear"]),
                       bend_warp=float(r["bending_warp"]), bend_weft=float(r["bending_weft"]),
                       tau=0.05, source=PETRAK_SOURCE)
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(f"{p}: bad fabric row {r!r} ({exc})") from None
        out[f.id] = f.validate()
    return out


def get_fabric(name: str | Fabric) -> Fabric:
    """A preset by id (``denim``…), a Petrak fabric (``m1``…``m6``), or a Fabric as is."""
    if isinstance(name, Fabric):
        return name.validate()
    if name in PRESETS:
        return PRESETS[name]
    if name.startswith("m") and name[1:].isdigit():
        table = load_petrak()
        if name in table:
            return table[name]
    known = ", ".join(list(PRESETS) + ["m1…m6"])
    raise InputError(f"unknown fabric {name!r} (known: {known})")


def resolve_fabric(spec, where: str = "fabric"):
    """A :class:`catwalk.cloth.fabrics.Fabric` from a preset name or a custom fabric object
    (``{"base": "denim", "density": 0.3}`` overrides a preset; otherwise every field of
    ``Fabric`` is given), or a ``Fabric`` itself."""

    if isinstance(spec, dict):
        fields = {f.name: f.type for f in dataclasses.fields(Fabric)}
        for key, value in spec.items():
            if key == "base":
                if not isinstance(value, str):
                    raise InputError(f"{where}: base must be a fabric preset name, got "
                                     f"{value!r:.60}")
            elif key not in fields:
                raise InputError(f"{where}: unknown fabric property {key!r:.60} (known: base, "
                                 f"{', '.join(fields)})")
            elif fields[key] in ("str", str):
                if not isinstance(value, str):
                    raise InputError(f"{where}: {key} must be a string, got {value!r:.60}")
            elif isinstance(value, bool) or not isinstance(value, (int, float)) \
                    or not math.isfinite(value):
                raise InputError(f"{where}: {key} must be a number, got {value!r:.60}")
    try:
        if isinstance(spec, Fabric):
            return spec.validate()
        if isinstance(spec, str):
            return get_fabric(spec)
        if isinstance(spec, dict):
            spec = dict(spec)
            if "base" in spec:
                base = get_fabric(spec.pop("base"))
                return base.with_(**spec)
            return Fabric(**spec).validate()
    except TypeError as exc:
        raise InputError(f"{where}: not a usable custom fabric ({exc})") from None
    except CatwalkError as exc:
        raise InputError(f"{where}: {exc}") from None
    raise InputError(f"{where}: a fabric is a preset name or an object, got {spec!r:.80}")


def fabric_choices() -> list[str]:
    """Every fabric a shopper may pick: the presets, then the measured (Petrak) fabrics."""
    return list(PRESETS) + sorted(load_petrak())
