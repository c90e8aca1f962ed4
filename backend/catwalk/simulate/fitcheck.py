"""The dressing check: does a garment dress, in one size, on that size's sample body?

A merchant's garment upload runs :func:`dressing_check` once per size (docs/tryon.md,
"Dressing check"): the garment is dressed standing with :func:`catwalk.tryon` (``seconds=0``,
the ``fast`` preset by default) and the result is checked three ways:

- **seams welded**: no seam still open by more than the preset's ``max_open_gap`` (3 cm), the
  limit over which :func:`catwalk.tryon` itself refuses the dressing. The dressing is run with
  that refusal turned off, so that a seam that cannot close is reported by name with its gap
  (``open_seams``) instead of only in an error message; the simulation is the same (the limit
  is only looked at once the garment has settled) and the result is then refused all the same
  (no :class:`~catwalk.simulate.tryon.TryOn` is returned);
- **no penetration**: the deepest cloth point inside the body, measured independently of the
  collider (:mod:`catwalk.geometry.surface`) on the cloth as shown (``Dressed.display``)
  against the body it was dressed on, within ``PENETRATION_LIMIT_MM``;
- **strain within limit**: the stretch/shear springs' largest strain after the dressing
  (``Dressed.stats["max_strain"]``) within the fabric's limit τ plus ``STRAIN_TOLERANCE``.

``catwalk garment dress-check`` runs it on every catalogue garment in every size on its
sample body (or on the garment files named) and prints a table; the thresholds below were
chosen from its figures.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from catwalk.catalogue.bodies import sample_body
from catwalk.catalogue.garments import catalogue_files
from catwalk.errors import SimulationError
from catwalk.exchange.garment_json import load_garment
from catwalk.geometry.surface import BodySurface, penetration
from catwalk.simulate.dressing import seam_names
from catwalk.simulate.tryon import resolve_settings, tryon
from catwalk.simulate.walking import strain_of

if TYPE_CHECKING:
    from catwalk.simulate.tryon import TryOn

# Thresholds, measured with `catwalk garment dress-check` (preset fast: the 7 catalogue
# garments in S, M, L on the sample body of each size, 21 dressings; docs/tryon.md, "Dressing
# check"). Penetration: 0.00 mm in all 21 (p99 0.00 mm): the collider keeps the cloth 4 mm
# (the fast preset's thickness) off the skin, and measured separately on the same 21 the
# closest cloth point was 3.6–4.0 mm outside the body. The limit, 2 mm inside, is what
# tests/simulate/test_catalogue_dressing.py allows too.
PENETRATION_LIMIT_MM = 2.0
# Max strain − τ after the strain relief (which stops at τ + 0.001): at most 0.0009 in all 21
# (bodice S, trousers M and L). The tolerance is 0.01 over τ, ten times that (and what
# tests/simulate/test_catalogue_dressing.py allows).
STRAIN_TOLERANCE = 0.01
# the dressing's own refusal is turned off (see the module docstring): no gap is that wide
_NEVER_REFUSE_M = 1.0e3


def dressing_check(body, garment, size: str | None, *, preset="fast",
                   cancel: Callable[[], bool] | None = None) -> tuple[dict, TryOn | None]:
    """Dress ``body`` (a :class:`~catwalk.body.types.Body` or a body .glb, as
    :func:`catwalk.tryon` takes it) in ``garment`` (a Garment, a dict or a garment JSON) in
    ``size``, standing, with ``preset`` (a name or a
    :class:`~catwalk.simulate.settings.Settings`), and check the result.

    Returns ``(report, tryon)``. The report: ``ok`` (every check passed), ``size``,
    ``seam_gap_mm`` (the widest seam gap left; 0 when every seam is welded), ``worst_seam``,
    ``open_seams`` (``[{"seam", "gap_mm"}]``, widest first: those over the preset's
    ``max_open_gap``), ``max_penetration_mm`` and ``p99_penetration_mm`` (cloth points inside
    the body), ``max_strain`` and ``strain_limit`` (the fabric's τ), ``checks``
    (``seams_welded``, ``no_penetration``, ``strain_within_limit``: booleans; None when the
    simulation failed before anything could be measured), ``limits`` (the thresholds used:
    ``seam_gap_mm``, ``penetration_mm``, ``strain``), ``message`` (one line naming what
    failed) and ``seconds`` (wall clock). ``tryon`` is the dressed
    :class:`~catwalk.simulate.tryon.TryOn`, or None when the garment could not be dressed
    (a seam left open, or a :class:`~catwalk.errors.SimulationError`, whose message the
    report keeps). :class:`~catwalk.errors.InputError` (bad garment, size, preset) and
    :class:`~catwalk.errors.Cancelled` (``cancel()`` returned true) are raised.
    """
    t0 = time.perf_counter()
    settings = resolve_settings(preset)
    seam_limit = settings.max_open_gap
    report = {
        "ok": False, "size": size, "seam_gap_mm": None, "worst_seam": None, "open_seams": [],
        "max_penetration_mm": None, "p99_penetration_mm": None, "max_strain": None,
        "strain_limit": None,
        "checks": {"stays_on": None, "seams_welded": None, "no_penetration": None,
                   "strain_within_limit": None},
        "top_above_crotch_mm": None,
        "limits": {"seam_gap_mm": round(1e3 * seam_limit, 1),
                   "penetration_mm": PENETRATION_LIMIT_MM, "strain": None},
        "message": "", "seconds": None,
    }
    try:
        res = tryon(body, garment, size=size, seconds=0,
                    preset=settings.with_(max_open_gap=_NEVER_REFUSE_M), measure=False,
                    cancel=cancel)
    except SimulationError as exc:   # InputError and Cancelled are not: they go up
        report["message"] = f"could not be dressed: {exc}"
        report["seconds"] = round(time.perf_counter() - t0, 2)
        return report, None

    d = res.dressed
    st = d.stats
    report["size"] = st["size"]
    # seams: the gap each seam has left (0: welded), as the dressing measured it
    gaps = {name: 1e3 * float(g) for name, g in st["seam_gaps_m"].items()}
    report["seam_gap_mm"] = round(1e3 * float(st["seam_gap_m"]), 2)
    report["worst_seam"] = st["worst_seam"]
    report["open_seams"] = [{"seam": name, "gap_mm": round(g, 1)}
                            for name, g in sorted(gaps.items(), key=lambda kv: -kv[1])
                            if g > 1e3 * seam_limit]
    # penetration: the cloth as shown against the body it was dressed on (its rest pose)

    b = res.body
    surface = BodySurface(b.faces, len(b.vertices))
    if report["open_seams"]:
        _explain_open_seams(report["open_seams"], d, b, surface, seam_names(d.cloth.garment))
    shown = d.display if d.display is not None else d.state.positions
    pen = 1e3 * penetration(surface, b.vertices, shown)
    report["max_penetration_mm"] = round(float(pen.max()), 2) if len(pen) else 0.0
    report["p99_penetration_mm"] = round(float(np.percentile(pen, 99)), 2) if len(pen) else 0.0
    # strain: after the strain relief, against the fabric's limit
    tau = float(d.cloth.fabric.tau)
    strain = float(st["max_strain"])
    report["max_strain"] = round(strain, 4) if math.isfinite(strain) else None
    report["strain_limit"] = tau
    report["limits"]["strain"] = round(tau + STRAIN_TOLERANCE, 4)

    # held up by the body: a garment sewn shut that slid off (a panel placed far from the
    # body) ends below the crotch; every garment worn reaches above it (the catalogue's tops
    # are 27–66 cm above)
    crotch = b.landmarks.get("crotch")
    top = float(shown[:, 1].max()) if len(shown) else float("-inf")
    report["top_above_crotch_mm"] = round(1e3 * (top - float(crotch[1])), 1) \
        if crotch is not None else None
    checks = {
        "stays_on": crotch is None or top > float(crotch[1]),
        "seams_welded": not report["open_seams"],
        "no_penetration": report["max_penetration_mm"] <= PENETRATION_LIMIT_MM,
        "strain_within_limit": math.isfinite(strain) and strain <= tau + STRAIN_TOLERANCE,
    }
    report["checks"] = checks
    report["ok"] = all(checks.values())
    report["message"] = _message(report, 1e3 * seam_limit, tau)
    report["seconds"] = round(time.perf_counter() - t0, 2)
    return report, (res if checks["seams_welded"] else None)


# why a seam stayed open: the body lies between its two sides by more than this (the panels
# were placed on either side of a limb or the torso), or the cloth at its points is within this
# of the fabric's strain limit (the garment is too small or too short there for this body)
BODY_BETWEEN_MM = 5.0
AT_LIMIT = 0.005


def _explain_open_seams(open_seams: list[dict], d, body, surface, names: list[str]) -> None:
    """Add to each open seam where its widest pair is: how far the body lies between its two
    sides, the largest strain of the springs at them, and the reason that makes."""
    m, x = d.model, d.state.positions
    gap = np.linalg.norm(x[m.seam_b] - x[m.seam_a], axis=1)
    strain = strain_of(m, x)
    ends_a, ends_b = m.spring_a[:len(strain)], m.spring_b[:len(strain)]
    tau = float(d.cloth.fabric.tau)
    for entry in open_seams:
        ids = [k for k, name in enumerate(names) if name == entry["seam"]]
        pairs = np.nonzero(np.isin(m.seam_id, ids))[0]
        if not len(pairs):
            continue
        k = pairs[np.argmax(gap[pairs])]
        a, b = x[m.seam_a[k]], x[m.seam_b[k]]
        line = a[None] + np.linspace(0.0, 1.0, 21)[:, None] * (b - a)[None]
        between = 1e3 * float(penetration(surface, body.vertices, line).max())
        sides = (m.seam_a[k], m.seam_b[k])
        near = np.isin(ends_a, sides) | np.isin(ends_b, sides)
        at = float(strain[near].max()) if near.any() else 0.0
        entry["body_between_mm"] = round(between, 1)
        entry["strain"] = round(at, 4)
        entry["reason"] = _reason(between, at, tau)


def _reason(between: float, at: float, tau: float) -> str:
    """Why a seam stayed open, from what was measured at its widest pair: how far the body
    lies between its sides (mm) and the strain at them against the fabric's τ."""
    through, stretched = between > BODY_BETWEEN_MM, at >= tau - AT_LIMIT
    body = f"the body lies between its two sides ({between / 10:.1f} cm)"
    limit = f"the cloth at it is stretched to the fabric's limit ({at:.3f}, τ {tau:g})"
    if through and stretched:
        return (f"{body} and {limit}: the garment is too small there for this body, or its "
                "panels were placed on either side of it; check the size and the placement")
    if through:
        return f"{body}: sewing pulls the panels through the body; check their placement"
    if stretched:
        return f"{limit}: the garment is too small or too short there for this body"
    return "sewing did not pull it shut: check the seam's direction and its sides' lengths"


def _message(report: dict, seam_limit_mm: float, tau: float) -> str:
    """One line: what failed, or the figures of a garment that dressed."""
    checks = report["checks"]
    pen, strain = report["max_penetration_mm"], report["max_strain"]
    if report["ok"]:
        gap = ("every seam welded" if report["seam_gap_mm"] == 0 else
               f"every seam closed to within {report['seam_gap_mm']:.1f} mm")
        return (f"dressed: {gap}, deepest cloth point {pen:.1f} mm inside the body, "
                f"max strain {strain:.3f} (fabric limit {tau:g})")
    failed = []
    if not checks["stays_on"]:
        failed.append(f"the garment slid off the body (its top is "
                      f"{-report['top_above_crotch_mm'] / 10:.0f} cm below the crotch; check "
                      "the placement hints)")
    if not checks["seams_welded"]:
        seams = "; ".join(f"{s['seam']!r} by {s['gap_mm'] / 10:.1f} cm"
                          + (f" ({s['reason']})" if s.get("reason") else "")
                          for s in report["open_seams"])
        failed.append(f"seams still open (limit {seam_limit_mm / 10:.1f} cm): {seams}")
    if not checks["no_penetration"]:
        failed.append(f"cloth {pen:.1f} mm inside the body (limit {PENETRATION_LIMIT_MM:g} mm)")
    if not checks["strain_within_limit"]:
        failed.append(f"cloth stretched {strain if strain is not None else float('nan'):.3f} "
                      f"(fabric limit {tau:g} + {STRAIN_TOLERANCE:g})")
    return "failed: " + "; ".join(failed)


# ---------------------------------------------------------------------------- the table

# the sample bodies (bodies/recipes.json) a size is dressed on when the garment names none
LADDER = ("XS", "S", "M", "L", "XL", "XXL")


def sample_for(garment, size: str) -> str:
    """The sample body a size is checked on: the garment's ``fit`` for it, else the ladder
    XS…XXL (women's; men's for trousers) by the size's name, or by its place among the
    garment's sizes (the middle one on M; more sizes than rungs spread over the ladder)."""
    if garment.fit.get(size):
        return garment.fit[size]
    sex = "male" if garment.type == "trousers" else "female"
    if size.upper() in LADDER:
        return f"{sex}-{size.upper()}"
    i, n = garment.sizes.index(size), len(garment.sizes)
    mid = LADDER.index("M")
    k = mid + (i - (n - 1) // 2) if n <= len(LADDER) else round(i * (len(LADDER) - 1) / (n - 1))
    return f"{sex}-{LADDER[min(max(k, 0), len(LADDER) - 1)]}"


def run(paths=None, preset: str = "fast", samples_dir=None, log=None) -> list[dict]:
    """:func:`dressing_check` on every garment in ``paths`` (default: the catalogue's
    garments/*.json) in every size, on its sample body; one row per size."""
    paths = [Path(p) for p in paths] if paths else catalogue_files()
    bodies, rows = {}, []
    for path in paths:
        g = load_garment(path)
        for size in g.sizes:
            name = sample_for(g, size)
            if name not in bodies:
                bodies[name] = sample_body(name, None if samples_dir is None
                                           else Path(samples_dir))
            report, _ = dressing_check(bodies[name], g, size, preset=preset)
            row = {"garment": path.stem, "body": name, **report}
            rows.append(row)
            if log:
                log(row)
    return rows


def format_table(rows: list[dict]) -> str:
    lines = ["| garment | size | body | ok | seam gap mm | penetration mm max (p99) | "
             "max strain (τ) | s |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["max_strain"] is None:
            lines.append(f"| {r['garment']} | {r['size']} | {r['body']} | no | | | | "
                         f"{r['seconds']} |")
            continue
        lines.append(
            f"| {r['garment']} | {r['size']} | {r['body']} | {'yes' if r['ok'] else 'no'} | "
            f"{r['seam_gap_mm']:.1f} | {r['max_penetration_mm']:.2f} "
            f"({r['p99_penetration_mm']:.2f}) | {r['max_strain']:.4f} ({r['strain_limit']:g}) | "
            f"{r['seconds']} |")
    done = [r for r in rows if r["max_strain"] is not None]
    if done:
        lines.append("")
        lines.append(
            f"over {len(done)} dressings: max penetration "
            f"{max(r['max_penetration_mm'] for r in done):.2f} mm (p99 at most "
            f"{max(r['p99_penetration_mm'] for r in done):.2f} mm), max strain − τ "
            f"{max(r['max_strain'] - r['strain_limit'] for r in done):.4f}, widest seam gap "
            f"{max(r['seam_gap_mm'] for r in done):.1f} mm; "
            f"{sum(r['ok'] for r in rows)}/{len(rows)} ok")
    for r in rows:
        if not r["ok"]:
            lines.append(f"{r['garment']} {r['size']}: {r['message']}")
    return "\n".join(lines)
