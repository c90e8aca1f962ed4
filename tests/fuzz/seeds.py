"""The valid files the fuzzers start from (made once per session, cached in memory).

- scans: the female MakeHuman body (``catwalk.body.rig.measured_base_body(0.0)``) as OBJ, PLY
  (binary and ASCII), binary STL and GLB (catwalk's body file, and trimesh's plain export);
  also the OBJ in centimetres;
- body: the same body as catwalk writes it (``catwalk.exchange.gltf.glb_bytes``);
- DXF: the AAMA/ASTM skirt as Gerber and CLO write it and the plain DXF of
  ``tests/garment/dxf_fixtures.py``, a catalogue garment exported by ``write_dxf``, and the
  skirt with what real exports carry (issue 46: cm under 'Units: METRIC', the sample size's
  'Quantity: 0', a piece of some sizes, repeated points, small self-crossing loops; as CLO and
  as Gerber write it) — so the mutations reach the repairs;
- garments: the catalogue (``garments/*.json``);
- markup: the FreeSewing markups (``garments/freesewing/markup``) with their drafts, the
  skirt markup of ``tests/garment/test_dxf.py`` with its DXF, and the real export's with its;
- GarmentCode: the two specifications in ``garments/garmentcode``;
- try-on files: a try-on .glb of a walking box body in a textured two-panel skirt
  (``tests/exchange/tryon_samples.py``).
"""

from __future__ import annotations

import importlib.util
import json
import tempfile
from functools import cache
from pathlib import Path

TESTS = Path(__file__).resolve().parents[1]
REPO = TESTS.parent
GARMENTS = REPO / "garments"
WORK = Path(tempfile.mkdtemp(prefix="catwalk-fuzz-"))


def _module(path: Path):
    spec = importlib.util.spec_from_file_location(f"_fuzz_{path.stem}", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@cache
def body():
    from catwalk.body.rig import measured_base_body

    return measured_base_body(0.0)


@cache
def body_glb() -> bytes:
    from catwalk.exchange.gltf import glb_bytes

    return glb_bytes(body())


@cache
def scans() -> dict[str, list[bytes]]:
    """Per scan format: the seed files."""
    import trimesh

    b = body()
    mesh = trimesh.Trimesh(b.vertices, b.faces, process=False)

    def export(m, **kw):
        out = m.export(**kw)
        return out.encode() if isinstance(out, str) else bytes(out)

    cm = trimesh.Trimesh(b.vertices * 100.0, b.faces, process=False)
    return {
        "obj": [export(mesh, file_type="obj"), export(cm, file_type="obj")],
        "ply": [export(mesh, file_type="ply"), export(mesh, file_type="ply", encoding="ascii")],
        "stl": [export(mesh, file_type="stl")],
        "glb": [body_glb(), export(mesh, file_type="glb")],
    }


@cache
def dxfs() -> list[bytes]:
    from catwalk.exchange.dxf import write_dxf
    from catwalk.exchange.garment_json import load_garment

    fx = _module(TESTS / "garment" / "dxf_fixtures.py")
    out = []
    for name, make in (("gerber.dxf", lambda p: fx.write_pattern(p, style="gerber")),
                       ("clo.dxf", lambda p: fx.write_pattern(p, style="clo", units="METRIC",
                                                              sizes=("M",))),
                       ("plain.dxf", fx.write_plain),
                       ("real-clo.dxf", fx.write_real_export),
                       ("real-gerber.dxf", lambda p: fx.write_real_export(p, style="gerber"))):
        make(WORK / name)
        out.append((WORK / name).read_bytes())
    write_dxf(load_garment(GARMENTS / "pencil-skirt.json"), WORK / "export.dxf", style="gerber")
    out.append((WORK / "export.dxf").read_bytes())
    return out


@cache
def garments() -> list[bytes]:
    return [p.read_bytes() for p in sorted(GARMENTS.glob("*.json"))]




@cache
def markups() -> list[tuple[bytes, str]]:
    """(markup, the pattern it applies to: a FreeSewing draft or a DXF path)."""
    out = []
    for m in sorted((GARMENTS / "freesewing" / "markup").glob("*.json")):
        draft = GARMENTS / "freesewing" / "drafts" / m.name
        if draft.is_file():
            out.append((m.read_bytes(), str(draft)))
    dxfs()
    fx = _module(TESTS / "garment" / "dxf_fixtures.py")
    out.append((json.dumps(fx.SKIRT_MARKUP).encode(), str(WORK / "gerber.dxf")))
    # a pocket of some sizes, the repaired outlines' numbering
    out.append((json.dumps(fx.real_export_markup()).encode(), str(WORK / "real-clo.dxf")))
    return out


@cache
def garmentcode() -> list[bytes]:
    return [p.read_bytes() for p in sorted((GARMENTS / "garmentcode").glob("*.json"))]


@cache
def tryons() -> list[bytes]:
    from catwalk.exchange.tryon_glb import tryon_bytes

    ts = _module(TESTS / "exchange" / "tryon_samples.py")
    png = ts.stripes_png(WORK / "stripes.png")
    return [tryon_bytes(ts.box_body(), ts.motion(12), [ts.skirt(texture=png, frames=5)]),
            tryon_bytes(ts.box_body(), None, [ts.skirt(frames=3)], normals=False)]
