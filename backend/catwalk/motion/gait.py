"""A procedural walk driven by published normal-gait joint-angle curves.

Curves (degrees over the gait cycle, 0 % = heel strike of the same leg, toe-off at 62 %) are
periodic cubic splines through the tabulated points below, which follow the mean free-speed
adult curves of Perry & Burnfield (2010) and Winter (1991) (see docs/motion.md for the sources
and what was read from them). The generator:

1. scales stride and cadence to the body (hip height h) and the requested speed with
   Alexander's relation λ/h = 2.3 (v²/gh)^0.3, rounded so the clip holds a whole number of
   cycles (a seamless loop);
2. moves the pelvis forward at constant speed, with a lateral sway towards the stance leg and
   pelvis rotation / obliquity / tilt; its height over the cycle is where the planted stance
   legs bend their knees as the knee curve says (blended across double support, never beyond
   reach), so the vertical bob comes out of the leg geometry;
3. plants the stance foot on its footprint and rolls it over the heel, flat, then over the ball
   (heel, ankle and forefoot rockers) — the pivot never moves, so the foot does not slide;
4. moves the swing foot along the ankle path of the hip/knee curves (forward kinematics from the
   moving hip), blended smoothly from the toe-off footprint to the next heel-strike footprint,
   with the foot pitch of the ankle curve and lateral clearance around the stance leg;
5. solves each leg with two-bone IK (knee towards the toes), counter-rotates the thorax, keeps
   the head level, brings the arms down from MakeHuman's A-pose to the sides and swings them
   in antiphase with the legs, elbows flexing as the arm swings forward.

Axes: glTF, metres; the body faces and walks along +Z; left = +X.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.interpolate import CubicSpline

from catwalk.body.types import Body, Motion
from catwalk.errors import InputError
from catwalk.geometry.quat import axis_angle, make_continuous, mat_to_quat, rot_x, rot_y, rot_z
from catwalk.motion.ik import bone_delta, two_bone_ik

G = 9.81

# --- normative sagittal curves: (percent of gait cycle, degrees) ------------------------------
# Hip flexion (+) / extension (−) of the thigh relative to the pelvis.  Perry & Burnfield 2010
# ch. 9 and Winter 1991 fig. 3.8 (natural cadence): ~30° flexed at initial contact, peak
# extension ~10° at 50 %, peak flexion ~35° at 85 %.
HIP_TABLE = np.array([
    [0, 30], [5, 29], [10, 27], [15, 23], [20, 18], [25, 13], [30, 8], [35, 3], [40, -2],
    [45, -6], [50, -10], [55, -9], [60, -4], [65, 4], [70, 13], [75, 21], [80, 28], [85, 33],
    [90, 34], [95, 32], [100, 30]], dtype=np.float64)
# Knee flexion (+).  Perry & Burnfield 2010 ch. 8; Winter 1991: ~5° at contact, 15–20° at
# loading response (15 %), ~5° at 40 %, ~40° at toe-off, 60–65° peak at ~72 %, ~2° at 97 %.
KNEE_TABLE = np.array([
    [0, 5], [5, 12], [10, 17], [15, 19], [20, 17], [25, 13], [30, 9], [35, 6], [40, 5],
    [45, 7], [50, 12], [55, 22], [60, 36], [65, 51], [70, 61], [73, 63], [76, 62], [80, 55],
    [85, 40], [90, 22], [95, 8], [100, 5]], dtype=np.float64)
# Ankle dorsiflexion (+) / plantarflexion (−).  Perry & Burnfield 2010 ch. 7; Winter 1991:
# 0° at contact, −5° at 7 %, +10° at ~45 %, −15…−20° just after toe-off (62 %), ~0° in swing.
ANKLE_TABLE = np.array([
    [0, 0], [4, -4], [7, -5], [10, -3], [15, 1], [20, 4], [25, 6], [30, 8], [35, 9], [40, 10],
    [45, 10], [50, 6], [55, -3], [60, -14], [63, -18], [66, -16], [70, -10], [75, -5],
    [80, -2], [85, 0], [90, 1], [95, 1], [100, 0]], dtype=np.float64)
# Pelvic obliquity (+ = this side's hip up): the swing side drops ~4–5° in loading response
# (peak ~17 %), mirrored in the other leg's stance.  Perry & Burnfield 2010 ch. 10.
OBLIQUITY_TABLE = np.array([
    [0, 0], [8, 3], [17, 5], [25, 4], [35, 1.5], [50, 0], [58, -3], [67, -5], [75, -4],
    [85, -1.5], [100, 0]], dtype=np.float64)
# Mean anterior pelvic tilt in lab data: hip angles are measured against the tilted pelvis, so
# the thigh's angle to the vertical is hip − tilt (Perry & Burnfield 2010: ~10° anterior).
PELVIC_TILT_MEAN_DEG = 10.0

STANCE_END = 0.62     # toe-off (Perry & Burnfield: pre-swing ends at 62 %)
FOOT_FLAT = 0.08      # end of the heel rocker
HEEL_OFF = 0.35       # heel rise, start of the forefoot rocker (terminal stance from 31 %)
# Skinning pulls the sole between the tipped foot and the flat toes a few mm under the floor at
# push-off; the foot is lifted by what exceeds this, so the toe pads stay (nearly) planted.
FOREFOOT_DIP_ALLOWED = 0.005


def _periodic(table: np.ndarray) -> CubicSpline:
    x = table[:, 0] / 100.0
    y = table[:, 1].copy()
    y[-1] = y[0]
    return CubicSpline(x, y, bc_type="periodic")


HIP = _periodic(HIP_TABLE)
KNEE = _periodic(KNEE_TABLE)
ANKLE = _periodic(ANKLE_TABLE)
OBLIQUITY = _periodic(OBLIQUITY_TABLE)


@dataclass(frozen=True)
class GaitStyle:
    name: str
    foot_x: float | None          # footprint ankle |x| from the midline (None: under the hip)
    crossing: float = 0.0         # footprints cross the midline by this much (m)
    pelvis_rotation_deg: float = 4.0
    obliquity_scale: float = 1.0  # × OBLIQUITY_TABLE (peak 5°)
    tilt_amplitude_deg: float = 1.5
    thorax_counter: float = 0.8   # thorax yaw = −counter × pelvis yaw (world)
    sway_m: float = 0.025         # pelvis lateral sway amplitude
    arm_swing_deg: float = 16.0
    elbow_mean_deg: float = 20.0
    elbow_amp_deg: float = 8.0
    toe_out_deg: float = 4.0
    knee_min_deg: float = 3.0     # stance knee never straighter than this
    stance_knee_scale: float = 1.0  # × the knee curve in stance (catwalk: straighter knees)
    swing_clearance_m: float = 0.012   # lateral bulge of the swing ankle path
    stride_scale: float = 1.0


STYLES = {
    "normal": GaitStyle("normal", foot_x=None),
    # Runway walk: feet land on (slightly across) the midline, larger pelvic rotation and
    # obliquity, shoulders steadier, a smaller arm swing, knees nearly straight in stance.
    "catwalk": GaitStyle("catwalk", foot_x=0.0, crossing=0.012, pelvis_rotation_deg=7.0,
                         obliquity_scale=1.5, tilt_amplitude_deg=1.5, thorax_counter=0.5,
                         sway_m=0.018, arm_swing_deg=11.0, elbow_mean_deg=14.0,
                         elbow_amp_deg=5.0, toe_out_deg=6.0, stance_knee_scale=0.6,
                         swing_clearance_m=0.095, stride_scale=0.95),
}

# relaxed-hand finger flexion per segment (degrees), as a hand hangs while walking
FINGER_CURL_DEG = {"index": (9, 13, 8), "middle": (11, 15, 8), "ring": (13, 17, 8),
                   "pinky": (15, 17, 8), "thumb": (0, 6, 6)}

REQUIRED_BONES = ("Root", "pelvis", "spine_01", "spine_02", "spine_03", "neck_01", "head",
                  "clavicle_l", "clavicle_r", "upperarm_l", "upperarm_r", "lowerarm_l",
                  "lowerarm_r", "hand_l", "hand_r", "thigh_l", "thigh_r", "calf_l", "calf_r",
                  "foot_l", "foot_r", "ball_l", "ball_r")


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    c = float(np.dot(a, b) / (np.linalg.norm(a) * np.linalg.norm(b)))
    return float(np.arccos(np.clip(c, -1.0, 1.0)))


def _smooth(s):
    """Quintic smootherstep on [0, 1] (zero first and second derivatives at both ends)."""
    s = np.clip(s, 0.0, 1.0)
    return s * s * s * (s * (s * 6 - 15) + 10)


def stride_length(hip_height: float, speed: float) -> float:
    """Alexander (1984): stride λ = 2.3 h (v² / g h)^0.3 for adults walking."""
    return 2.3 * hip_height * (speed * speed / (G * hip_height)) ** 0.3


@dataclass
class _Leg:
    side: float          # +1 left, −1 right
    phase0: float        # gait phase at t = 0
    hip: int
    knee: int
    ankle: int
    ball: int
    hip0: np.ndarray
    knee0: np.ndarray
    ankle0: np.ndarray
    ball0: np.ndarray
    toe0: np.ndarray
    heel0: np.ndarray
    l1: float
    l2: float
    rest_bend: float = 0.0   # angle between thigh and shank at rest (joint centres), rad
    # set once the walk's timing is known (_Gait): the hip relative to the pelvis at rest, the
    # forefoot's (pitches, lift) table and the footprints' z offset
    pelvis_to_hip: np.ndarray | None = None
    lift: tuple | None = None
    fp_z0: float = 0.0


def _foot_heel(body: Body, leg_ankle: int, ankle0: np.ndarray,
               pitch_hs: float) -> np.ndarray:
    """The heel rocker's pivot on the floor: the point about which the rest foot, tipped toes-up
    by the heel-strike pitch, just touches the floor with its heel (the heel is rounded, so
    this lies a little ahead of the heel's rearmost vertex)."""
    v = np.asarray(body.vertices)
    ground = float(v[:, 1].min())
    w = (body.skin_weights * (body.skin_joints == leg_ankle)).sum(axis=1)
    heel = v[(w > 0.5) & (v[:, 2] < ankle0[2]) & (v[:, 1] < ankle0[1])]
    if len(heel) < 3:
        return np.array([ankle0[0], ground, ankle0[2] - 0.04])
    rear = float(heel[:, 2].min())
    c, s = np.cos(pitch_hs), np.sin(pitch_hs)

    def lowest(zp):   # lowest heel point after tipping toes-up by pitch_hs about (zp, ground)
        dz, dy = heel[:, 2] - zp, heel[:, 1] - ground
        return float(np.min(dy * c + dz * s))

    lo, hi = rear, float(ankle0[2])
    if lowest(lo) <= 0.0:
        return np.array([ankle0[0], ground, rear])
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if lowest(mid) > 0.0:
            lo = mid
        else:
            hi = mid
    return np.array([ankle0[0], ground, lo])


def _forefoot_lift(body: Body, lg: _Leg, p_to: float):
    """(pitches, lift): how far to raise a foot rolled over its ball by a (negative) pitch so
    that no skinned sole vertex dips under the floor. Linear blend skinning pulls the vertices
    between the tipped foot and the flat toes down a few millimetres; the lift keeps them within
    ``FOREFOOT_DIP_ALLOWED`` of the floor without moving anything horizontally."""
    pitches = np.linspace(min(p_to, -1e-3) * 1.05, 0.0, 64)
    v = np.asarray(body.vertices)
    ground = float(v[:, 1].min())
    w_foot = (body.skin_weights * (body.skin_joints == lg.ankle)).sum(axis=1)
    w_ball = (body.skin_weights * (body.skin_joints == lg.ball)).sum(axis=1)
    sel = ((w_foot + w_ball) > 0.5) & (v[:, 1] < ground + 0.03)
    if not sel.any():
        return pitches, np.zeros_like(pitches)
    q, wf = v[sel], w_foot[sel] / (w_foot[sel] + w_ball[sel])
    rel = q - lg.ball0
    lift = np.empty_like(pitches)
    for i, p in enumerate(pitches):
        c, s_ = np.cos(-p), np.sin(-p)
        y_foot = lg.ball0[1] + rel[:, 1] * c - rel[:, 2] * s_
        y = wf * y_foot + (1 - wf) * q[:, 1]
        lift[i] = max(0.0, ground - float(y.min()) - FOREFOOT_DIP_ALLOWED)
    return pitches, lift


def _toe_tip(body: Body, ball: int, ball0: np.ndarray) -> np.ndarray:
    """The front of the toes on the ground (the toe bone's farthest-forward vertex)."""
    v = np.asarray(body.vertices)
    w = (body.skin_weights * (body.skin_joints == ball)).sum(axis=1)
    sel = w > 0.5
    if sel.sum() < 3:
        return np.array([ball0[0], float(v[:, 1].min()), ball0[2] + 0.06])
    return np.array([ball0[0], float(v[:, 1].min()), float(v[sel, 2].max())])


def _arm_clearance_abduction(body: Body, sk, side: str, shoulder, elbow_len, fore_len) -> float:
    """Smallest arm abduction (rad) that keeps the hanging arm off the torso and hips."""
    v = np.asarray(body.vertices)
    parts = body.parts if body.parts is not None else np.zeros(len(v), np.int8)
    trunk = v[(parts == 0) | (parts == 3) | (parts == 4)]
    sgn = 1.0 if side == "l" else -1.0
    trunk = trunk[trunk[:, 0] * sgn > 0]
    ju = sk.index(f"upperarm_{side}")
    jf = sk.index(f"lowerarm_{side}")
    arm = v[parts == (1 if side == "l" else 2)]
    rw = sk.rest_world
    axis_u = rw[jf, :3, 3] - rw[ju, :3, 3]
    axis_u /= np.linalg.norm(axis_u)
    rel = arm - rw[ju, :3, 3]
    along = rel @ axis_u
    near = (along > 0.05) & (along < elbow_len - 0.03)
    radius = 0.04
    if near.sum() > 10:
        perp = rel[near] - along[near, None] * axis_u
        radius = float(np.percentile(np.linalg.norm(perp, axis=1), 80))
    radius = float(np.clip(radius, 0.03, 0.08))
    total = elbow_len + fore_len
    crotch = float(np.mean(sk.rest_world[[sk.index("thigh_l"), sk.index("thigh_r")], 1, 3]))
    # the legs move under the pelvis when walking: only their part above the crotch counts
    trunk = trunk[trunk[:, 1] > crotch - 0.04]
    # from below the armpit (mid upper arm) down to the wrist
    for deg in np.arange(4.0, 40.0, 1.0):
        a = np.radians(deg)
        ok = True
        for s in np.linspace(0.6 * elbow_len / total, 1.0, 12):
            d = s * total
            px = abs(shoulder[0]) + d * np.sin(a)
            py = shoulder[1] - d * np.cos(a)
            pz = shoulder[2] + max(0.0, d - elbow_len) * np.sin(np.radians(15.0))
            # the trunk beside the arm (not the buttocks or belly far behind / in front of it)
            band = trunk[(np.abs(trunk[:, 1] - py) < 0.02) & (np.abs(trunk[:, 2] - pz) < 0.07)]
            if len(band) == 0:
                continue
            r = radius * (1.0 - 0.3 * s)
            if px - r < np.abs(band[:, 0]).max() + 0.004:
                ok = False
                break
        if ok:
            return float(np.radians(deg + 1.0))
    return float(np.radians(40.0))


def _checked_style(body: Body, seconds: float, speed: float, style: str, fps: float,
                   arm_swing_deg: float | None) -> GaitStyle:
    """The walk's style, once every input is checked (:class:`InputError` naming it)."""
    if body.skeleton is None or body.skin_joints is None or body.skin_weights is None:
        raise InputError("this body has no rig (skeleton and skin weights); make it with "
                         "`catwalk body make` or another rigged source")
    if not np.isfinite(seconds) or seconds <= 0:
        raise InputError(f"seconds must be > 0, got {seconds}", "seconds")
    if not np.isfinite(speed) or not 0.3 <= speed <= 3.0:
        raise InputError(f"speed must be within 0.3–3 m/s, got {speed}", "speed")
    if not np.isfinite(fps) or not 1 <= fps <= 240:
        raise InputError(f"fps must be within 1–240, got {fps}", "fps")
    if style not in STYLES:
        raise InputError(f"unknown style {style!r}; choose one of {', '.join(STYLES)}")
    if arm_swing_deg is not None and not (np.isfinite(arm_swing_deg) and
                                          0.0 <= arm_swing_deg <= 90.0):
        raise InputError(f"arm swing must be within 0–90°, got {arm_swing_deg}",
                         "arm_swing_deg")
    missing = [b for b in REQUIRED_BONES if b not in body.skeleton.names]
    if missing:
        raise InputError(f"the body's rig lacks the bones {', '.join(missing)} needed to walk")
    st = STYLES[style]
    if arm_swing_deg is not None:
        st = replace(st, arm_swing_deg=float(arm_swing_deg))
    return st


def _reach_height(lg: _Leg, ank, hp, knee_deg):
    """Pelvis height at which the leg spans hip → ankle with the knee flexed knee_deg beyond
    its rest pose (the rest knee's joint centres are already bent a few degrees)."""
    bend = np.radians(knee_deg) + lg.rest_bend
    d = np.sqrt(lg.l1 ** 2 + lg.l2 ** 2 + 2 * lg.l1 * lg.l2 * np.cos(bend))
    horiz2 = (hp[:, 0] - ank[:, 0]) ** 2 + (hp[:, 2] - ank[:, 2]) ** 2
    return ank[:, 1] + np.sqrt(np.maximum(d ** 2 - horiz2, 0.0)) - hp[:, 1]


class _Gait:
    """One body's walk in time: its legs' geometry, the clip's timing (whole cycles), the hip
    curve's scale that makes the legs' step the stride, the pelvis over the cycle (its height
    from the planted stance legs) and the footprints — what every frame's pose is made from.
    Each leg's per-walk facts (its heel pivot, forefoot lift table, pelvis-to-hip offset and
    footprint offset) are kept on its :class:`_Leg`."""

    def __init__(self, body: Body, st: GaitStyle, seconds: float, speed: float, fps: float,
                 closing_frame: bool):
        sk = body.skeleton
        self.body, self.st, self.speed = body, st, speed
        rw = sk.rest_world
        self.R0 = rw[:, :3, :3]
        self.P0 = rw[:, :3, 3]
        self.idx = {n: i for i, n in enumerate(sk.names)}
        self.legs = self._legs()
        self.ground = float(np.asarray(body.vertices)[:, 1].min())
        self.pelvis_j = self.idx["pelvis"]
        self.hip_height = float(np.mean([lg.hip0[1] for lg in self.legs]) - self.ground)
        self.leg_length = float(np.mean([lg.l1 + lg.l2 for lg in self.legs]))
        # timing: the clip holds whole gait cycles (so it loops); its length is the requested
        # one rounded to whole cycles and frames, which keeps the cadence within a frame of the
        # natural one
        stride0 = stride_length(self.hip_height, speed) * st.stride_scale
        period0 = stride0 / speed
        self.cycles = max(1, int(round(seconds / period0)))
        n_frames = max(2, int(round(self.cycles * period0 * fps)))
        self.clip = n_frames / fps
        self.period = self.clip / self.cycles
        self.stride = speed * self.period
        self.t_frames = np.arange(n_frames + (1 if closing_frame else 0)) / fps
        # the hip amplitude scaled so the curves' step matches the stride
        self.hip_mean = float(np.mean(HIP(np.linspace(0, 1, 200, endpoint=False))))
        self.hip_scale = self._hip_scale()
        self.toe_out = np.radians(st.toe_out_deg)
        for lg in self.legs:
            lg.pelvis_to_hip = lg.hip0 - self.P0[self.pelvis_j]
        # the pelvis's height is filled in by _pelvis_height, once the footprints are known
        self.height_grid = np.linspace(0.0, 1.0, 401)
        self.height_y = None
        # stance foot: pitch at heel strike and toe-off, and the rockers
        _, _, p_fk0 = self.sagittal(np.array([0.0]), self.hip_scale)
        _, _, p_fkto = self.sagittal(np.array([STANCE_END]), self.hip_scale)
        self.p_hs = max(float(p_fk0[0]), 0.0)
        self.p_to = min(float(p_fkto[0]), 0.0)
        for lg in self.legs:
            lg.heel0 = _foot_heel(body, lg.ankle, lg.ankle0, self.p_hs)
            lg.lift = _forefoot_lift(body, lg, self.p_to)
        self._footprint_offsets()
        self._pelvis_height()

    def _legs(self) -> list[_Leg]:
        P0, idx = self.P0, self.idx
        legs = []
        for side, phase0 in (("l", 0.0), ("r", 0.5)):
            hip, knee = idx[f"thigh_{side}"], idx[f"calf_{side}"]
            ankle, ball = idx[f"foot_{side}"], idx[f"ball_{side}"]
            toe0 = _toe_tip(self.body, ball, P0[ball])
            legs.append(_Leg(
                side=1.0 if side == "l" else -1.0, phase0=phase0, hip=hip, knee=knee,
                ankle=ankle, ball=ball, hip0=P0[hip], knee0=P0[knee], ankle0=P0[ankle],
                ball0=P0[ball], toe0=toe0, heel0=P0[ankle],
                l1=float(np.linalg.norm(P0[knee] - P0[hip])),
                l2=float(np.linalg.norm(P0[ankle] - P0[knee])),
                rest_bend=_angle(P0[knee] - P0[hip], P0[ankle] - P0[knee])))
        return legs

    # ---- the sagittal curves ------------------------------------------------------------
    def sagittal(self, phi, k):
        """The curves' foot (z, y) below the hip and its pitch at phases ``phi``, the hip
        curve scaled by ``k`` about its mean."""
        a_th = np.radians(self.hip_mean + k * (HIP(phi) - self.hip_mean) - PELVIC_TILT_MEAN_DEG)
        a_sh = a_th - np.radians(KNEE(phi))
        l1, l2 = self.legs[0].l1, self.legs[0].l2
        fz = l1 * np.sin(a_th) + l2 * np.sin(a_sh)
        fy = -(l1 * np.cos(a_th) + l2 * np.cos(a_sh))
        pitch = a_sh + np.radians(ANKLE(phi))
        return fz, fy, pitch

    def _fk_step(self, k) -> float:
        fz0, _, _ = self.sagittal(np.array([0.0]), k)
        fz5, _, _ = self.sagittal(np.array([0.5]), k)
        return float(fz0[0] - fz5[0])

    def _hip_scale(self) -> float:
        lo_k, hi_k = 0.3, 2.5
        for _ in range(50):
            mid = 0.5 * (lo_k + hi_k)
            if self._fk_step(mid) < 0.5 * self.stride:
                lo_k = mid
            else:
                hi_k = mid
        return 0.5 * (lo_k + hi_k)

    # ---- the pelvis ---------------------------------------------------------------------
    def foot_x(self, lg: _Leg) -> float:
        """The footprint ankle's x for the style (frontal geometry)."""
        st = self.st
        if st.foot_x is None:
            return lg.side * abs(lg.hip0[0])
        return lg.side * st.foot_x - lg.side * st.crossing

    def pelvis_state(self, t):
        """The pelvis at times ``t``: position, rotation, yaw, roll, tilt, phase."""
        st = self.st
        ph = (t / self.period) % 1.0
        yaw = np.radians(st.pelvis_rotation_deg) * np.cos(2 * np.pi * ph)   # left hip forward
        roll = np.radians(st.obliquity_scale * OBLIQUITY(ph))               # left hip up
        tilt = np.radians(st.tilt_amplitude_deg) * np.cos(4 * np.pi * (ph - 0.45))
        delta = rot_y(-yaw) @ rot_z(roll) @ rot_x(tilt)
        pos = np.zeros(t.shape + (3,))
        pos[..., 0] = st.sway_m * np.sin(2 * np.pi * ph)
        if self.height_y is not None:
            pos[..., 1] = np.interp(ph, self.height_grid, self.height_y)
        pos[..., 2] = self.P0[self.pelvis_j, 2] + self.speed * t
        return pos, delta, yaw, roll, tilt, ph

    @staticmethod
    def hip_pos(lg: _Leg, pos, delta):
        return pos + delta @ lg.pelvis_to_hip

    # ---- the stance foot ----------------------------------------------------------------
    def stance_pitch(self, phi):
        p = np.zeros_like(phi)
        a = phi < FOOT_FLAT
        p[a] = self.p_hs * (1.0 - _smooth(phi[a] / FOOT_FLAT))
        b = phi > HEEL_OFF
        s = (phi[b] - HEEL_OFF) / (STANCE_END - HEEL_OFF)
        p[b] = self.p_to * s * s
        return p

    @staticmethod
    def foot_point(lg: _Leg, q_rest, pitch, yaw_f, footprint):
        """World position of a rest-foot point for a foot rolled by ``pitch`` (toes up +) on
        its pivot (heel for p > 0, ball joint for p < 0) and placed on ``footprint`` (the
        flat-foot ankle position, (…, 3))."""
        pivot = np.where((pitch > 0)[..., None], lg.heel0, lg.ball0)
        rel = rot_x(-pitch) @ (q_rest - pivot)[..., None]
        local = (pivot - lg.ankle0) + rel[..., 0]
        return footprint + (rot_y(yaw_f) @ local[..., None])[..., 0]

    def leg_yaw(self, lg: _Leg) -> float:
        return lg.side * self.toe_out

    def _footprint_offsets(self) -> None:
        """Each leg's footprint z: the mean stance offset between the planted ankle and the
        curves' ankle."""
        period = self.period
        dense = np.linspace(0.0, period, 400, endpoint=False)
        pos_d, delta_d, *_ = self.pelvis_state(dense)
        for lg in self.legs:
            ph = (dense / period - lg.phase0) % 1.0
            stance = ph < STANCE_END
            hz = self.hip_pos(lg, pos_d, delta_d)[:, 2]
            fz, _, _ = self.sagittal(ph, self.hip_scale)
            fp0 = np.zeros((stance.sum(), 3))
            ank = self.foot_point(lg, lg.ankle0, self.stance_pitch(ph[stance]),
                                  self.leg_yaw(lg), fp0)
            kstep = np.floor(dense[stance] / period - lg.phase0)
            lg.fp_z0 = float(np.mean(hz[stance] + fz[stance] - ank[:, 2] - kstep * self.stride))

    def footprint(self, lg: _Leg, k):
        k = np.asarray(k, dtype=np.float64)
        out = np.zeros(k.shape + (3,))
        out[..., 0] = self.foot_x(lg)
        out[..., 1] = lg.ankle0[1]
        out[..., 2] = lg.fp_z0 + k * self.stride
        return out

    def _pelvis_height(self) -> None:
        """The pelvis height over the cycle: the height at which the stance legs, planted on
        their footprints, bend their knees as the knee curve says (weighted across double
        support), but never higher than any stance leg reaches with its knee bent at least
        knee_min. The vertical bob of the centre of mass comes out of this geometry (inverted
        pendulum)."""
        st, period = self.st, self.period
        grid_t = self.height_grid[:-1] * period
        pos_g, delta_g, *_ = self.pelvis_state(grid_t)          # height 0 for now
        num = np.zeros(len(grid_t))
        den = np.zeros(len(grid_t))
        cap = np.full(len(grid_t), np.inf)
        ds = STANCE_END - 0.5                               # double-support fraction
        for lg in self.legs:
            ph = (grid_t / period - lg.phase0) % 1.0
            stance = ph < STANCE_END
            kstep = np.floor(grid_t[stance] / period - lg.phase0)
            pst = self.stance_pitch(ph[stance])
            ank = self.foot_point(lg, lg.ankle0, pst, self.leg_yaw(lg), self.footprint(lg, kstep))
            ank[:, 1] += np.interp(pst, *lg.lift)
            hp = self.hip_pos(lg, pos_g[stance], delta_g[stance])
            knee_c = np.maximum(st.knee_min_deg, st.stance_knee_scale * KNEE(ph[stance]))
            want = _reach_height(lg, ank, hp, knee_c)
            top = _reach_height(lg, ank, hp, st.knee_min_deg)
            w = np.where(ph[stance] < ds, _smooth(ph[stance] / ds),
                         np.where(ph[stance] > 0.5, 1.0 - _smooth((ph[stance] - 0.5) / ds), 1.0))
            num[stance] += w * want
            den[stance] += w
            cap[stance] = np.minimum(cap[stance], top)
        y_cycle = np.minimum(num / np.maximum(den, 1e-9), cap)
        # soften the corners (circular moving average over ±2 % of the cycle), then re-cap
        kern = np.ones(9) / 9.0
        y_cycle = np.minimum(np.convolve(np.concatenate([y_cycle[-4:], y_cycle, y_cycle[:4]]),
                                         kern, mode="valid"), cap)
        self.height_y = np.append(y_cycle, y_cycle[0])
        self.y0 = float(np.mean(y_cycle))
        self.bob = float(np.ptp(y_cycle))

    def fk_at(self, lg: _Leg, tt, phi):
        """The curves' ankle position at times ``tt`` for a fixed phase ``phi``."""
        pp, dd, *_ = self.pelvis_state(tt)
        fz_, fy_, _ = self.sagittal(np.full(tt.shape, phi), self.hip_scale)
        return self.hip_pos(lg, pp, dd) + np.stack([np.zeros_like(tt), fy_, fz_], axis=1)


class _Pose:
    """Every frame's joint rotations relative to the rest pose (``delta``, (F, J, 3, 3)); the
    joints given one explicitly (``explicit``) — the others follow their parent."""

    def __init__(self, frames: int, joints: int, idx: dict):
        self.idx = idx
        self.delta = np.repeat(np.eye(3)[None, None], frames, axis=0).repeat(joints, axis=1)
        self.explicit = np.zeros(joints, dtype=bool)

    def set(self, name_or_j, d) -> None:
        j = name_or_j if isinstance(name_or_j, int) else self.idx[name_or_j]
        self.delta[:, j] = d
        self.explicit[j] = True


def _swing_ankle(g: _Gait, lg: _Leg, sw, ph, kstep, hip_w, fy, fz, pfk, yaw_f):
    """The swing foot's ankle target and pitch at the frames ``sw``: along the curves' ankle
    path from the moving hip, blended from the toe-off footprint to the next heel-strike one,
    with lateral clearance round the stance leg and the toes kept 1.5 cm·sin off the floor;
    also the toes' bend relative to the foot."""
    st, period = g.st, g.period
    s = (ph[sw] - STANCE_END) / (1.0 - STANCE_END)
    k = kstep[sw]
    t_to = (k + lg.phase0 + STANCE_END) * period
    t_hs = (k + 1 + lg.phase0) * period
    fk_now = hip_w[sw] + np.stack([np.zeros_like(s), fy[sw], fz[sw]], axis=1)
    a_to = g.foot_point(lg, lg.ankle0, np.full(s.shape, g.p_to), yaw_f, g.footprint(lg, k))
    a_hs = g.foot_point(lg, lg.ankle0, np.full(s.shape, g.p_hs), yaw_f, g.footprint(lg, k + 1))
    d0 = a_to - g.fk_at(lg, t_to, STANCE_END)
    d1 = a_hs - g.fk_at(lg, t_hs, 1.0)
    w = _smooth(s)[:, None]
    target = fk_now + d0 * (1 - w) + d1 * w
    # lateral clearance around the stance leg
    target[:, 0] += lg.side * st.swing_clearance_m * np.sin(np.pi * s)
    # pitch: the ankle curve, matched to the stance pitch at both ends
    pitch_sw = pfk[sw] + (g.p_to - float(g.sagittal(np.array([STANCE_END]),
                                                    g.hip_scale)[2][0])) * (1 - _smooth(s)) \
        + (g.p_hs - float(g.sagittal(np.array([1.0]), g.hip_scale)[2][0])) * _smooth(s)
    toe_rel = -g.p_to * (1.0 - _smooth(np.clip(s / 0.35, 0.0, 1.0)))
    # toe clearance: lift the foot where its lowest point would come under 1.5 cm·sin
    pts = []
    for q in (lg.heel0, lg.toe0, np.array([lg.ball0[0], 0.0, lg.ball0[2]])):
        rel = rot_x(-pitch_sw) @ (q - lg.ankle0)
        pts.append(target[:, 1] + (rot_y(yaw_f) @ rel[..., None])[..., 0][:, 1])
    lowest = np.min(np.stack(pts), axis=0) - g.ground
    want = 0.015 * np.sin(np.pi * s)
    target[:, 1] += np.maximum(0.0, want - lowest)
    return target, pitch_sw, toe_rel


def _pose_leg(g: _Gait, pose: _Pose, lg: _Leg, pos, delta_p) -> None:
    """The leg's thigh, calf, foot and toes: the stance foot planted on its footprint and
    rolled over heel, sole and ball, the swing foot along :func:`_swing_ankle`, the knee by
    two-bone IK towards the toes."""
    t_frames = g.t_frames
    F = len(t_frames)
    tau = t_frames / g.period - lg.phase0
    ph = tau % 1.0
    kstep = np.floor(tau)
    stance = ph < STANCE_END
    yaw_f = g.leg_yaw(lg)
    hip_w = g.hip_pos(lg, pos, delta_p)
    fz, fy, pfk = g.sagittal(ph, g.hip_scale)
    pitch = np.where(stance, g.stance_pitch(ph), pfk)
    ankle_t = np.zeros((F, 3))
    toe_rel = np.zeros(F)
    # stance: on the footprint
    if np.any(stance):
        ankle_t[stance] = g.foot_point(lg, lg.ankle0, pitch[stance], yaw_f,
                                       g.footprint(lg, kstep[stance]))
        ankle_t[stance, 1] += np.interp(pitch[stance], *lg.lift)
        toe_rel[stance] = np.where(pitch[stance] < 0, -pitch[stance], 0.0)
    sw = ~stance
    if np.any(sw):
        ankle_t[sw], pitch[sw], toe_rel[sw] = _swing_ankle(g, lg, sw, ph, kstep, hip_w, fy, fz,
                                                           pfk, yaw_f)
    # two-bone IK, knee towards the toes
    pole = np.stack([np.full(F, np.sin(yaw_f)), np.zeros(F), np.full(F, np.cos(yaw_f))],
                    axis=1)
    knee_w, ankle_w = two_bone_ik(hip_w, ankle_t, pole, lg.l1, lg.l2,
                                  min_bend_deg=float(np.degrees(lg.rest_bend)))
    side_axis = np.cross(pole, ankle_w - hip_w)
    side_axis /= np.linalg.norm(side_axis, axis=1, keepdims=True)
    x_axis = np.array([1.0, 0.0, 0.0])
    pose.set(lg.hip, bone_delta(lg.knee0 - lg.hip0, x_axis, knee_w - hip_w, side_axis))
    pose.set(lg.knee, bone_delta(lg.ankle0 - lg.knee0, x_axis, ankle_w - knee_w, side_axis))
    pose.set(lg.ankle, rot_y(yaw_f) @ rot_x(-pitch))
    pose.set(lg.ball, rot_y(yaw_f) @ rot_x(-(pitch + toe_rel)))


def _pose_trunk(g: _Gait, pose: _Pose, yaw_p, roll_p, tilt_p) -> np.ndarray:
    """The spine blends from the pelvis to the counter-rotated thorax; the head level; the
    clavicles with the thorax. Returns the thorax's rotation."""
    st = g.st
    yaw_t = -st.thorax_counter * yaw_p
    roll_t = -0.3 * roll_p
    for frac, name in ((1 / 3, "spine_01"), (2 / 3, "spine_02"), (1.0, "spine_03")):
        yw = (1 - frac) * yaw_p + frac * yaw_t
        rl = (1 - frac) * roll_p + frac * roll_t
        tl = (1 - frac) * tilt_p
        pose.set(name, rot_y(-yw) @ rot_z(rl) @ rot_x(tl))
    d_thorax = pose.delta[:, pose.idx["spine_03"]]
    pose.set("neck_01", rot_y(0.5 * st.thorax_counter * yaw_p) @ rot_z(0.5 * roll_t))
    pose.set("head", np.eye(3))
    pose.set("clavicle_l", d_thorax)
    pose.set("clavicle_r", d_thorax)
    return d_thorax


def _pose_arms(g: _Gait, pose: _Pose, d_thorax) -> None:
    """The arms: down from the A-pose to clear the torso, then a swing in antiphase with the
    same-side leg, the elbow flexing as the arm swings forward."""
    st, P0, idx = g.st, g.P0, g.idx
    for side, phase0 in (("l", 0.0), ("r", 0.5)):
        sgn = 1.0 if side == "l" else -1.0
        ju, jf, jh = idx[f"upperarm_{side}"], idx[f"lowerarm_{side}"], idx[f"hand_{side}"]
        u0 = P0[jf] - P0[ju]
        f0 = P0[jh] - P0[jf]
        lu, lf = float(np.linalg.norm(u0)), float(np.linalg.norm(f0))
        a_rest = float(np.arctan2(abs(u0[0]), -u0[1]))
        a_tgt = _arm_clearance_abduction(g.body, g.body.skeleton, side, P0[ju], lu, lf)
        lower = rot_z(-sgn * (a_rest - a_tgt))
        ph = (g.t_frames / g.period - phase0) % 1.0
        flex = np.radians(st.arm_swing_deg) * np.cos(2 * np.pi * (ph - 0.5))
        d_upper = d_thorax @ rot_x(-flex) @ lower
        hinge = np.cross(u0, f0)
        hinge /= np.linalg.norm(hinge)
        e_rest = float(np.arccos(np.clip(np.dot(u0, f0) / (lu * lf), -1, 1)))
        elbow = np.radians(st.elbow_mean_deg + st.elbow_amp_deg * np.cos(2 * np.pi * (ph - 0.5)))
        pose.set(ju, d_upper)
        pose.set(jf, d_upper @ axis_angle(hinge, elbow - e_rest))


def _finger_curls(sk, R0) -> dict:
    """Relaxed hands: each finger segment curls a little about its own X axis (Blender's bend
    axis); joint → its rotation."""
    extra = {}
    for j, name in enumerate(sk.names):
        base, _, side = name.rpartition("_")
        finger, _, seg = base.partition("_")
        if side in ("l", "r") and finger in FINGER_CURL_DEG and seg in ("01", "02", "03"):
            extra[j] = axis_angle(R0[j][:, 0], np.radians(FINGER_CURL_DEG[finger][int(seg) - 1]))
    return extra


def _local_transforms(g: _Gait, pose: _Pose, pos) -> tuple[np.ndarray, np.ndarray]:
    """World transforms down the hierarchy (joints without a rotation of their own follow
    their parent, fingers curled), then the local ones: (F, J, 4) quaternions and (F, J, 3)
    translations."""
    sk, R0, P0, speed, t_frames = g.body.skeleton, g.R0, g.P0, g.speed, g.t_frames
    F, J = len(t_frames), len(sk.names)
    delta, explicit = pose.delta, pose.explicit
    extra = _finger_curls(sk, R0)
    world_R = np.repeat(R0[None], F, axis=0)
    world_p = np.repeat(P0[None], F, axis=0)
    root_j = g.idx["Root"]
    for j, p in enumerate(sk.parents):
        if j in extra and not explicit[j] and p >= 0:
            delta[:, j] = delta[:, p] @ extra[j]
        elif not explicit[j] and p >= 0:
            delta[:, j] = delta[:, p]
        world_R[:, j] = delta[:, j] @ R0[j]
        if j == root_j:
            world_p[:, j] = P0[j] + np.stack([np.zeros(F), np.zeros(F), speed * t_frames], 1)
        elif j == g.pelvis_j:
            world_p[:, j] = pos
        elif p >= 0:
            world_p[:, j] = world_p[:, p] + (world_R[:, p] @ sk.rest_local[j, :3, 3][:, None])[
                ..., 0]
    rot_local = np.empty((F, J, 4))
    trans_local = np.empty((F, J, 3))
    for j, p in enumerate(sk.parents):
        if p < 0:
            lr, lt = world_R[:, j], world_p[:, j]
        else:
            rpt = np.swapaxes(world_R[:, p], -1, -2)
            lr = rpt @ world_R[:, j]
            lt = (rpt @ (world_p[:, j] - world_p[:, p])[..., None])[..., 0]
        rot_local[:, j] = mat_to_quat(lr)
        trans_local[:, j] = lt
    return make_continuous(rot_local), trans_local


def walk_motion(body: Body, seconds: float, speed: float = 1.2, style: str = "catwalk",
                fps: float = 30, closing_frame: bool = False,
                arm_swing_deg: float | None = None) -> Motion:
    """A looping walk for a rigged body (see the module docstring).

    ``arm_swing_deg``: the arms' swing amplitude about the shoulder, forward and back (default
    the style's: 11° catwalk, 16° normal); up to 90° (arms raised to the horizontal at the
    front of the swing — and, beyond the shoulder's ≈ 60° of extension, at its back: a stress
    case, not a pose).

    The clip holds a whole number of gait cycles: ``seconds`` is rounded to whole cycles (and
    frames). Frame ``frames`` (one past the last) would equal frame 0 moved forward by
    ``meta["loop_offset"]``; ``closing_frame=True`` appends it (for players that need the
    closing key; the Motion is then not ``loop``-wrapped for velocities).
    """
    st = _checked_style(body, seconds, speed, style, fps, arm_swing_deg)
    g = _Gait(body, st, seconds, speed, fps, closing_frame)
    pos, delta_p, yaw_p, roll_p, tilt_p, _ = g.pelvis_state(g.t_frames)
    pose = _Pose(len(g.t_frames), len(body.skeleton.names), g.idx)
    pose.set("pelvis", delta_p)
    pose.set("Root", np.eye(3))
    for lg in g.legs:
        _pose_leg(g, pose, lg, pos, delta_p)
    d_thorax = _pose_trunk(g, pose, yaw_p, roll_p, tilt_p)
    _pose_arms(g, pose, d_thorax)
    rot_local, trans_local = _local_transforms(g, pose, pos)
    meta = {
        "style": style, "speed_m_s": float(speed), "stride_m": float(g.stride),
        "step_length_m": float(g.stride / 2), "cycle_s": float(g.period), "cycles": g.cycles,
        "cadence_steps_per_min": float(120.0 / g.period), "hip_height_m": g.hip_height,
        "leg_length_m": g.leg_length, "hip_amplitude_scale": float(g.hip_scale),
        "loop_offset": [0.0, 0.0, float(speed * g.clip)],
        "step_width_m": float(abs(g.foot_x(g.legs[0]) - g.foot_x(g.legs[1]))),
        "pelvis_height_m": g.y0, "pelvis_bob_m": g.bob,
        "stance_end": STANCE_END,
    }
    return Motion(fps=float(fps), rotations=rot_local, translations=trans_local,
                  loop=not closing_frame, meta=meta)


# ---- checks (used by tests and `catwalk bench gait`) ------------------------------------------


