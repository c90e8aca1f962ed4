"""``catwalk garment …``: check a garment, import DXF / GarmentCode patterns.

- ``catwalk garment check FILE [--json]``
- ``catwalk garment import FILE.dxf [--size S] [--units U] [--markup M.json] [--json] -o G.json``
- ``catwalk garment from-garmentcode SPEC.json [--markup M.json] -o G.json``
- ``catwalk garment from-freesewing DRAFT.json [--markup M.json] -o G.json`` (``--describe``)
- ``catwalk garment edit G.json --panel P [--move DX DY] [--rotate DEG] [--mirror x|y]
  [--type T] [--texture IMG] [--fabric F] -o OUT.json``
- ``catwalk garment export-dxf G.json [--style clo|gerber] [--units METRIC|ENGLISH] -o P.dxf``
- ``catwalk garment catalogue``: rebuild ``garments/`` from its sources and check every garment
- ``catwalk garment freesewing-lengths [-o garments/freesewing/lengths.json]``: the sample
  bodies' lengths that ``garments/freesewing/draft.mjs`` drafts with
- ``catwalk garment info FILE [--size S] [--json]``: panels, areas, seam lengths
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from catwalk.catalogue.garments import build_catalogue, catalogue_dir
from catwalk.catalogue.lengths import BODY_LENGTHS, freesewing_lengths
from catwalk.errors import InputError
from catwalk.exchange.dxf import pieces_to_garment, read_dxf, write_dxf
from catwalk.exchange.freesewing import describe, load_freesewing
from catwalk.exchange.garment_json import (
    garment_from_dict,
    garment_to_dict,
    load_garment,
    save_garment,
)
from catwalk.exchange.garmentcode import load_garmentcode
from catwalk.exchange.markup import apply_markup, load_markup
from catwalk.fileio import atomic_path, check_writable
from catwalk.garment.check import check_garment, require_valid
from catwalk.garment.edit import edit
from catwalk.simulate import fitcheck


def _check(args) -> int:
    g = load_garment(args.file)
    rep = check_garment(g)
    if args.json:
        print(json.dumps(rep.as_dict(), indent=1))
    else:
        for w in rep.warnings:
            print(f"warning: {w}", file=sys.stderr)
        if rep.ok:
            print(f"{args.file}: garment {g.name!r} ({g.type}), sizes {', '.join(g.sizes)}, "
                  f"{len(g.panels)} panels, {len(g.seams)} seams: ok")
    if rep.errors:
        raise InputError(f"{args.file}: garment {g.name!r} has {len(rep.errors)} problem(s):\n  "
                         + "\n  ".join(rep.errors))
    return 0


def _output(out: str, suffix: str, what: str) -> None:
    """Refuse, before reading any input, an output with the wrong extension or a place it
    cannot be written."""
    if not str(out).lower().endswith(suffix):
        raise InputError(f"-o {out}: {what} is written as a {suffix} file")
    check_writable(out, "-o")


def _write(g, out: str, strict: bool) -> None:
    try:   # what is written must read back: the format's reader has the last word
        garment_from_dict(garment_to_dict(g), name=f"garment {g.name!r}")
    except InputError as exc:
        raise InputError(f"-o {out}: not written: {exc}") from None
    if strict:
        require_valid(g, Path(out).parent)
    else:
        rep = check_garment(g, Path(out).parent)
        geometry = [e for e in rep.errors if "reachable" not in e]
        if geometry:
            raise InputError(f"garment {g.name!r} has {len(geometry)} problem(s):\n  "
                             + "\n  ".join(geometry))
        if rep.errors:
            print("note: no seams yet (give --markup); `catwalk garment check` will ask for "
                  "them", file=sys.stderr)
    save_garment(g, out, "-o")


def _import(args) -> int:
    _output(args.output, ".json", "the garment")
    markup = load_markup(args.markup) if args.markup else None
    pieces, warnings = read_dxf(args.file, size=args.size, units=args.units)
    for w in warnings:
        print(f"warning: {w['message']}", file=sys.stderr)
    source = {"dxf": Path(args.file).name, "importer": "catwalk garment import"}
    g = pieces_to_garment(pieces, Path(args.file).stem, source=source)
    if markup is not None:
        apply_markup(g, markup, str(args.markup))
    _write(g, args.output, strict=markup is not None)
    if args.json:
        print(json.dumps({"pieces": [p.summary() for p in pieces], "warnings": warnings},
                         indent=1))
    else:
        for p in pieces:
            s = p.summary()
            qty = str(s["quantity"]) if s["flipped"] is None else \
                f"{s['quantity']} ({s['flipped']} flipped)"
            print(f"{s['name']:<24} size {s['size']:<8} qty {qty}  "
                  f"area {s['area_m2']:.4f} m²  perimeter {s['perimeter_m']:.3f} m  "
                  f"notches {s['notches']}  mirror line {'yes' if s['mirrored'] else 'no'}")
        print(f"wrote {args.output}", file=sys.stderr)
    return 0


def _from_garmentcode(args) -> int:
    _output(args.output, ".json", "the garment")
    g = load_garmentcode(args.file, name=args.name, garment_type=args.type, size=args.size)
    if args.markup:
        apply_markup(g, load_markup(args.markup), str(args.markup))
    _write(g, args.output, strict=True)
    print(f"wrote {args.output}: {len(g.panels)} panels, {len(g.seams)} seams", file=sys.stderr)
    return 0


def _from_freesewing(args) -> int:
    g = load_freesewing(args.file)
    if args.describe:
        print(describe(g, args.size))
        return 0
    if not args.output:
        raise InputError("-o: the garment is written as a .json file")
    _output(args.output, ".json", "the garment")
    if args.markup:
        apply_markup(g, load_markup(args.markup), str(args.markup))
    _write(g, args.output, strict=bool(args.markup))
    print(f"wrote {args.output}: {len(g.panels)} panels, {len(g.seams)} seams, sizes "
          f"{', '.join(g.sizes)}", file=sys.stderr)
    return 0


def _edit(args) -> int:
    _output(args.output, ".json", "the garment")
    g = load_garment(args.file)
    edit(g, args.panel, move=args.move, rotate=args.rotate, mirror=args.mirror,
         ptype=args.type, texture=args.texture, texture_size=args.texture_size,
         fabric=args.fabric)
    _write(g, args.output, strict=True)
    print(f"wrote {args.output}", file=sys.stderr)
    return 0


def _catalogue(args) -> int:
    for line in build_catalogue(args.root, only=args.only):
        print(line)
    return 0


def _freesewing_lengths(args) -> int:
    if args.output is None:
        args.output = str(catalogue_dir() / "freesewing" / "lengths.json")
    if args.output != "-":   # before measuring a dozen bodies: can it be written at all?
        check_writable(args.output, "-o")
    data = {"about": "Lengths and girths (mm) of catwalk's sample bodies (bodies/recipes.json) "
                     "that draft.mjs puts in place of the FreeSewing model set's: "
                     + ", ".join(BODY_LENGTHS)
                     + " (bustSpan: women only). Made by `catwalk garment freesewing-lengths`.",
            "bodies": freesewing_lengths()}
    text = json.dumps(data, indent=1) + "\n"
    if args.output == "-":
        print(text, end="")
        return 0
    try:
        with atomic_path(args.output) as tmp:
            tmp.write_text(text)
    except OSError as exc:
        raise InputError(f"-o {args.output}: cannot write it ({exc.strerror})") from None
    for name, v in data["bodies"].items():
        print(f"{name}: " + ", ".join(f"{k} {x:.0f} mm" for k, x in v.items()))
    return 0


def _export_dxf(args) -> int:
    _output(args.output, ".dxf", "the pattern")
    g = load_garment(args.file)
    n = write_dxf(g, args.output, style=args.style, units=args.units)
    print(f"wrote {args.output}: {n} blocks ({args.style} style, {args.units})", file=sys.stderr)
    return 0


def _info(args) -> int:
    g = load_garment(args.file)
    rep = check_garment(g)
    rows = [r for r in rep.panels if args.size is None or r["size"] == args.size]
    seams = [r for r in rep.seams if args.size is None or r["size"] == args.size]
    if args.json:
        print(json.dumps({"panels": rows, "seams": seams, "errors": rep.errors}, indent=1))
        return 0
    for r in rows:
        print(f"{r['size']:<6} {r['panel']:<20} area {r['area_m2']:.4f} m²  perimeter "
              f"{r['perimeter_m']:.3f} m  edges {r['edges']}"
              + ("  (cut on fold)" if r["fold"] else "")
              + (f"  (copy of {r['copy_of']})" if r["copy_of"] else ""))
    for r in seams:
        print(f"{r['size']:<6} seam {r['seam']:<3} {r['name']:<20} {r['length_a_m']:.4f} m ↔ "
              f"{r['length_b_m']:.4f} m  ({r['difference'] * 100:.2f} %)")
    for e in rep.errors:
        print(f"error: {e}", file=sys.stderr)
    return 0


def _dress_check_arguments(ap) -> None:
    """``catwalk garment dress-check``'s arguments."""
    ap.add_argument("garments", nargs="*", help="garment JSON files (default: garments/*.json)")
    ap.add_argument("--preset", default="fast", choices=["fast", "balanced", "accurate"])
    ap.add_argument("--samples-dir", default=None,
                    help="where sample bodies are made and kept (default: bodies/generated)")
    ap.add_argument("--json", action="store_true", help="the reports as JSON")


def _dress_check(args) -> int:
    """``catwalk garment dress-check``: a table (or JSON) of every size's check; exit 3 when a
    size does not dress."""
    def log(row):
        print(f"{row['garment']} {row['size']} on {row['body']}: {row['seconds']} s, "
              f"{'ok' if row['ok'] else row['message']}", file=sys.stderr)

    rows = fitcheck.run(args.garments, args.preset, args.samples_dir, log)
    print(json.dumps(rows, indent=1) if args.json else fitcheck.format_table(rows))
    return 0 if all(r["ok"] for r in rows) else 3


def register(top, groups) -> None:
    help_text = "garments: check, import DXF / GarmentCode patterns"
    gp = top.add_parser("garment", help=help_text, description=help_text)
    sub = gp.add_subparsers(dest="garment_command", metavar="COMMAND")
    sub.required = True
    groups["garment"] = sub

    p = sub.add_parser("check", help="validate a garment file (exit 2 with every problem)")
    p.add_argument("file")
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    p.set_defaults(func=_check)

    p = sub.add_parser("dress-check", help="dress every size on its sample body standing and "
                       "check it: seams welded, no penetration, strain within the fabric's "
                       "limit, held up by the body (exit 3 if a size fails)")
    _dress_check_arguments(p)
    p.set_defaults(func=_dress_check)

    p = sub.add_parser("import", help="import an AAMA/ASTM or plain DXF pattern")
    p.add_argument("file")
    p.add_argument("--size", help="import only this size")
    p.add_argument("--units", choices=["in", "mm", "cm", "m", "ft"],
                   help="units of the file when it does not say (overrides Units:/$INSUNITS)")
    p.add_argument("--markup", help="markup JSON: panel types, seams, fabric, placement")
    p.add_argument("--json", action="store_true",
                   help="print {\"pieces\", \"warnings\"} as JSON: each piece's name, size, "
                        "quantity, flipped (ASTM's mirrored copies), area_m2, perimeter_m, "
                        "notches, mirrored (a mirror line); each repair or assumption made as "
                        "{code, message, piece?, size?, …}")
    p.add_argument("-o", "--output", required=True, help="garment JSON to write")
    p.set_defaults(func=_import)

    p = sub.add_parser("from-garmentcode", help="convert a GarmentCode pattern specification")
    p.add_argument("file")
    p.add_argument("--name", help="garment name (default: the file's)")
    p.add_argument("--type", help="garment type (default: guessed from the panels)")
    p.add_argument("--size", default="M", help="size label of this specification (default M)")
    p.add_argument("--markup", help="markup JSON applied after conversion")
    p.add_argument("-o", "--output", required=True)
    p.set_defaults(func=_from_garmentcode)

    p = sub.add_parser("from-freesewing",
                       help="convert a FreeSewing draft (garments/freesewing/draft.mjs output)")
    p.add_argument("file")
    p.add_argument("--markup", help="markup JSON: names, types, seams, placement")
    p.add_argument("--describe", action="store_true",
                   help="print every panel's vertices and edges (to write the markup)")
    p.add_argument("--size", help="size to describe")
    p.add_argument("-o", "--output")
    p.set_defaults(func=_from_freesewing)

    p = sub.add_parser("edit", help="the editor's operations on a panel: move, rotate, mirror, "
                                    "type, texture, fabric")
    p.add_argument("file")
    p.add_argument("--panel", required=True)
    p.add_argument("--move", nargs=2, type=float, metavar=("DX", "DY"), help="metres")
    p.add_argument("--rotate", type=float, metavar="DEG",
                   help="counter-clockwise, about the panel's centre")
    p.add_argument("--mirror", choices=["x", "y"], help="x: left ↔ right, y: up ↔ down")
    p.add_argument("--type", help="panel type")
    p.add_argument("--texture", help="image path, relative to the output file")
    p.add_argument("--texture-size", nargs=2, type=float, metavar=("W", "H"),
                   help="metres one repeat covers")
    p.add_argument("--fabric", help="fabric preset")
    p.add_argument("-o", "--output", required=True)
    p.set_defaults(func=_edit)

    p = sub.add_parser("export-dxf", help="write a garment as an AAMA-style DXF R12 pattern")
    p.add_argument("file")
    p.add_argument("--style", choices=["clo", "gerber"], default="clo")
    p.add_argument("--units", choices=["METRIC", "ENGLISH"], default="METRIC")
    p.add_argument("-o", "--output", required=True)
    p.set_defaults(func=_export_dxf)

    p = sub.add_parser("catalogue", help="rebuild the catalogue in garments/ (textures, "
                                         "FreeSewing and GarmentCode garments) and check it")
    p.add_argument("--root", default=None, help="the garments folder (default: the repo's)")
    p.add_argument("--only", nargs="*", help="only these garment ids")
    p.set_defaults(func=_catalogue)

    p = sub.add_parser("freesewing-lengths",
                       help="the sample bodies' lengths (mm) that the FreeSewing drafts use")
    p.add_argument("-o", "--output", default=None,
                   help="where to write them (default garments/freesewing/lengths.json; - for "
                        "stdout)")
    p.set_defaults(func=_freesewing_lengths)

    p = sub.add_parser("info", help="panels (area, perimeter) and seam lengths of a garment")
    p.add_argument("file")
    p.add_argument("--size")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_info)
