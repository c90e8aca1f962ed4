"""``catwalk walk --body body.glb --seconds S [--speed 1.2] [--style catwalk|normal]
-o walk.glb``: a rigged body walking, written as an animated .glb."""

from __future__ import annotations

import json
import math
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from catwalk.body.rig import rigged_base_body, skin_weights
from catwalk.body.skinning import (
    Skinner,
    body_frames,
    joint_world_matrices,
    skinning_matrices,
)
from catwalk.errors import InputError
from catwalk.exchange.gltf import read_body, write_glb
from catwalk.motion.checks import (
    armpit_faces,
    foot_sliding,
    foot_vertices,
    inverted_triangles,
    sagittal_angles,
)
from catwalk.motion.gait import ANKLE, HIP, KNEE, STYLES, walk_motion


def _walk(args) -> int:
    body_path = Path(args.body)
    if not body_path.is_file():
        raise InputError(f"--body {body_path}: no such file")
    if not math.isfinite(args.seconds) or args.seconds <= 0:
        raise InputError(f"--seconds must be > 0, got {args.seconds}")
    if args.seconds > 600:
        raise InputError(f"--seconds {args.seconds}: at most 600 s")
    if not math.isfinite(args.speed) or not 0.3 <= args.speed <= 3.0:
        raise InputError(f"--speed must be within 0.3–3 m/s, got {args.speed}")
    if not math.isfinite(args.fps) or not 1 <= args.fps <= 240:
        raise InputError(f"--fps must be within 1–240, got {args.fps}")
    if args.style not in STYLES:
        raise InputError(f"--style must be one of {', '.join(STYLES)}")
    if not str(args.output).lower().endswith(".glb"):
        raise InputError(f"-o {args.output}: the walk is written as a .glb file")


    t0 = time.perf_counter()
    body = read_body(body_path)
    if body.skeleton is None or body.skin_joints is None or body.skin_weights is None:
        raise InputError(f"--body {body_path}: the body has no rig (skeleton and skin "
                           "weights); make one with `catwalk body make`")
    motion = walk_motion(body, args.seconds, speed=args.speed, style=args.style, fps=args.fps)
    write_glb(args.output, body, motion)
    m = motion.meta
    print(json.dumps({
        "file": str(args.output), "frames": motion.frames, "fps": motion.fps,
        "seconds": round(motion.seconds, 4), "style": m["style"], "speed_m_s": m["speed_m_s"],
        "cycles": m["cycles"], "stride_m": round(m["stride_m"], 4),
        "cadence_steps_per_min": round(m["cadence_steps_per_min"], 1),
        "step_width_m": round(m["step_width_m"], 4),
        "elapsed_s": round(time.perf_counter() - t0, 2)}, indent=2))
    return 0


def _bench_skinning(args) -> int:
    if args.repeats < 1:
        raise InputError("--repeats must be ≥ 1")
    body = rigged_base_body(0.5)
    motion = walk_motion(body, args.seconds, speed=1.2, style="catwalk", fps=args.fps)
    sk = body.skeleton
    world = joint_world_matrices(sk, motion.rotations, motion.translations)
    mats = skinning_matrices(sk, world)
    skinner = Skinner(body.vertices, body.skin_joints, body.skin_weights, len(sk.names))
    mats32 = np.ascontiguousarray(mats[..., :3, :4], dtype=np.float32)
    out = np.empty((len(body.vertices), 3), np.float32)
    skinner(mats[0])                     # compile / load the kernels
    skinner(mats[:2])

    def best(fn, n):
        times = []
        for _ in range(n):
            t0 = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t0)
        return min(times), float(np.median(times))

    one_min, one_med = best(lambda: [skinner(mats32[f], out) for f in range(motion.frames)],
                            args.repeats)
    batch_min, batch_med = best(lambda: skinner(mats32), args.repeats)
    fk_min, _ = best(lambda: joint_world_matrices(sk, motion.rotations, motion.translations),
                     args.repeats)
    bf_min, _ = best(lambda: body_frames(body, motion), args.repeats)
    gen_min, _ = best(lambda: walk_motion(body, args.seconds, 1.2, "catwalk", args.fps),
                      max(1, args.repeats // 3))
    f = motion.frames
    result = {
        "vertices": int(len(body.vertices)), "joints": len(sk.names), "frames": f,
        "skin_us_per_frame_single_call": round(1e6 * one_min / f, 1),
        "skin_us_per_frame_single_call_median": round(1e6 * one_med / f, 1),
        "skin_us_per_frame_batched": round(1e6 * batch_min / f, 1),
        "skin_us_per_frame_batched_median": round(1e6 * batch_med / f, 1),
        "fk_us_per_frame": round(1e6 * fk_min / f, 1),
        "body_frames_us_per_frame": round(1e6 * bf_min / f, 1),
        "walk_motion_ms": round(1e3 * gen_min, 1),
    }
    if args.json:
        print(json.dumps(result, indent=2))
    else:
        for k, v in result.items():
            print(f"{k:40s} {v}")
    return 0


def _bench_gait(args) -> int:
    rows = []
    for gender, label in ((0.0, "female"), (0.5, "neutral"), (1.0, "male")):
        body = rigged_base_body(gender)
        feet = np.concatenate([foot_vertices(body, "l"), foot_vertices(body, "r")])
        pits = body.faces[armpit_faces(body)]
        # the same body with MakeHuman's armpit weights as they are: what the diffusion buys
        joints, weights, parts = skin_weights(body.skeleton.names, armpit_smoothing=0)
        raw = replace(body, skin_joints=joints, skin_weights=weights, parts=parts)
        for style in ("catwalk", "normal"):
            for speed in args.speed:
                m = walk_motion(body, args.seconds, speed=speed, style=style, fps=args.fps)
                verts, vel = body_frames(body, m)
                slide = foot_sliding(body, m, verts)
                low = verts[:, feet, 1].min(axis=1)
                q = m.rotations
                dots = np.concatenate([np.sum(q[1:] * q[:-1], axis=-1).ravel(),
                                       np.sum(q[0] * q[-1], axis=-1).ravel()])
                offset = np.asarray(m.meta["loop_offset"], dtype=np.float32)
                wrap = float(np.linalg.norm(verts[0] + offset - verts[-1], axis=1).max())
                step = float(np.linalg.norm(np.diff(verts, axis=0), axis=2).max())
                ph, hip, knee, ankle = sagittal_angles(body, m, "l")

                def rms(a, ref):
                    return round(float(np.sqrt(np.mean((a - ref) ** 2))), 1)
                rows.append({
                    "body": label, "style": style, "speed_m_s": speed,
                    "stride_m": round(m.meta["stride_m"], 3),
                    "cadence_steps_per_min": round(m.meta["cadence_steps_per_min"], 1),
                    "step_width_m": round(m.meta["step_width_m"], 3),
                    "steps": int(len(slide)),
                    "foot_slide_per_step_max_mm": round(1000 * float(slide.max()), 2),
                    "foot_slide_per_step_mean_mm": round(1000 * float(slide.mean()), 2),
                    "feet_lowest_mm": round(1000 * float(low.min()), 2),
                    "feet_highest_support_mm": round(1000 * float(low.max()), 2),
                    "min_consecutive_quat_dot": round(float(dots.min()), 5),
                    "loop_wrap_jump_mm": round(1000 * wrap, 1),
                    "largest_frame_step_mm": round(1000 * step, 1),
                    "mean_forward_velocity_m_s": round(float(vel[..., 2].mean()), 4),
                    "pelvis_bob_cm": round(100 * m.meta["pelvis_bob_m"], 2),
                    "hip_rms_vs_curve_deg": rms(hip, HIP(ph)),
                    "knee_rms_vs_curve_deg": rms(knee, KNEE(ph)),
                    "ankle_rms_vs_curve_deg": rms(ankle, ANKLE(ph)),
                    "knee_range_deg": [round(float(knee.min()), 1), round(float(knee.max()), 1)],
                    "armpit_inverted_triangles_max": int(
                        inverted_triangles(body, m, verts, pits).max()),
                    "armpit_inverted_triangles_max_undiffused": int(
                        inverted_triangles(raw, m, body_frames(raw, m)[0], pits).max()),
                })
    if args.json:
        print(json.dumps(rows, indent=2))
    else:
        keys = list(rows[0])
        print("  ".join(keys))
        for r in rows:
            print("  ".join(str(r[k]) for k in keys))
    return 0


def register(top, groups) -> None:
    if "bench" in groups:
        g = groups["bench"].add_parser(
            "gait", help="walk checks: foot sliding, floor contact, flips, loop closure, "
            "armpits turned inside out")
        g.add_argument("--seconds", type=float, default=4.0, help="walk length, s")
        g.add_argument("--fps", type=float, default=30.0)
        g.add_argument("--speed", type=float, nargs="+", default=[1.2], help="m/s")
        g.add_argument("--json", action="store_true", help="print JSON")
        g.set_defaults(func=_bench_gait)
        b = groups["bench"].add_parser(
            "skinning", help="time linear blend skinning and the walk (13k-vertex body)")
        b.add_argument("--seconds", type=float, default=4.0, help="walk length, s")
        b.add_argument("--fps", type=float, default=30.0)
        b.add_argument("--repeats", type=int, default=20)
        b.add_argument("--json", action="store_true", help="print JSON")
        b.set_defaults(func=_bench_skinning)

    p = top.add_parser("walk", help="make a rigged body walk (catwalk or normal gait) → .glb",
                       description="Animate a rigged body (.glb from `catwalk body make`) with "
                       "a looping procedural walk and write it as a .glb.")
    p.add_argument("--body", required=True, help="rigged body .glb")
    p.add_argument("--seconds", type=float, required=True,
                   help="clip length, s (rounded to whole gait cycles at the given speed)")
    p.add_argument("--speed", type=float, default=1.2, help="walking speed, m/s (0.3–3)")
    p.add_argument("--style", default="catwalk", choices=("catwalk", "normal"),
                   help="catwalk: feet on the midline; normal: feet under the hips")
    p.add_argument("--fps", type=float, default=30.0, help="frames per second")
    p.add_argument("-o", "--output", required=True, help=".glb to write")
    p.set_defaults(func=_walk)
