"""Placing cut pieces around a body from its landmarks (paper §5: "automatically positioned").

:func:`place_panels` turns each panel's placement hint into a rigid transform of its pattern
plane (u, v, 0) → world and, for panels that wrap round their body part, a cylinder (axis point,
axis direction, radius) on which the flat placement is bent. Each result's ``to_world(uv)``
is what :class:`catwalk.cloth.builder.Panel` takes as ``placement``.

Conventions (world = glTF: +Y up, the body faces +Z, its left is +X; pattern coordinates are
seen from outside the garment, +v up):

- torso / legs, side ``front``: the panel faces +Z, +u → +X (the body's left); ``back``: faces
  −Z, +u → −X; ``left``: faces +X, +u → −Z; ``right``: faces −X, +u → +Z;
- arms: the axis runs through ``arm_root_<side>`` (the shoulder joint, when the body has a rig;
  else the anchor) towards the elbow (else the wrist) — the upper arm, where a sleeve's cap
  is — and, wrapped, bends at ``elbow_<side>`` towards ``wrist_<side>`` so a long sleeve
  follows the forearm; +v runs from the wrist to the shoulder along it, the panel faces outwards
  (±X; away from the armpit when the body has ``armpit_left``/``armpit_right``, so that a
  sleeve's underarm seam meets the bodice's side seam) and +u points to the front on the right
  arm, to the back on the left arm (a sleeve drafted with its front on +u is a right sleeve;
  its mirrored copy is the left one);
- the panel point at ``anchor_vertex`` (numbered as stored; mapped into mirrored copies and
  opened folds) / ``anchor_point`` (default: the top centre of its
  bounding box) goes to the ``anchor`` landmark (default by part: neck_base, waist,
  shoulder_left / shoulder_right), moved out to the part's surface + ``distance`` and by
  ``offset``; ``rotation`` turns the panel about its outward normal. A torso panel anchored
  at the neck hangs from its top: the anchor point only centres it across, and the panel's
  highest point (the high shoulder point of a bodice) goes to the height of ``neck_side_left``
  (front and back necklines differ by 5–10 cm, so anchoring both centre necks at one height
  would put their shoulder seams that far apart);
- one leg (``left_leg``/``right_leg``), wrapped: the tube follows the leg from
  ``leg_root_<side>`` (the hip joint, for a rigged body) through the knee to the ankle when
  those landmarks exist (a vertical cylinder through the knee otherwise);
- a panel with an explicit ``transform`` (placed on another body, e.g. GarmentCode's) that is
  a wrapped torso or legs panel keeps only where it sits across the body: the pattern point
  on the body's centre line (world x = 0 under its transform) on its top edge becomes its
  anchor point, and it is then placed on this body like any other; a wrapped limb panel
  (``left_arm`` … ``right_leg``: a sleeve's or a trouser leg's front or back half, a cuff)
  keeps only which of its pattern directions runs along the limb and which side is its
  outer seam, and is wrapped round this body's limb, front halves round the front, back
  halves round the back (:func:`_place_limbs`); other such panels are placed flat by the
  transform as given;
- ``wrap``: torso and legs panels bend round a vertical cylinder (for the torso centred, front
  to back, at the armpits' depth, so front and back panels meet under the arms) of the part's
  radius +
  ``distance``; sleeves round their arm's axis with the radius that closes them
  (width / 2π).

Landmarks are a dict name → [x, y, z] (metres), as :mod:`catwalk.body.measure` finds them
(``neck_base``, ``shoulder_left``, ``wrist_left``, ``waist``, ``knee_left``, …; the torso
landmarks are centres of sections, and only their height is used for torso panels;
``neck_front`` and ``neck_back`` are accepted as aliases of ``neck_base``). Radii come from
``girths`` (``bust``, ``waist``, ``hips`` in metres; the largest torso girth sets the torso
cylinder) or default to a medium body's.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from catwalk.errors import InputError
from catwalk.garment.model import Garment, Placement, cut_pieces, piece_vertex

DEFAULT_GIRTHS = {"bust": 0.98, "waist": 0.80, "hips": 1.06}
ARM_RADIUS = 0.05
LEG_RADIUS = 0.09
NECK_ANCHORS = ("neck_base", "neck_front", "neck_back", "neck")
DEFAULT_ANCHOR = {"torso": {"front": "neck_base", "back": "neck_base"},
                  "legs": "waist", "left_leg": "waist", "right_leg": "waist",
                  "left_arm": "shoulder_left", "right_arm": "shoulder_right"}


@dataclass
class PanelPlacement:
    name: str
    matrix: np.ndarray                  # (3, 4): world = M @ [u, v, 0, 1] (flat placement)
    cylinder: tuple | None              # (axis point (3,), axis direction (3,), radius) or None
    to_world: Callable[[np.ndarray], np.ndarray]


def _frame(part: str, side: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(e_u, e_v, outward normal) for a panel on ``part`` seen from ``side``."""
    y = np.array([0.0, 1.0, 0.0])
    normals = {"front": np.array([0.0, 0.0, 1.0]), "back": np.array([0.0, 0.0, -1.0]),
               "left": np.array([1.0, 0.0, 0.0]), "right": np.array([-1.0, 0.0, 0.0])}
    n = normals[side]
    e_u = np.cross(y, n)   # viewer's right when looking at the panel from outside
    return e_u, y, n


# names other bodies may use for the same place
ALIASES = {"neck_front": ("neck_base", "neck"), "neck_back": ("neck_base", "neck"),
           "neck_base": ("neck",), "chest": ("bust",), "bust": ("chest",),
           "head_top": ("top_of_head",)}


def _landmark(landmarks: dict, name: str, panel: str) -> np.ndarray:
    if name not in landmarks:
        for alt in ALIASES.get(name, ()):
            if alt in landmarks:
                name = alt
                break
    if name not in landmarks:
        raise InputError(f"panel {panel!r}: the body has no landmark {name!r} (it has: "
                         f"{', '.join(sorted(landmarks)) or 'none'})")
    p = np.asarray(landmarks[name], dtype=float)
    if p.shape != (3,):
        raise InputError(f"landmark {name!r} is not a 3D point")
    return p


def place_panels(garment: Garment, landmarks: dict, size: str | None = None,
                 girths: dict | None = None, tolerance: float = 2e-3) -> list[PanelPlacement]:
    """A placement per cut piece (same order as :func:`catwalk.garment.model.cut_pieces`)."""
    gi = dict(DEFAULT_GIRTHS, **(girths or {}))
    torso_r = max(gi["bust"], gi["waist"], gi["hips"]) / (2 * math.pi)
    hips_r = gi["hips"] / (2 * math.pi)
    size = garment.size(size)
    pieces, seams = cut_pieces(garment, size, tolerance)
    central = [np.asarray(landmarks[k], float) for k in
               ("neck_base", "neck", "bust", "underbust", "waist", "hips", "crotch")
               if k in landmarks]
    axis_xz = np.mean([p[[0, 2]] for p in central], axis=0) if central else np.zeros(2)
    out: list[PanelPlacement | None] = []
    for piece in pieces:
        pl = piece.panel.placement or Placement()
        if pl.transform is not None and pl.wrap and pl.part in LIMBS:
            out.append(None)   # re-placed on this body's limb below, after the panels
            continue           # they are sewn to
        pts = piece.flat.points
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        if pl.anchor_vertex is not None:
            a_uv = piece_vertex(garment, piece, pl.anchor_vertex, size)
        elif pl.anchor_point is not None:
            a_uv = np.asarray(pl.anchor_point, dtype=float)
        else:
            a_uv = np.array([0.5 * (lo[0] + hi[0]), hi[1]])
        offset = np.asarray(pl.offset, float)
        part = pl.part
        if pl.transform is not None:   # an explicit 3D placement (e.g. from GarmentCode)
            r = np.asarray(pl.transform["rotation"], float)
            t = np.asarray(pl.transform["translation"], float)
            centre_u = _centre_line_u(r, t, lo, hi)
            if not (pl.wrap and part in ("torso", "legs") and centre_u is not None):
                m = np.concatenate([r[:, :2], (t + offset)[:, None]], axis=1)
                out.append(PanelPlacement(piece.name, m, None, _flat(m, a_uv, 0.0)))
                continue
            # made on another body: keep where the panel sits across the body (its u on the
            # centre line), and hang it from this body's landmarks like any torso/legs panel
            a_uv = np.array([centre_u, hi[1]])
            # the other body's panels may run their u the other way round than ours (a back
            # panel seen from the front): keep their orientation, or seams would cross sides
            flip_u = bool(np.sign(r[0, 0]) != np.sign(_frame(part, pl.side)[0][0]))
        else:
            flip_u = False
        if pl.anchor:
            anchor_name = pl.anchor
        elif part == "torso":
            anchor_name = DEFAULT_ANCHOR["torso"]["back" if pl.side == "back" else "front"]
        else:
            anchor_name = DEFAULT_ANCHOR[part]
        anchor = _landmark(landmarks, anchor_name, piece.name)
        if part == "torso" and anchor_name in NECK_ANCHORS:
            # a bodice hangs from its neck points: the panel's top (the high shoulder point)
            # goes to the height where neck meets shoulder; the anchor keeps it centred
            a_uv = np.array([a_uv[0], hi[1]])
            side_pt = landmarks.get("neck_side_left", landmarks.get("neck_side_right"))
            if side_pt is not None:
                anchor = np.array([anchor[0], float(side_pt[1]), anchor[2]])
        if part in ("left_arm", "right_arm"):
            side = "left" if part == "left_arm" else "right"
            centre, d, n = _arm_frame(landmarks, side, anchor)
            e_v = d
            e_u = np.cross(e_v, n)
            radius = (hi[0] - lo[0]) / (2 * math.pi) if pl.wrap else ARM_RADIUS + pl.distance
        else:
            e_u, e_v, n = _frame(part, pl.side)
            if flip_u:
                e_u = -e_u
            d = np.array([0.0, 1.0, 0.0])
            cz = axis_xz[1]
            if part == "torso":
                r0, cx = torso_r, axis_xz[0]
                pits = [landmarks[k] for k in ("armpit_left", "armpit_right") if k in landmarks]
                if pits:   # side seams (where front and back meet) run up to the armpits
                    cz = float(np.mean([p[2] for p in pits]))
            elif part == "legs":
                r0, cx = hips_r, axis_xz[0]
            else:
                r0 = LEG_RADIUS
                knee = landmarks.get("knee_left" if part == "left_leg" else "knee_right")
                cx = (float(knee[0]) if knee is not None else
                      axis_xz[0] + (0.5 if part == "left_leg" else -0.5) * hips_r)
            centre = np.array([cx, 0.0, cz])
            radius = r0 + pl.distance
        foot = centre + np.dot(anchor - centre, d) * d        # the anchor's height on the axis
        surface = foot + radius * n + offset                  # where the anchor point goes
        m = np.stack([e_u, e_v, surface - a_uv[0] * e_u - a_uv[1] * e_v], axis=1)
        cyl = (centre + offset, d, float(radius)) if pl.wrap else None
        to_world = (_wrapped(a_uv, surface, e_u, e_v, n, cyl, pl.rotation) if cyl
                    else _flat(m, a_uv, pl.rotation))
        if cyl and part in ("left_arm", "right_arm"):
            elbow = landmarks.get(f"elbow_{side}")
            wrist = landmarks.get(f"wrist_{side}")
            if elbow is not None and wrist is not None:   # follow the bent arm
                axis = np.array([foot, elbow, wrist], float) + offset
                to_world = _wrapped_bent(a_uv, axis, n, float(radius), pl.rotation,
                                         reach=float(a_uv[1] - lo[1]))
        elif cyl and part in ("left_leg", "right_leg"):
            side = "left" if part == "left_leg" else "right"
            root, knee = landmarks.get(f"leg_root_{side}"), landmarks.get(f"knee_{side}")
            ankle = landmarks.get(f"ankle_{side}")
            if root is not None and knee is not None and ankle is not None:   # follow the leg
                root, knee, ankle = (np.asarray(p, float) for p in (root, knee, ankle))
                up = (root - knee) / np.linalg.norm(root - knee)
                top = root + up * (anchor[1] - root[1]) / max(up[1], 0.2)
                axis = np.array([top, knee, ankle]) + offset
                to_world = _wrapped_bent(a_uv, axis, n, float(radius), pl.rotation)
        out.append(PanelPlacement(piece.name, m, cyl, to_world))
    _place_limbs(pieces, seams, out, landmarks)
    return out


def _arm_frame(landmarks: dict, side: str, anchor: np.ndarray):
    """(axis point, unit direction up the upper arm, outward normal) of one arm: the axis
    through ``arm_root_<side>`` (else the anchor) from the elbow (else the wrist), the normal
    away from the armpit (else out to the side)."""
    sign = 1.0 if side == "left" else -1.0
    root = landmarks.get(f"arm_root_{side}")
    centre = anchor if root is None else np.asarray(root, float)
    below = landmarks.get(f"elbow_{side}", landmarks.get(f"wrist_{side}"))
    d = (centre - np.asarray(below, float)) if below is not None \
        else np.array([-0.3 * sign, 1.0, 0.0])   # arms hanging a little apart
    d = d / np.linalg.norm(d)
    n = np.array([sign, 0.0, 0.0]) - sign * d[0] * d
    armpit = landmarks.get(f"armpit_{side}")
    if armpit is not None:   # the sleeve's underarm faces the armpit, where the
        away = anchor - np.asarray(armpit, float)   # bodice's side seam ends
        away -= np.dot(away, d) * d
        if np.linalg.norm(away) > 1e-6:
            n = away
    return centre, d, n / np.linalg.norm(n)


def _centre_line_u(r: np.ndarray, t: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """The pattern u at which an explicitly placed panel crosses the body's centre line
    (world x = 0), for a panel whose u runs along ±world x; None otherwise."""
    ux = r[0, 0]
    if abs(ux) < 0.9 or abs(r[0, 1]) > 0.1:
        return None
    u = -t[0] / ux
    return float(np.clip(u, lo[0], hi[0]))


def _rotate(uv: np.ndarray, a_uv: np.ndarray, degrees: float) -> np.ndarray:
    if not degrees:
        return uv
    a = math.radians(degrees)
    r = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    return (uv - a_uv) @ r.T + a_uv


def _flat(m: np.ndarray, a_uv: np.ndarray, degrees: float):
    def to_world(uv: np.ndarray) -> np.ndarray:
        uv = _rotate(np.asarray(uv, float), a_uv, degrees)
        return uv @ m[:, :2].T + m[:, 2]
    return to_world


def _wrapped_bent(a_uv, axis: np.ndarray, n: np.ndarray, radius: float, degrees: float,
                  reach: float | None = None):
    """Wrap round a tube whose axis is a polyline (shoulder → elbow → wrist, extended at both
    ends): the anchor row sits at ``axis[0]``, +v runs back up the axis, arc length along u
    is kept, and each segment carries the outward direction ``n`` made perpendicular to it.
    ``reach``: the panel's length below the anchor; a panel longer than the axis (a sleeve
    longer than this arm) is gathered along it to end 3 cm short of the axis's end, instead of
    starting round the hand or foot (the cloth starts compressed, which it takes without force
    to speak of, and falls back to its length as it settles)."""
    seg = np.diff(axis, axis=0)
    length = np.linalg.norm(seg, axis=1)
    total = float(length.sum())
    gather = 1.0
    if reach is not None and reach > total - 0.03 and total > 0.06:
        gather = (total - 0.03) / reach
    t = seg / length[:, None]
    starts = np.concatenate([[0.0], np.cumsum(length)[:-1]])
    nk = n[None] - np.sum(n[None] * t, axis=1)[:, None] * t
    nk /= np.linalg.norm(nk, axis=1)[:, None]
    uk = np.cross(-t, nk)

    def to_world(uv: np.ndarray) -> np.ndarray:
        uv = _rotate(np.asarray(uv, float), a_uv, degrees)
        s = (a_uv[1] - uv[:, 1]) * gather          # distance down the arm from the anchor row
        k = np.clip(np.searchsorted(starts, s, side="right") - 1, 0, len(t) - 1)
        on = axis[k] + (s - starts[k])[:, None] * t[k]
        phi = (uv[:, 0] - a_uv[0]) / radius
        return on + radius * (np.sin(phi)[:, None] * uk[k] + np.cos(phi)[:, None] * nk[k])
    return to_world


def _wrapped(a_uv, surface, e_u, e_v, n, cyl, degrees: float):
    """Bend the flat placement round the cylinder: arc length along e_u is kept."""
    centre, d, radius = cyl

    def to_world(uv: np.ndarray) -> np.ndarray:
        uv = _rotate(np.asarray(uv, float), a_uv, degrees)
        du, dv = uv[:, 0] - a_uv[0], uv[:, 1] - a_uv[1]
        flat = surface[None] + dv[:, None] * e_v[None]
        along = (flat - centre[None]) @ d
        phi = du / radius
        return (centre[None] + along[:, None] * d[None]
                + radius * (np.sin(phi)[:, None] * e_u[None] + np.cos(phi)[:, None] * n[None]))
    return to_world


# ------------------------------------------------- limb panels placed on another body

LIMBS = ("left_arm", "right_arm", "left_leg", "right_leg")
_SNAP_COS = math.cos(math.radians(20.0))


def _run(n: int, start: int, end: int) -> np.ndarray:
    """Flattened point indices of a seam run from ``start`` forward to ``end``."""
    if end >= start:
        return np.arange(start, end + 1)
    return np.concatenate([np.arange(start, n), np.arange(0, end + 1)])


def _sewn_runs(pieces, seams, i: int) -> list[tuple[np.ndarray, int, np.ndarray]]:
    """Piece ``i``'s seams to other pieces: (its point indices, the other piece, theirs)."""
    out = []
    for pa, sa, ea, pb, sb, eb, _ in seams:
        for (p, s, e), (q, t, f) in (((pa, sa, ea), (pb, sb, eb)), ((pb, sb, eb), (pa, sa, ea))):
            if p == i and q != i:
                out.append((_run(len(pieces[p].flat.points), s, e), q,
                            _run(len(pieces[q].flat.points), t, f)))
    return out


def _limb_axes(rotation, part: str, chords: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Pattern directions of a limb panel placed by ``rotation`` on another body: ``a`` up
    the limb (towards the shoulder or hip), ``b`` round it towards the limb's outer seam (the
    top of the arm, the outside of the leg). ``a`` follows the seams to the limb's other
    panels (``chords``: their runs' end − start), which run along the limb; without any, the
    pattern direction whose 3D image is nearest up the limb on the other body (arms taken 45°
    out from vertical), snapped to the panel's u or v axis within 20°."""
    sign = 1.0 if part.startswith("left") else -1.0
    h = math.sqrt(0.5)
    if part.endswith("arm"):
        up, out = np.array([-sign * h, h, 0.0]), np.array([sign * h, h, 0.0])
    else:
        up, out = np.array([0.0, 1.0, 0.0]), np.array([sign, 0.0, 0.0])
    r2 = np.asarray(rotation, float)[:, :2]
    a = r2.T @ up
    a = a / np.linalg.norm(a) if np.linalg.norm(a) > 1e-9 else np.array([0.0, 1.0])
    along = np.sum([c if np.dot(c, a) >= 0 else -c for c in chords], axis=0) if chords \
        else np.zeros(2)
    if np.linalg.norm(along) > 1e-9:
        a = along / np.linalg.norm(along)
    elif np.abs(a).max() > _SNAP_COS:
        k = int(np.argmax(np.abs(a)))
        a = np.eye(2)[k] * np.sign(a[k])
    b = np.array([-a[1], a[0]])
    return a, (b if np.dot(r2 @ b, out) >= 0 else -b)


def _leg_axis(landmarks: dict, side: str, height: float) -> np.ndarray:
    """A leg's axis from ``height`` (on the thigh's line) through the knee to the ankle; a
    vertical line through the knee (else beside the centre) without those landmarks."""
    knee, ankle = landmarks.get(f"knee_{side}"), landmarks.get(f"ankle_{side}")
    if knee is None or ankle is None:
        x = float(knee[0]) if knee is not None else (LEG_RADIUS if side == "left" else -LEG_RADIUS)
        z = float(knee[2]) if knee is not None else 0.0
        return np.array([[x, height, z], [x, height - 1.0, z]])
    knee, ankle = np.asarray(knee, float), np.asarray(ankle, float)
    root = landmarks.get(f"leg_root_{side}")
    root = np.asarray(root, float) if root is not None else knee + np.array([0.0, 0.4, 0.0])
    up = (root - knee) / np.linalg.norm(root - knee)
    top = root + up * (height - root[1]) / max(up[1], 0.2)
    return np.array([top, knee, ankle])


def _along(axis: np.ndarray, p: np.ndarray) -> float:
    """Distance down the polyline ``axis`` (extended at both ends) to the point nearest
    ``p``."""
    seg = np.diff(axis, axis=0)
    length = np.linalg.norm(seg, axis=1)
    starts = np.concatenate([[0.0], np.cumsum(length)[:-1]])
    best, at = np.inf, 0.0
    for k in range(len(seg)):
        t = float(np.clip(np.dot(p - axis[k], seg[k]) / length[k] ** 2,
                          -np.inf if k == 0 else 0.0, np.inf if k == len(seg) - 1 else 1.0))
        dist = float(np.linalg.norm(axis[k] + t * seg[k] - p))
        if dist < best:
            best, at = dist, float(starts[k] + t * length[k])
    return at


def _trim(axis: np.ndarray, down: float) -> np.ndarray:
    """The polyline ``axis`` from ``down`` along it on (before its start when negative)."""
    seg = np.diff(axis, axis=0)
    ends = np.cumsum(np.linalg.norm(seg, axis=1))
    k = min(int(np.searchsorted(ends, down, side="right")), len(seg) - 1)
    start = ends[k] - np.linalg.norm(seg[k])
    unit = seg[k] / np.linalg.norm(seg[k])
    head = axis[k] + (down - start) * unit
    if down > ends[-1] - 0.02:   # at (or past) its end: the last segment's line on
        return np.array([head, head + 0.1 * unit])
    return np.concatenate([head[None], axis[k + 1:]])


def _limb_frame(pieces, seams, out: list, i: int) -> dict:
    """What :func:`_limb_placement` needs of limb panel ``i``: its directions along and round
    the limb, the round coordinate of its outer seam, its width between its seams to the
    other panels of its tube (same limb, same panel type: a sleeve's halves, a trouser leg's,
    a cuff's) and its seams to other panels (``root``)."""
    pl, pts, ptype = pieces[i].panel.placement, pieces[i].flat.points, pieces[i].panel.type
    runs = _sewn_runs(pieces, seams, i)
    in_tube = [out[q] is None and pieces[q].panel.type == ptype
               and pieces[q].panel.placement.part == pl.part for _, q, _ in runs]
    tube = [own for (own, _, _), t in zip(runs, in_tube, strict=True) if t]
    a, b = _limb_axes(pl.transform["rotation"], pl.part,
                      [pts[own[-1]] - pts[own[0]] for own in tube])
    w = pts @ b
    wt = w[np.concatenate(tube)] if tube else w
    root = [r for r, t in zip(runs, in_tube, strict=True) if not t]
    return {"a": a, "b": b, "top": float(wt.max()), "width": float(wt.max() - wt.min()),
            "root": root, "tube": (pl.part, ptype)}


def _place_limbs(pieces, seams, out: list, landmarks: dict) -> None:
    """Place the limb panels made on another body (``out[i]`` None: GarmentCode's sleeve and
    trouser halves, their cuffs) round this body's limbs, those sewn to panels already placed
    first (a cuff after its sleeve). Each panel's pattern is read in its own directions along
    and round the limb (:func:`_limb_axes`) and wrapped round the limb's axis
    (:func:`_wrapped_bent`): its outer seam on the limb's outer line (the top of the arm, away
    from the armpit; the outside of the leg), a front panel round the front and a back panel
    round the back, at the radius at which its tube's panels together close (the sum of their
    widths between their seams / 2π; at least the limb's radius + 1 cm). A sleeve sewn to the
    bodice has its top at the shoulder joint; any other limb panel has its seams to placed
    panels (a jumpsuit's bodice, a waistband, a cuff's sleeve) where those are along the
    limb's axis, else its top at the waist. Lengths round the limb are kept; a panel longer
    than the limb is gathered along it (see :func:`_wrapped_bent`)."""
    todo = [i for i, pl in enumerate(out) if pl is None]
    frames = {i: _limb_frame(pieces, seams, out, i) for i in todo}
    widths: dict[tuple, float] = {}
    for i in todo:
        widths[frames[i]["tube"]] = widths.get(frames[i]["tube"], 0.0) + frames[i]["width"]
    while todo:
        ready = [i for i in todo if any(out[q] is not None for _, q, _ in frames[i]["root"])]
        # (each pass sees the panels placed before it: placing a panel does not move another
        # of the same pass, such as the other leg sewn to it at the crotch)
        roots = {i: [(pieces[i].flat.points[own], out[q].to_world(pieces[q].flat.points[theirs]),
                      pieces[q].panel.placement.part in LIMBS)
                     for own, q, theirs in frames[i]["root"] if out[q] is not None]
                 for i in ready or todo}
        for i, root in roots.items():
            part = frames[i]["tube"][0]
            least = (ARM_RADIUS if part.endswith("arm") else LEG_RADIUS) + 0.01
            radius = max(widths[frames[i]["tube"]] / (2 * math.pi), least)
            out[i] = _limb_placement(pieces[i], frames[i], radius, root, landmarks)
        todo = [i for i in todo if out[i] is None]


def _limb_placement(piece, frame: dict, radius: float, root: list,
                    landmarks: dict) -> PanelPlacement:
    """One limb panel of :func:`_place_limbs` (``root``: its seams to placed panels as (its
    pattern points, their world points, whether that panel is on a limb))."""
    pl = piece.panel.placement
    a, b = frame["a"], frame["b"]
    side = "left" if pl.part.startswith("left") else "right"
    s = piece.flat.points @ a
    s_anchor, down = float(s.max()), 0.0
    if pl.part.endswith("arm"):
        anchor = _landmark(landmarks, pl.anchor or DEFAULT_ANCHOR[pl.part], piece.name)
        centre, d, n = _arm_frame(landmarks, side, anchor)
        foot = centre + np.dot(anchor - centre, d) * d
        elbow, wrist = landmarks.get(f"elbow_{side}"), landmarks.get(f"wrist_{side}")
        axis = (np.array([foot, elbow, wrist], float) if elbow is not None
                and wrist is not None else np.array([foot, foot - 0.6 * d]))
        sleeve = root and not all(on_limb for _, _, on_limb in root)
    else:
        n = np.array([1.0 if side == "left" else -1.0, 0.0, 0.0])
        top = float(_landmark(landmarks, pl.anchor or "waist", piece.name)[1])
        if root:
            top = max(top, max(float(w[:, 1].max()) for _, w, _ in root)) + 0.05
        axis = _leg_axis(landmarks, side, top)
        sleeve = False
    if root and not sleeve:   # its seams to placed panels go where those are along the axis
        s_anchor = float(np.mean(np.concatenate([own for own, _, _ in root]) @ a))
        down = _along(axis, np.mean(np.concatenate([w for _, w, _ in root]), axis=0))
    axis = _trim(axis, down) + np.asarray(pl.offset, float)
    # front panels round the front: +u of the bent tube points back on the left limbs
    sigma = (1.0 if side == "left" else -1.0) * (-1.0 if pl.side == "back" else 1.0)
    canon = np.array([sigma * b, a])
    ref = frame["top"] * b + s_anchor * a
    bent = _wrapped_bent(np.zeros(2), axis, n, radius, pl.rotation,
                         reach=s_anchor - float(s.min()))

    def to_world(uv: np.ndarray) -> np.ndarray:
        return bent((np.asarray(uv, float).reshape(-1, 2) - ref) @ canon.T)

    # the flat placement: the tangent plane at the anchor
    o = to_world(ref[None])[0]
    jac = np.stack([(to_world((ref + 1e-4 * e)[None])[0] - o) / 1e-4 for e in np.eye(2)], 1)
    m = np.concatenate([jac, (o - jac @ ref)[:, None]], axis=1)
    t0 = axis[1] - axis[0]
    return PanelPlacement(piece.name, m, (axis[0], -t0 / np.linalg.norm(t0), float(radius)),
                          to_world)
