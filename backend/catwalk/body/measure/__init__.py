"""Body measurements and landmarks from the surface alone (no rig), for any body or scan:
:func:`measure_body`.

Input: a triangle mesh in glTF metres (+Y up, the body faces +Z, body's left = +X), as
:func:`catwalk.exchange.scan.load_scan` returns it. Everything is derived from planar sections of
the surface: a section is split into connected loops (through the mesh's edge connectivity),
and a girth is the perimeter of the convex hull of the torso's loop (a tape measure bridges
hollows), as ISO 8559-1 defines girths. The definitions are in ``docs/bodies-measure.md``.

The hot path is one numba kernel that slices many levels at once
(:func:`~catwalk.body.measure.slicing.slice_kernel`). Extrema (bust, waist, neck, wrist) are
refined by golden-section search on exact sections, and levels read off a profile (buttocks,
bust point, breast fold, acromion) by a soft arg-min (:mod:`.profiles`), so that the numbers
move smoothly with the shape (the body fitter takes finite differences). Holes are closed by
fans before slicing (scans have them: :mod:`.topology`).

The modules: :mod:`.topology` (the mesh's connectivity), :mod:`.slicing` (sections and their
loops), :mod:`.profiles` (searches along a profile), :mod:`.measurement` (one measurement in
progress), and the stages :mod:`.torso` (structure, crotch, armpits), :mod:`.girths` (hips,
bust, underbust, bust points, waist, neck), :mod:`.shoulders` (acromions, side neck points,
shoulder width), :mod:`.limbs` (wrists, elbows, arm length, upper arm, knees, ankles).
"""

from __future__ import annotations

import numpy as np

from catwalk.body.measure.girths import girths, neck
from catwalk.body.measure.limbs import arms, legs
from catwalk.body.measure.measurement import Measurement
from catwalk.body.measure.shoulders import shoulder_width, shoulders
from catwalk.body.measure.slicing import CX, CZ
from catwalk.body.measure.topology import mesh_topology
from catwalk.body.measure.torso import armpits, crotch, structure
from catwalk.errors import InputError

__all__ = ["measure_body"]


def measure_body(vertices, faces, sex: str | None = None) -> dict:
    """Measurements (metres) and landmarks of a standing body in glTF axes.

    ``sex`` is ``"female"``, ``"male"`` or None; it only decides whether an underbust is
    reported (not for men). ``bust`` and ``chest`` are the same number. See
    ``docs/bodies-measure.md`` for the definitions.
    """
    V = np.asarray(vertices, dtype=np.float64)
    if V.ndim != 2 or V.shape[1] != 3 or len(V) < 4:
        raise InputError("measure: vertices must be an (N, 3) array")
    if not np.isfinite(V).all():
        raise InputError("measure: vertex coordinates contain NaN or infinity")
    if sex not in (None, "female", "male"):
        raise InputError(f"measure: sex must be 'female' or 'male', not {sex!r}")
    topo = mesh_topology(np.asarray(faces), len(V))
    V = topo.extend(V)
    meas = Measurement(V, topo)
    if not 0.5 <= meas.H <= 2.6:
        raise InputError(f"measure: the body is {meas.H:.3f} m tall; expected a standing adult "
                         "in metres (0.5–2.6 m)")
    structure(meas)
    crotch(meas)
    armpits(meas)
    g, lm = girths(meas, sex)
    neck_girth = neck(meas)
    shoulders(meas)
    sw = shoulder_width(meas)
    arms(meas)
    legs(meas)
    out = {
        "height": meas.H,
        "bust": g["bust"],
        "chest": g["chest"],
        "underbust": g.get("underbust"),
        "bust_span": g.get("bust_span"),
        "waist": g["waist"],
        "hips": g["hips"],
        "inseam": float(meas.crotch_y - meas.ymin),
        "shoulder_width": float(sw),
        "arm_length": 0.5 * (meas.arm_length[1] + meas.arm_length[-1]),
        "upper_arm_girth": 0.5 * (meas.upper_arm[1] + meas.upper_arm[-1]),
        "neck_girth": float(neck_girth),
    }
    if sex == "male":
        out.pop("underbust")
        out.pop("bust_span")
        for k in ("underbust", "bust_point_left", "bust_point_right"):
            lm.pop(k, None)
    out["landmarks"] = _landmarks(meas, lm)
    return out


def _landmarks(meas: Measurement, lm: dict) -> dict:
    """The landmarks by name (lists of x, y, z), the girths' ``lm`` among them."""
    V, used = meas.V, meas.topo.used
    return {
        "neck_base": _point(0.5 * (meas.side_neck[1] + meas.side_neck[-1])),
        **_sides("neck_side", meas.side_neck),
        **_sides("shoulder", meas.acromion),
        **_sides("armpit", meas.armpit_pt),
        **lm,
        "crotch": _point(meas.crotch_pt),
        **_sides("elbow", meas.elbow),
        **_sides("wrist", meas.wrist),
        **_sides("knee", meas.knee),
        **_sides("ankle", meas.ankle),
        "neck": [float(meas.neck_row[CX]), float(meas.neck_y), float(meas.neck_row[CZ])],
        "top_of_head": _point(V[used[np.argmax(V[used, 1])]]),
    }


def _point(a) -> list[float]:
    return [float(t) for t in a]


def _sides(name: str, points: dict) -> dict:
    """``name``_left and ``name``_right: the points of sides 1 (the body's left) and −1."""
    return {f"{name}_left": _point(points[1]), f"{name}_right": _point(points[-1])}
