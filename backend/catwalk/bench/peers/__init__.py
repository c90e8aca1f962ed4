"""``catwalk bench peers``: the same garment on the same walking body, simulated by other
cloth simulators, each timed per frame and judged by catwalk's own measures.

The scene (:mod:`.scene`) is written once to an ``.npz``; each peer runs in its own process
(its own Python, its own libraries) from a runner script beside this module, reads the scene,
and writes the garment's positions at every frame and the wall seconds each frame took:

* ``blender``: Blender's cloth (Debian's ``blender``, headless, one thread; ``blender_run.py``,
  installed by ``blender_setup.sh``);
* ``newton``: NVIDIA Newton's cloth solver on the CPU through Warp (``newton_run.py``, a venv
  made by ``newton_setup.sh`` under ``.peers/``).

Neither is installed by ``make test``: the benchmark installs what is missing the first time
it runs a peer (Blender needs root for apt-get). catwalk itself walks the scene with its
default collider (``hybrid``) and with ``object``, measured by the same function. Each row:
ms per frame (mean over the recorded frames; catwalk's is collider + cloth, a peer's the whole
frame it advances, its one-off set-up and compilation outside), the ratio to catwalk's
default, max and p99 penetration, max and p99 strain (against the pattern's rest lengths, τ =
the fabric's limit), and the RMS distance to catwalk's default run.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

import numpy as np

from catwalk.bench import (
    add_output_flags,
    add_walk_seconds,
    check_walk_seconds,
    cpu_model,
    log_lines,
)
from catwalk.bench.peers.scene import measure, paper_scene, rms_mm, welded
from catwalk.cloth.solvers import ClothExplosionError
from catwalk.errors import InputError
from catwalk.simulate.walking import walk

HERE = Path(__file__).resolve().parent
PEERS = ("blender", "newton")
PEER_TIMEOUT_S = 600
BLENDER_QUALITY = 10
BLENDER_COLLISION_QUALITY = 4


def newton_venv() -> Path:
    """Where ``newton_setup.sh`` makes Newton's venv (``CATWALK_PEERS_DIR``, default ``.peers``
    in the working directory)."""
    return Path(os.environ.get("CATWALK_PEERS_DIR", ".peers")).resolve() / "newton"


def _install(script: str, *args: str) -> None:
    """Run a set-up script quietly (its output would mix with --json); its tail on failure."""
    p = subprocess.run(["bash", str(HERE / script), *args], capture_output=True, text=True)
    if p.returncode:
        tail = (p.stderr or p.stdout).strip().splitlines()[-3:]
        raise OSError(f"{script} failed (exit {p.returncode}): " + " | ".join(tail))


def _setup(peer: str) -> list[str]:
    """Install ``peer`` if missing; the command line that runs its runner script."""
    if peer == "blender":
        _install("blender_setup.sh")
        return ["blender", "-b", "--factory-startup", "-t", "1", "--python-exit-code", "1",
                "--python",
                str(HERE / "blender_run.py"), "--"]
    venv = newton_venv()
    _install("newton_setup.sh", str(venv))
    return [str(venv / "bin" / "python"), str(HERE / "newton_run.py")]


def _peer_runs(peers, opts: dict) -> list[tuple[str, str, list[str]]]:
    """(row name, peer, the runner's extra arguments) for each run asked for: Blender once per
    quality (its cloth steps a frame)."""
    runs = []
    for peer in peers:
        if peer == "blender":
            for q in opts.get("blender_quality", [BLENDER_QUALITY]):
                runs.append((f"blender-q{q}", peer, [
                    "--quality", str(q), "--collision-quality", str(BLENDER_COLLISION_QUALITY)]))
        else:
            runs.append((peer, peer, []))
    return runs


def peer_timeout(frames: int) -> float:
    """Seconds a peer may run: its set-up and compilation, and 30 s a frame (Newton took 6)."""
    return PEER_TIMEOUT_S + 30.0 * frames


def run_peer(peer: str, scene_path: Path, out_path: Path, args: list[str],
             timeout: float = PEER_TIMEOUT_S) -> dict:
    """Run one peer on the scene file (``args``: the runner's own options): its positions,
    frame seconds and info, or an error (a peer that cannot be installed, fails, runs past
    ``timeout`` seconds or writes a result that cannot be read)."""
    try:
        cmd = _setup(peer)
    except OSError as exc:
        return {"error": f"could not install {peer}: {exc}"}
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    out_path.unlink(missing_ok=True)     # never read an earlier run's result as this one's
    t0 = time.perf_counter()
    try:
        p = subprocess.run(cmd + [str(scene_path), str(out_path)] + args,
                           capture_output=True, text=True, timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        return {"error": f"{peer} ran past {timeout:.0f} s"}
    except OSError as exc:
        return {"error": f"could not start {peer}: {exc}"}
    wall = time.perf_counter() - t0
    if not out_path.exists():
        tail = (p.stderr or p.stdout).strip().splitlines()[-5:]
        return {"error": f"{peer} wrote no result (exit {p.returncode}): " + " | ".join(tail)}
    try:
        with np.load(out_path) as r:
            info = json.loads(str(r["info"]))
            positions, secs = r["positions"], r["frame_seconds"]
    except (OSError, ValueError, KeyError, zipfile.BadZipFile) as exc:
        return {"error": f"{peer}'s result {out_path.name} cannot be read: {exc}"}
    error = info.get("error") or "; ".join(info.get("errors", [])) or None
    if error is None and p.returncode:
        error = f"exit {p.returncode}"
    return {"positions": positions, "frame_seconds": secs, "info": info, "wall_s": wall,
            "error": error}


def _peer_row(scene, r: dict) -> dict:
    """A peer's row: its ms per frame over the recorded frames it reached, and the measures
    when it reached them all (``incomplete``: how many it did, when not)."""
    row = {"settings": r.get("info", {})}
    if r.get("error"):
        row["error"] = r["error"]
    if "positions" not in r:
        return row
    secs = np.asarray(r["frame_seconds"])[scene.n_pre - 1:]
    pos = np.asarray(r["positions"])
    pos = pos[scene.n_pre:] if pos.ndim == 3 else pos[:0]
    if len(secs) == 0:
        row.setdefault("error", "no recorded frame reached")
        return row
    row.update(ms_per_frame=round(1e3 * float(np.mean(secs)), 1),
               wall_s=round(r["wall_s"], 1), positions=pos)
    if len(pos) == len(scene.recorded):
        row.update(measure(scene, pos))
    else:
        row["incomplete"] = len(pos)
    return row


def _catwalk_rows(scene, log) -> dict:
    rows = {}
    for mode in ("hybrid", "object"):
        say = log or (lambda *a: None)
        say(f"catwalk: walking with the {mode} collider")
        try:
            w = walk(scene.body, scene.motion, scene.dressed,
                     scene.settings.with_(collider=mode), measure=False)
        except ClothExplosionError as exc:
            rows[f"catwalk-{mode}"] = {"error": str(exc)}
            continue
        ms = w.stats["ms_per_frame"]
        pos = welded(scene.dressed, w.positions)
        rows[f"catwalk-{mode}"] = {
            "ms_per_frame": round(ms["collider"] + ms["cloth"], 1), "positions": pos,
            "settings": {"collider": mode, "preset": scene.settings.name,
                         "h_m": scene.settings.h, "threads": scene.settings.threads,
                         # the walk's own strain figures are of its simulated state; the
                         # row's of the positions it shows (off the body's sharp vertices)
                         "state_max_strain": round(w.stats["max_strain"], 4),
                         "state_p99_strain": round(w.stats["p99_strain"], 4),
                         "cloth_steps_per_frame": w.stats["cloth_steps_per_frame"],
                         "collisions_per_frame": w.stats["collisions_per_frame"]},
            **measure(scene, pos)}
    return rows


def run(seconds: float = 2.0, peers=PEERS, opts: dict | None = None, log=None,
        keep: str | None = None) -> dict:
    """Dress the scene, walk it with catwalk, run each peer on it, measure them all.
    ``keep``: a directory to keep the scene and the peers' results in."""
    say = log or (lambda *a: None)
    say("dressing the paper's scene")
    scene = paper_scene(seconds)
    rows = _catwalk_rows(scene, log)
    base = rows.get(f"catwalk-{scene.settings.collider}", {})   # catwalk's default
    with tempfile.TemporaryDirectory(prefix="catwalk-peers-") as tmp:
        work = Path(keep or tmp)
        work.mkdir(parents=True, exist_ok=True)
        scene_path = scene.save(work / "scene.npz")
        for name, peer, args in _peer_runs(peers, opts or {}):
            say(f"{name}: simulating (its set-up first, if missing)")
            r = run_peer(peer, scene_path, work / f"{name}.npz", args,
                         timeout=peer_timeout(len(scene.frames)))
            rows[name] = _peer_row(scene, r)
    for row in rows.values():
        if "ms_per_frame" in row and "ms_per_frame" in base:
            row["ratio_to_catwalk"] = round(row["ms_per_frame"] / base["ms_per_frame"], 2)
            if row.get("finite") and base.get("finite"):
                row["rms_to_catwalk_mm"] = rms_mm(row["positions"], base["positions"])
    for row in rows.values():
        row.pop("positions", None)
    return {"machine": {"cpu": cpu_model(), "threads": 1},
            "scene": {"garment": "dress", "size": "M", "h_m": scene.h,
                      "points": int(scene.dressed.model.n_points),
                      "triangles": int(len(scene.dressed.model.triangles)),
                      "body_triangles": int(len(scene.body.faces)),
                      "frames": len(scene.recorded), "steps": len(scene.frames) - 1,
                      "fps": float(scene.motion.fps),
                      "tau": float(scene.dressed.cloth.fabric.tau)},
            "runs": rows}


def format_table(r: dict) -> str:
    s = r["scene"]
    lines = [f"scene: {s['garment']} {s['size']}, {s['points']} points, {s['triangles']} "
             f"triangles, on the walking body ({s['body_triangles']} triangles), "
             f"{s['frames']} recorded frames at {s['fps']:.0f} fps; τ = {s['tau']}; "
             f"machine: {r['machine']['cpu']}, one thread",
             "",
             "| run | ms/frame | × catwalk | max / p99 penetration (mm) | max / p99 strain | "
             "RMS to catwalk (mm) |",
             "|---|---|---|---|---|---|"]
    for name, row in r["runs"].items():
        if "ms_per_frame" not in row:
            lines.append(f"| {name} | failed: {row.get('error')} | | | | |")
            continue
        err = f" (stopped: {row['error']})" if row.get("error") else ""
        if row.get("finite"):
            pen = f"{row['max_penetration_mm']:.1f} / {row['p99_penetration_mm']:.1f}"
            strain = f"{row['max_strain']:.3f} / {row['p99_strain']:.3f}"
        elif "incomplete" in row:
            pen = strain = f"stopped after {row['incomplete']} of {s['frames']} frames"
        else:
            pen = strain = "non-finite"
        lines.append(f"| {name}{err} | {row['ms_per_frame']:.1f} | "
                     f"{row.get('ratio_to_catwalk', '')} | {pen} | {strain} | "
                     f"{row.get('rms_to_catwalk_mm', '')} |")
    return "\n".join(lines)


def register(bench) -> None:
    p = bench.add_parser(
        "peers", help="the paper's scene simulated by Blender's cloth and by Newton beside "
        "catwalk: ms per frame, penetration, strain",
        description="Dress the paper's scene once; walk it with catwalk and have each peer "
        "(installed on first use, not by make test) simulate the same garment on the same "
        "walking body; time and measure every run the same way.")
    add_walk_seconds(p)
    p.add_argument("--peers", nargs="+", default=list(PEERS), choices=list(PEERS),
                   help="which peers to run (default: all)")
    p.add_argument("--blender-quality", type=int, nargs="+", default=[BLENDER_QUALITY],
                   help=f"Blender's cloth steps per frame, a run for each (default "
                   f"{BLENDER_QUALITY})")
    p.add_argument("--keep", help="keep the scene and the peers' results in this directory")
    add_output_flags(p)
    p.set_defaults(func=main)


def main(args) -> int:
    check_walk_seconds(args.seconds)
    for q in args.blender_quality:
        if not 1 <= q <= 200:
            raise InputError(f"--blender-quality must be within 1–200, got {q}")
    r = run(args.seconds, tuple(args.peers), {"blender_quality": args.blender_quality},
            log=log_lines(args), keep=args.keep)
    print(json.dumps(r, indent=2) if args.json else format_table(r))
    sys.stdout.flush()
    return 0
