"""Every file reader on damaged files: each input ends in InputError or a sane result, never
another exception, a printed warning, a hang (> 5 s) or a huge allocation (harness.py).

``make fuzz`` is the deep run (10,000 inputs per fuzzer: ``CATWALK_FUZZ_EXAMPLES``); by
default each tries a few (the suite within a minute).
"""

from __future__ import annotations

from collections import Counter

from hypothesis import given
from hypothesis import strategies as st

from . import mutate, seeds
from .harness import TALLY, check, fuzz_settings


def _scan(fmt: str, strategy):
    @fuzz_settings()
    @given(case=strategy(seeds.scans()[fmt]))
    def run(worker, case):
        check(f"scan {fmt}", worker.run("scan", case.data, {"format": fmt}), case.data, case.how)

    return run


test_scan_obj = _scan("obj", mutate.text)
test_scan_ply = _scan("ply", mutate.ply)
test_scan_stl = _scan("stl", mutate.stl)
test_scan_glb = _scan("glb", mutate.glb)


@fuzz_settings()
@given(case=mutate.glb([seeds.body_glb()]))
def test_body_glb(worker, case):
    check("body glb", worker.run("body", case.data), case.data, case.how)


@fuzz_settings()
@given(case=mutate.dxf(seeds.dxfs()), units=st.sampled_from([None, None, "mm", "in"]))
def test_dxf(worker, case, units):
    answer = worker.run("dxf", case.data, {"units": units})
    check("dxf", answer, case.data, case.how)
    if answer["outcome"] == "ok":   # how many were read with a repair (issue 46's seeds)
        repaired = " 0 repairs" not in answer["message"]
        TALLY.setdefault("dxf read", Counter())["repaired" if repaired else "as drawn"] += 1


@fuzz_settings()
@given(case=mutate.json_doc(seeds.garments()))
def test_garment_json(worker, case):
    check("garment json", worker.run("garment", case.data, {"base_dir": str(seeds.GARMENTS)}),
          case.data, case.how)


@fuzz_settings()
@given(which=st.integers(0, len(seeds.markups()) - 1), ops=st.data())
def test_markup(worker, which, ops):
    markup, base = seeds.markups()[which]
    case = ops.draw(mutate.json_doc([markup]))
    check("markup", worker.run("markup", case.data, {"base": base}), case.data, case.how)


@fuzz_settings()
@given(case=mutate.json_doc(seeds.garmentcode()),
       gtype=st.sampled_from([None, None, None, "dress", "spaceship", ""]),
       size=st.sampled_from(["M", "M", "", " ", "XL"]))
def test_garmentcode(worker, case, gtype, size):
    check("garmentcode", worker.run("garmentcode", case.data, {"type": gtype, "size": size}),
          case.data, f"{case.how}; type {gtype!r}, size {size!r}")


@fuzz_settings()
@given(case=mutate.glb(seeds.tryons()))
def test_tryon_glb_scene(worker, case):
    check("try-on glb (render)", worker.run("scene", case.data), case.data, case.how)
