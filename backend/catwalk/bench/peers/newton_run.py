"""Newton peer for ``catwalk bench peers``: the garment on the walking body, simulated with
NVIDIA Newton's VBD cloth solver on the CPU (through Warp).

STANDALONE: imports only numpy, warp, newton and the standard library (never catwalk), and is
run with the Newton venv's interpreter (``newton_setup.sh`` makes it)::

    <venv>/bin/python newton_run.py SCENE.npz OUT.npz [--substeps N] [--iterations K]

Solver choice: ``newton.solvers.SolverVBD``. Newton's cloth examples that put cloth against a
*body* use either Style3D (``example_cloth_style3d`` / ``example_cloth_h1``: a garment on a
mannequin / robot) or VBD (``example_cloth_twist``, ``_poker_cards``, ``_rollers``,
``_franka``).  Style3D needs the garment's 2-D sewing panels (UV rest shape) and collides only
with *rigid* shapes; our scene has a 3-D rest shape and a skinned (every vertex moving) body.
VBD is the solver whose own examples drive *kinematic particles* (``example_cloth_twist``
writes prescribed positions into ``particle_q`` of non-ACTIVE particles every substep) and
resolve cloth contact against them with its vertex-triangle + edge-edge contact
("self contact", with divide-and-truncate penetration-free truncation) -- Newton issue #3260
says this hand-written per-substep kinematic update is how everyone drives deformables today.

The deforming body: the body mesh is added as a second cloth mesh whose particles have zero
mass and no ACTIVE flag (VBD never moves them; their triangles have zero stiffness). Every
substep a Warp kernel writes the body linearly interpolated between the two frames into
``particle_q`` (and the frame's finite-difference velocity into ``particle_qd``), and VBD's
self-contact then handles garment-vertex/body-triangle, body-vertex/garment-triangle and
garment-edge/body-edge pairs as well as the garment's own self-contact. Body-body pairs are
excluded: VBD drops a pair closer than a radius in the REST positions, and the body's rest
positions are all put at one far point (see ``BODY_REST_POINT``); the simulated states get the
real body every substep. The body has no edges unless ``--body-edges`` (garment-body edge-edge
contact, slower).

Material mapping (scene -> Newton units; Newton's VBD membrane is a stable Neo-Hookean with
Lame parameters tri_ke = mu, tri_ka = lambda, per unit rest area, i.e. N/m for a membrane):
- mu = G (shear per unit width, N/m); lambda = max(E - 2G, 0), so that lambda + 2 mu = E: the
  tensile stiffness of one fibre direction with the other held (our spring grid has no
  Poisson coupling beyond the shear diagonals). The free-edge uniaxial modulus is then
  4G(E-G)/E (isotropic Newton cannot give both E and G when E > 4G).
- Bending: Newton's hinge energy is 1/2 * k * L * (theta - theta0)^2; the continuum 1/2 B kappa^2
  over the hinge's third of the two triangles' area with kappa ~ theta / h gives
  k = 3 B L / (A1 + A2) per edge (set per edge after the builder made the edges).
- Mass: per point from ``cloth_mass`` (written into the builder's particle masses).
- Damping: stiffness-proportional, tri_kd = 0.01 * mu * dt_sub, edge_kd = 0.01 * k * dt_sub.
- Contact: margin (interaction distance) = thickness, detection gap = thickness, penalty
  stiffness soft_contact_ke (default 1e4 N/m, log-barrier under margin/2), friction
  soft_contact_mu = scene friction. Known limit: VBD computes friction from within-step
  displacements, and a kinematic (inactive) particle has none, so the body counts as still
  inside a substep for friction.
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import traceback  # noqa: E402
from dataclasses import dataclass  # noqa: E402

import numpy as np  # noqa: E402

DEFAULT_SUBSTEPS = 10
DEFAULT_ITERATIONS = 10
CONTACT_KE = 1.0e4
BODY_REST_POINT = (100.0, 100.0, 100.0)


def _write(out_path, positions, frame_seconds, info):
    np.savez(
        out_path,
        positions=np.asarray(positions, dtype=np.float32),
        frame_seconds=np.asarray(frame_seconds, dtype=np.float64),
        info=np.array(json.dumps(info)),
    )


def _bend_stiffness(edge_indices, x, tris, bend):
    """k = 3 B L / (A1 + A2) per Newton bending edge (o0, o1, v0, v1); 0 on boundary edges."""
    e = np.asarray(edge_indices, dtype=np.int64)
    k = np.zeros(len(e))
    inner = (e[:, 0] >= 0) & (e[:, 1] >= 0)
    o0, o1, a, b = (e[inner, i] for i in range(4))
    L = np.linalg.norm(x[b] - x[a], axis=1)
    A1 = 0.5 * np.linalg.norm(np.cross(x[a] - x[o0], x[b] - x[o0]), axis=1)
    A2 = 0.5 * np.linalg.norm(np.cross(x[a] - x[o1], x[b] - x[o1]), axis=1)
    k[inner] = 3.0 * bend * L / np.maximum(A1 + A2, 1e-12)
    return k


@dataclass
class _Scene:
    """The scene as read from SCENE.npz, plus the run's frame count and substep."""

    xc: np.ndarray  # garment initial positions (P, 3), float64
    vc: np.ndarray  # garment initial velocities (P, 3)
    tc: np.ndarray  # garment triangles
    mc: np.ndarray  # per-point garment mass (kg)
    tb: np.ndarray  # body faces
    frames: np.ndarray  # body vertex positions per frame (F, V, 3), float32
    fps: float
    E: float  # stretch (N/m)
    G: float  # shear (N/m)
    B: float  # bend (N m)
    mu_f: float  # friction
    thick: float  # thickness (m)
    n_frames: int  # frames to simulate (including frame 0)
    S: int  # substeps per frame
    dt: float  # substep (s)

    @property
    def P(self) -> int:
        return len(self.xc)

    @property
    def V(self) -> int:
        return self.frames.shape[1]

    @property
    def lam(self) -> float:
        return max(self.E - 2.0 * self.G, 0.0)


def _parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene")
    ap.add_argument("out")
    ap.add_argument("--substeps", type=int, default=DEFAULT_SUBSTEPS)
    ap.add_argument("--iterations", type=int, default=DEFAULT_ITERATIONS)
    ap.add_argument("--contact-ke", type=float, default=CONTACT_KE)
    ap.add_argument("--body-edges", action="store_true",
                    help="add the body's edges too (garment-body edge-edge contact; slower)")
    ap.add_argument("--frames", type=int, default=0, help="simulate only this many frames (0: all)")
    return ap.parse_args(argv)


def _read_scene(args) -> _Scene:
    sc = np.load(args.scene)
    frames = np.asarray(sc["body_frames"], dtype=np.float32)
    fps = float(sc["fps"])
    n_frames = frames.shape[0] if args.frames <= 0 else min(args.frames, frames.shape[0])
    return _Scene(
        xc=np.asarray(sc["cloth_positions"], dtype=np.float64),
        vc=np.asarray(sc["cloth_velocities"], dtype=np.float64),
        tc=np.asarray(sc["cloth_triangles"], dtype=np.int64),
        mc=np.asarray(sc["cloth_mass"], dtype=np.float64),
        tb=np.asarray(sc["body_faces"], dtype=np.int64),
        frames=frames, fps=fps,
        E=float(sc["stretch"]), G=float(sc["shear"]), B=float(sc["bend"]),
        mu_f=float(sc["friction"]), thick=float(sc["thickness"]),
        n_frames=n_frames, S=args.substeps, dt=1.0 / fps / args.substeps,
    )


def _material_info(sc: _Scene, contact_ke: float) -> dict:
    """The scene -> Newton material mapping, as recorded in OUT.npz's info."""
    xc, tc = sc.xc, sc.tc
    area = 0.5 * np.linalg.norm(
        np.cross(xc[tc[:, 1]] - xc[tc[:, 0]], xc[tc[:, 2]] - xc[tc[:, 0]]), axis=1)
    return {
        "tri_ke(mu)=G": sc.G, "tri_ka(lambda)=max(E-2G,0)": sc.lam, "tri_kd": 0.01 * sc.G * sc.dt,
        "edge_ke": "3*B*L/(A1+A2) per edge", "B": sc.B, "E": sc.E,
        "density_kg_m2(mean, masses set per point)": float(sc.mc.sum() / area.sum()),
        "soft_contact_ke": contact_ke, "soft_contact_mu": sc.mu_f,
        "self_contact_margin=thickness": sc.thick, "self_contact_gap=thickness": sc.thick,
    }


def _add_body(builder, sc: _Scene, body_edges: bool) -> None:
    """Add the body at frame 0 after the garment: zero-stiffness triangles, edges if asked."""
    import warp as wp

    P, V, tb, thick = sc.P, sc.V, sc.tb, sc.thick
    body0 = sc.frames[0].astype(np.float64)
    if body_edges:
        builder.add_cloth_mesh(
            pos=wp.vec3(0.0, 0.0, 0.0), rot=wp.quat_identity(), scale=1.0,
            vel=wp.vec3(0.0, 0.0, 0.0), vertices=[wp.vec3(*p) for p in body0],
            indices=tb.reshape(-1).tolist(), density=0.0, tri_ke=0.0, tri_ka=0.0, tri_kd=0.0,
            edge_ke=0.0, edge_kd=0.0, particle_radius=thick, label="body",
        )
    else:
        # particles + triangles only: no body edges, so no body-body / garment-body edge-edge
        # pairs (VBD's contact kernels launch 4 threads per particle or edge, whichever is more)
        builder.add_particles(body0.tolist(), [(0.0, 0.0, 0.0)] * V,
                              mass=[0.0] * V, radius=[thick] * V)
        zeros = [0.0] * len(tb)
        builder.add_triangles(P + tb[:, 0], P + tb[:, 1], P + tb[:, 2], tri_ke=zeros,
                              tri_ka=zeros, tri_kd=zeros, tri_drag=zeros, tri_lift=zeros)


def _build_model(sc: _Scene, args, material: dict):
    """The Newton model: the garment, then the kinematic body (see the module docstring)."""
    import newton
    import warp as wp

    P, V, G, dt = sc.P, sc.V, sc.G, sc.dt
    builder = newton.ModelBuilder(up_axis=newton.Axis.Y, gravity=(0.0, -9.81, 0.0))
    builder.add_cloth_mesh(
        pos=wp.vec3(0.0, 0.0, 0.0), rot=wp.quat_identity(), scale=1.0,
        vel=wp.vec3(0.0, 0.0, 0.0), vertices=[wp.vec3(*p) for p in sc.xc],
        indices=sc.tc.reshape(-1).tolist(), density=0.0, tri_ke=G, tri_ka=sc.lam,
        tri_kd=0.01 * G * dt, edge_ke=0.0, edge_kd=0.0, particle_radius=sc.thick,
        label="garment",
    )
    n_cloth_edges = len(builder.edge_indices)
    _add_body(builder, sc, args.body_edges)
    # per-point garment mass; body particles: zero mass, not ACTIVE (kinematic)
    for i in range(P):
        builder.particle_mass[i] = float(sc.mc[i])
        builder.particle_qd[i] = wp.vec3(*sc.vc[i])
    active = int(newton.ParticleFlags.ACTIVE)
    for i in range(P, P + V):
        builder.particle_mass[i] = 0.0
        builder.particle_flags[i] = int(builder.particle_flags[i]) & ~active
    kb = _bend_stiffness(builder.edge_indices[:n_cloth_edges], sc.xc, sc.tc, sc.B)
    for j in range(n_cloth_edges):
        builder.edge_bending_properties[j] = (float(kb[j]), float(0.01 * kb[j] * dt))
    material["edge_ke_mean"] = float(kb[kb > 0].mean()) if (kb > 0).any() else 0.0
    builder.color(include_bending=True)
    model = builder.finalize(device="cpu")
    # Body-body pairs: VBD filters out candidate pairs whose separation in the REST positions
    # (model.particle_q, read at every detection) is under particle_rest_shape_contact_exclusion
    # _radius. Collapsing the body's rest positions to one far point makes every body-body
    # pair's rest separation 0 (excluded) and every garment-body one ~170 m (kept); the
    # simulated states get the real body every substep. Garment-garment pairs keep their rest
    # separations, and a 0.1 mm exclusion radius leaves them alone.
    q_rest = model.particle_q.numpy()
    q_rest[P:] = BODY_REST_POINT
    model.particle_q.assign(q_rest)
    model.soft_contact_ke = args.contact_ke
    model.soft_contact_kd = 0.0
    model.soft_contact_mu = sc.mu_f
    return model


def _make_solver(model, sc: _Scene, iterations: int):
    import newton

    return newton.solvers.SolverVBD(
        model,
        iterations=iterations,
        particle_enable_self_contact=True,
        particle_self_contact_margin=sc.thick,
        particle_self_contact_gap=sc.thick,
        particle_vertex_contact_buffer_size=32,
        particle_edge_contact_buffer_size=64,
        particle_rest_shape_contact_exclusion_radius=1.0e-4,
    )


def _make_advance(solver, sc: _Scene):
    """advance(states, f): one frame (f-1 -> f), the body written into the states every substep."""
    import warp as wp

    P, V, S, dt, fps, frames = sc.P, sc.V, sc.S, sc.dt, sc.fps, sc.frames
    body_prev = wp.zeros(V, dtype=wp.vec3, device="cpu")
    body_next = wp.zeros(V, dtype=wp.vec3, device="cpu")

    @wp.kernel
    def set_body(prev: wp.array(dtype=wp.vec3), nxt: wp.array(dtype=wp.vec3), a: float,
                 fps: float, offset: int, q0: wp.array(dtype=wp.vec3),
                 q1: wp.array(dtype=wp.vec3), qd0: wp.array(dtype=wp.vec3),
                 qd1: wp.array(dtype=wp.vec3)):
        i = wp.tid()
        p = wp.lerp(prev[i], nxt[i], a)
        v = (nxt[i] - prev[i]) * fps
        q0[offset + i] = p
        q1[offset + i] = p
        qd0[offset + i] = v
        qd1[offset + i] = v

    def set_body_at(states, a):
        wp.launch(set_body, dim=V,
                  inputs=[body_prev, body_next, a, fps, P,
                          states[0].particle_q, states[1].particle_q,
                          states[0].particle_qd, states[1].particle_qd], device="cpu")

    def advance(states, f):
        """Advance one frame (f-1 -> f); states = [s0, s1] swapped in place."""
        body_prev.assign(frames[f - 1])
        body_next.assign(frames[f])
        # the body at the frame's start (the states may hold the collapsed rest body), then a
        # full BVH rebuild once a frame (as example_cloth_twist does), refits in between
        set_body_at(states, 0.0)
        solver.rebuild_bvh(states[0])
        for s in range(S):
            set_body_at(states, (s + 1) / S)
            states[0].clear_forces()
            solver.step(states[0], states[1], None, None, dt)
            states[0], states[1] = states[1], states[0]

    return advance


def _run_frames(model, advance, sc: _Scene, positions: list, frame_seconds: list,
                info: dict) -> None:
    """Warm up (compile), then the timed frames: append to positions / frame_seconds."""
    # warm-up (Warp compiles kernels at first launch): one throwaway frame, then reset
    t0 = time.perf_counter()
    warm = [model.state(), model.state()]
    advance(warm, 1)
    info["compile_seconds"] = time.perf_counter() - t0
    del warm

    states = [model.state(), model.state()]
    cpu0 = time.process_time()
    wall0 = time.perf_counter()
    for f in range(1, sc.n_frames):
        t = time.perf_counter()
        advance(states, f)
        q = states[0].particle_q.numpy()[:sc.P]  # synchronises (CPU launches are synchronous)
        frame_seconds.append(time.perf_counter() - t)
        positions.append(q.copy())
        if not np.isfinite(q).all():
            raise FloatingPointError(f"non-finite garment positions at frame {f}")
    wall = time.perf_counter() - wall0
    info["cpu_over_wall"] = (time.process_time() - cpu0) / max(wall, 1e-9)
    info["ms_per_frame_mean"] = 1e3 * float(np.mean(frame_seconds)) if frame_seconds else None
    info["frames"] = len(positions)


def main(argv=None) -> int:
    args = _parse_args(argv)
    info: dict = {"solver": "newton.solvers.SolverVBD", "substeps": args.substeps,
                  "iterations": args.iterations, "device": "cpu",
                  "body_edges": bool(args.body_edges), "errors": []}
    positions: list = []
    frame_seconds: list = []
    t_start = time.perf_counter()
    try:
        import newton
        import warp as wp

        info["newton_version"] = getattr(newton, "__version__", "?")
        info["warp_version"] = wp.config.version
        wp.config.quiet = True
        wp.init()
        wp.set_device("cpu")

        sc = _read_scene(args)
        positions.append(sc.xc.astype(np.float32))
        info["material"] = _material_info(sc, args.contact_ke)
        model = _build_model(sc, args, info["material"])
        solver = _make_solver(model, sc, args.iterations)
        info["setup_seconds"] = time.perf_counter() - t_start

        _run_frames(model, _make_advance(solver, sc), sc, positions, frame_seconds, info)
        _write(args.out, positions, frame_seconds, info)
        return 0
    except Exception as exc:  # noqa: BLE001 -- report whatever failed in OUT.npz
        info["errors"].append(f"{type(exc).__name__}: {exc}")
        info["traceback"] = traceback.format_exc()
        info["frames"] = len(positions)
        try:
            _write(args.out, positions if positions else np.zeros((0, 0, 3)), frame_seconds, info)
        finally:
            print(info["traceback"], file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
