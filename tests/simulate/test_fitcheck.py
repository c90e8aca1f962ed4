"""The dressing check (catwalk.simulate.fitcheck): a catalogue garment passes with sane figures,
a seam that cannot close is named with its gap, a fabric limit the cloth cannot keep fails the
strain check; bad input and cancelling are raised, a failed simulation is reported (small
scenes: the fast preset, the pencil skirt in size S on the sample body female-S)."""

import copy
import re

import pytest

from catwalk.errors import Cancelled, InputError
from catwalk.exchange.garment_json import load_garment
from catwalk.simulate import fitcheck
from catwalk.simulate.fitcheck import PENETRATION_LIMIT_MM, STRAIN_TOLERANCE, dressing_check

SKIRT = "garments/pencil-skirt.json"
KEYS = {"ok", "size", "seam_gap_mm", "worst_seam", "open_seams", "max_penetration_mm",
        "p99_penetration_mm", "max_strain", "strain_limit", "top_above_crotch_mm", "checks",
        "limits", "message", "seconds"}
CHECKS = {"stays_on", "seams_welded", "no_penetration", "strain_within_limit"}


@pytest.fixture(scope="module")
def skirt_body():
    """The sample body the skirt's S was drafted for (made once, kept in bodies/generated)."""
    from catwalk.catalogue.bodies import sample_body

    return sample_body("female-S")


@pytest.fixture
def skirt(repo_root):
    return load_garment(repo_root / SKIRT)


def test_a_catalogue_garment_passes(skirt_body, skirt):
    report, res = dressing_check(skirt_body, skirt, "S")
    assert set(report) == KEYS and set(report["checks"]) == CHECKS
    assert report["ok"] is True and all(v is True for v in report["checks"].values())
    assert report["size"] == "S" and res is not None and res.metrics["size"] == "S"
    assert res.walked is None                       # dressed standing, no walk
    # every seam welded
    assert report["seam_gap_mm"] == 0.0 and report["open_seams"] == []
    assert report["worst_seam"] in {s.name for s in skirt.seams}
    # nothing inside the body
    assert 0.0 <= report["p99_penetration_mm"] <= report["max_penetration_mm"]
    assert report["max_penetration_mm"] <= PENETRATION_LIMIT_MM
    # the wool suiting's limit; the cloth is stretched to it on the waist, and no further
    assert report["strain_limit"] == 0.04
    assert 0.03 < report["max_strain"] <= 0.04 + STRAIN_TOLERANCE
    assert report["max_strain"] == round(res.dressed.stats["max_strain"], 4)
    assert report["limits"] == {"seam_gap_mm": 30.0, "penetration_mm": PENETRATION_LIMIT_MM,
                                "strain": 0.04 + STRAIN_TOLERANCE}
    assert report["message"].startswith("dressed: every seam welded")
    assert "\n" not in report["message"]
    assert 0 < report["seconds"] < 60
    # the skirt hangs on the hips, not round the feet
    y = res.dressed.display[:, 1]
    assert y.max() > skirt_body.landmarks["crotch"][1]


@pytest.fixture(scope="module")
def unclosable(skirt_body, repo_root):
    """The skirt with its front panel placed a metre above where it belongs: the side seams
    cannot close (measured: 'side left' 98.0 mm, 'side right' 97.3 mm after sewing stalled)."""
    g = load_garment(repo_root / SKIRT)
    g.panel("front").placement.offset = [0.0, 1.0, 0.0]
    return g, dressing_check(skirt_body, copy.deepcopy(g), "S")


def test_a_seam_that_cannot_close_is_named(unclosable):
    _, (report, res) = unclosable
    assert set(report) == KEYS
    assert report["ok"] is False and report["checks"]["seams_welded"] is False
    assert res is None                               # catwalk.tryon refuses such a dressing
    names = [s["seam"] for s in report["open_seams"]]
    assert set(names) == {"side left", "side right"}
    gaps = [s["gap_mm"] for s in report["open_seams"]]
    assert gaps == sorted(gaps, reverse=True)         # widest first
    assert all(g > report["limits"]["seam_gap_mm"] for g in gaps)
    assert report["worst_seam"] == names[0] and report["seam_gap_mm"] == pytest.approx(gaps[0],
                                                                                      abs=0.1)
    # the darts and the centre back (within the back panels) closed
    assert "centre back" not in names and not any("dart" in n for n in names)
    msg = report["message"]
    assert msg.startswith("failed: seams still open (limit 3.0 cm):") and "\n" not in msg
    for s in report["open_seams"]:
        assert f"{s['seam']!r} by {s['gap_mm'] / 10:.1f} cm ({s['reason']})" in msg
        # the front hangs a metre up: the body lies between it and the back (measured 36–39 mm)
        assert s["body_between_mm"] > 5 and s["reason"].startswith("the body lies between")
    # the rest was still measured
    assert report["max_penetration_mm"] is not None and report["max_strain"] is not None


def test_the_open_seams_are_those_the_dressing_refuses(unclosable, skirt_body):
    """The same garment through catwalk.tryon: its DressingError names the same seams with
    the same gaps (the check runs the same simulation, with the refusal left to itself)."""
    import catwalk
    from catwalk.simulate import DressingError

    g, (report, _) = unclosable
    with pytest.raises(DressingError) as err:
        catwalk.tryon(skirt_body, g, size="S", seconds=0, preset="fast", measure=False)
    text = str(err.value)
    for s in report["open_seams"]:
        # the report's gap is rounded to 0.1 mm, the message's to 1 mm: 101.5 mm may read
        # "10.1 cm" there
        m = re.search(rf"{re.escape(repr(s['seam']))} by (\d+\.\d) cm", text)
        assert m and float(m.group(1)) == pytest.approx(s["gap_mm"] / 10, abs=0.051), text
    assert "'centre back' by" not in text


def test_a_strain_limit_the_cloth_cannot_keep_fails(skirt_body, skirt):
    """A custom fabric whose limit is tiny (τ = 0.002): the waist stays stretched past it."""
    skirt.fabric = {"base": "wool-suiting", "tau": 0.002}
    report, res = dressing_check(skirt_body, skirt, "S")
    assert report["strain_limit"] == 0.002
    assert report["max_strain"] > 0.002 + STRAIN_TOLERANCE
    assert report["checks"] == {"stays_on": True, "seams_welded": True,
                                "no_penetration": True, "strain_within_limit": False}
    assert report["ok"] is False and res is not None
    assert report["message"].startswith("failed: cloth stretched")
    assert "0.002" in report["message"] and "seams" not in report["message"]


def test_a_size_too_small_for_the_body_fails_the_strain_check(dressable_body, skirt):
    """The skirt's S on the MakeHuman base body, whose waist is wider than female-S's: the
    waistband, held by the body at both ends, stays over the wool's limit (≈ 0.07, τ 0.04)."""
    report, _ = dressing_check(dressable_body, skirt, "S")
    assert report["checks"]["seams_welded"] and report["checks"]["no_penetration"]
    assert report["checks"]["strain_within_limit"] is False and report["ok"] is False
    assert report["max_strain"] > 0.04 + STRAIN_TOLERANCE


def test_a_failed_simulation_is_reported(skirt_body, skirt, monkeypatch):
    import catwalk.simulate.tryon as entry
    from catwalk.cloth.solvers import ClothExplosionError

    def explodes(*a, **k):
        raise ClothExplosionError("the cloth blew up at 0.40 s")

    monkeypatch.setattr(entry, "dress", explodes)
    report, res = dressing_check(skirt_body, skirt, "S")
    assert res is None and report["ok"] is False and set(report) == KEYS
    assert report["message"] == "could not be dressed: the cloth blew up at 0.40 s"
    assert report["checks"] == dict.fromkeys(CHECKS)       # nothing could be measured
    assert report["max_strain"] is None and report["open_seams"] == []


def test_bad_input_and_cancelling_are_raised(skirt_body, skirt):
    with pytest.raises(InputError) as err:
        dressing_check(skirt_body, skirt, "XXL")
    assert err.value.field == "size"
    with pytest.raises(InputError):
        dressing_check(skirt_body, skirt, "S", preset="fastest")
    with pytest.raises(Cancelled):
        dressing_check(skirt_body, skirt, "S", cancel=lambda: True)


def test_the_table(monkeypatch, capsys):
    """`catwalk garment dress-check`: one row per size, the maxima under the table; exit 3
    when a size does not dress."""
    rows = [{"garment": "skirt", "body": "female-S", "ok": True, "size": "S",
             "seam_gap_mm": 0.0, "max_penetration_mm": 0.0, "p99_penetration_mm": 0.0,
             "max_strain": 0.0406, "strain_limit": 0.04, "seconds": 2.5, "message": "dressed"},
            {"garment": "shirt", "body": "female-M", "ok": False, "size": "M",
             "seam_gap_mm": 80.1, "max_penetration_mm": 0.5, "p99_penetration_mm": 0.0,
             "max_strain": 0.1036, "strain_limit": 0.1, "seconds": 2.7,
             "message": "failed: seams still open: 'sleeve' by 8.0 cm"},
            {"garment": "coat", "body": "female-M", "ok": False, "size": "M",
             "seam_gap_mm": None, "max_penetration_mm": None, "p99_penetration_mm": None,
             "max_strain": None, "strain_limit": None, "seconds": 0.4,
             "message": "could not be dressed: boom"}]
    monkeypatch.setattr(fitcheck, "run", lambda *a, **k: rows)
    from catwalk.cli.main import main

    assert main(["garment", "dress-check", "--preset", "fast"]) == 3
    out = capsys.readouterr().out
    assert "| skirt | S | female-S | yes | 0.0 | 0.00 (0.00) | 0.0406 (0.04) | 2.5 |" in out
    assert "| coat | M | female-M | no | | | | 0.4 |" in out
    assert ("over 2 dressings: max penetration 0.50 mm (p99 at most 0.00 mm), max strain − τ "
            "0.0036, widest seam gap 80.1 mm; 1/3 ok") in out
    assert "shirt M: failed: seams still open: 'sleeve' by 8.0 cm" in out


def test_a_garment_that_slides_off_fails(skirt_body, repo_root):
    """The front panel placed 60 cm to the side: the skirt sews shut and falls to the floor;
    every other check passes, the stays-on check does not."""
    g = load_garment(repo_root / SKIRT)
    g.panel("front").placement.offset = [0.6, 0.0, 0.0]
    report, res = dressing_check(skirt_body, g, "S")
    assert report["checks"]["seams_welded"] is True
    assert report["checks"]["stays_on"] is False and report["ok"] is False
    assert report["top_above_crotch_mm"] < 0
    assert report["message"].startswith("failed: the garment slid off the body")
