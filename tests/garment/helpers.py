"""Small garments built in code for the tests."""

from __future__ import annotations

import argparse

import numpy as np

from catwalk.cli.garment import register
from catwalk.errors import CatwalkError
from catwalk.garment.geometry import Segment
from catwalk.garment.model import Garment, Panel, Placement, Seam, SeamSide, Shape


def rect(w, h, x0=0.0, y0=0.0):
    return [Segment("line", np.array(p, float)) for p in
            [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]]


def tube(width=0.5, height=0.7, sizes=("M",)):
    """Front and back rectangles sewn at both sides (a tube top)."""
    front = Panel("front", "front", {s: Shape(rect(width, height)) for s in sizes},
                  placement=Placement(side="front", anchor="bust"))
    back = Panel("back", "back", {s: Shape(rect(width, height)) for s in sizes},
                 placement=Placement(side="back", anchor="bust"))
    seams = [Seam(SeamSide("front", 1, 2), SeamSide("back", 3, 0), reverse=True, name="left"),
             Seam(SeamSide("front", 3, 0), SeamSide("back", 1, 2), reverse=True, name="right")]
    return Garment("tube", "top", list(sizes), [front, back], seams)


def cli(argv, capsys=None):
    """Run ``catwalk garment …`` through our own parser; returns (exit code, out, err)."""
    ap = argparse.ArgumentParser(prog="catwalk")
    top = ap.add_subparsers(dest="command")
    register(top, {})
    args = ap.parse_args(argv)
    try:
        rc = args.func(args)
        code = int(rc or 0)
        msg = ""
    except CatwalkError as exc:
        code, msg = 2, str(exc)
    out, err = ("", "")
    if capsys is not None:
        cap = capsys.readouterr()
        out, err = cap.out, cap.err
    return code, out, err + msg


BAD_VALUES = [None, "x", -1, [], {}, True]


def json_paths(node, path=()):
    """Every path into a JSON document, leaves and containers (lists: first two items)."""
    yield path
    if isinstance(node, dict):
        for k, v in node.items():
            yield from json_paths(v, (*path, k))
    elif isinstance(node, list):
        for i, v in enumerate(node[:2]):
            yield from json_paths(v, (*path, i))


def assert_only_input_errors(base: dict, use, bad_values=BAD_VALUES) -> int:
    """Replace every field of ``base`` in turn by each bad value and call ``use(doc)``: it may
    succeed or raise InputError (exit 2), never anything else (a traceback). Returns the count
    of documents tried."""
    import copy

    from catwalk.errors import InputError

    tried = 0
    for path in [p for p in json_paths(base) if p]:
        for bad in bad_values:
            doc = copy.deepcopy(base)
            node = doc
            for k in path[:-1]:
                node = node[k]
            node[path[-1]] = bad
            tried += 1
            try:
                use(doc)
            except InputError:
                pass
            except Exception as exc:
                raise AssertionError(f"{path} = {bad!r}: {type(exc).__name__}: {exc}") from exc
    return tried
