"""The Cusick drape test, simulated: a circular specimen (30 cm across) laid on a support disc
(18 cm), left to drape under gravity until it settles; the drape coefficient is

    DC = (shadow area − disc area) / (specimen area − disc area),

the shadow being the specimen's projection on the horizontal plane (BS 5058 / ISO 9073-9). As on
the instrument, the specimen is clamped on the support disc (points on it stop, and a second
disc above keeps them from lifting).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from catwalk.cloth.analytic import DiscCollider
from catwalk.cloth.builder import Panel, build_cloth, circle, horizontal
from catwalk.cloth.model import ClothModel
from catwalk.cloth.solvers.explicit.solver import Solver
from catwalk.cloth.state import State

SPECIMEN_RADIUS = 0.15
DISC_RADIUS = 0.09
DISC_HEIGHT = 0.5
DISC_THICKNESS = 0.001


#: a node is a lobe of the shadow's outline at least this far out beyond its neighbouring
#: troughs (m) and this share of the outline's whole radial range
NODE_PROMINENCE_M = 0.003
NODE_PROMINENCE_SHARE = 0.15
NODE_SMOOTH_DEG = 9


@dataclass
class DrapeResult:
    fabric: str
    dc: float
    h: float
    seconds: float
    steps: int
    settled: bool
    model: ClothModel
    state: State
    nodes: int = 0


def shadow_area(model: ClothModel, positions: np.ndarray, pixel: float = 0.0005) -> float:
    """Area (m²) of the cloth's shadow on the horizontal (XZ) plane."""
    x = np.ascontiguousarray(positions[:, 0])
    z = np.ascontiguousarray(positions[:, 2])
    lo_x, lo_z = x.min() - pixel, z.min() - pixel
    nx = int(math.ceil((x.max() - lo_x) / pixel)) + 2
    nz = int(math.ceil((z.max() - lo_z) / pixel)) + 2
    return float(_shadow_kernel(x, z, model.triangles, lo_x, lo_z, pixel, nx, nz))


def drape_coefficient(model: ClothModel, positions: np.ndarray,
                      specimen_radius: float = SPECIMEN_RADIUS,
                      disc_radius: float = DISC_RADIUS) -> float:
    disc = math.pi * disc_radius ** 2
    spec = math.pi * specimen_radius ** 2
    return (shadow_area(model, positions) - disc) / (spec - disc)


def outline_profile(positions: np.ndarray, centre=(0.0, 0.0), bins: int = 360) -> np.ndarray:
    """The shadow's outline as its radius (m) from ``centre`` (x, z) in each of ``bins`` equal
    angles round it: the farthest point in each (empty bins filled from their neighbours)."""
    dx = positions[:, 0] - centre[0]
    dz = positions[:, 2] - centre[1]
    r = np.hypot(dx, dz)
    b = ((np.arctan2(dz, dx) + np.pi) / (2 * np.pi) * bins).astype(np.int64) % bins
    prof = np.full(bins, np.nan)
    np.fmax.at(prof, b, r)
    ok = ~np.isnan(prof)
    if not ok.any():
        return np.zeros(bins)
    idx = np.arange(bins)
    return np.interp(idx, idx[ok], prof[ok], period=bins)


def drape_nodes(hem: np.ndarray, centre=(0.0, 0.0)) -> int:
    """The number of nodes (folds hanging outward) of a draped specimen from its ``hem`` (the
    specimen's outline points): the lobes of the hem's outline seen from above
    (:func:`outline_profile`, smoothed over ``NODE_SMOOTH_DEG`` degrees) that stand out from
    the troughs on either side by ``NODE_PROMINENCE_M`` and by ``NODE_PROMINENCE_SHARE`` of the
    outline's radial range. (The hem, not every point: a point inside the outline would read
    as a dip in it.)"""
    from scipy.ndimage import (
        uniform_filter1d,  # deferred: scipy loads in ≈ 0.3 s; only this path needs it
    )  # deferred: scipy loads in ≈ 0.3 s; only this path needs it
    from scipy.signal import find_peaks  # deferred: scipy loads in ≈ 0.3 s; only this path needs it

    prof = outline_profile(hem, centre)
    n = len(prof)
    smooth = uniform_filter1d(prof, NODE_SMOOTH_DEG, mode="wrap")   # round the full turn
    spread = float(smooth.max() - smooth.min())
    if spread <= 0:
        return 0
    # three turns round, so that a lobe across the start is seen whole; count the middle one
    peaks, _ = find_peaks(np.tile(smooth, 3),
                          prominence=max(NODE_PROMINENCE_M, NODE_PROMINENCE_SHARE * spread))
    return int(np.count_nonzero((peaks >= n) & (peaks < 2 * n)))


def cusick_drape(fabric, h: float = 0.01, method: str = "ordered", max_seconds: float = 6.0,
                 settle_speed: float = 0.005, dc_tolerance: float = 0.003,
                 extra_air: float = 3.0, seed: int = 0,
                 specimen_radius: float = SPECIMEN_RADIUS,
                 disc_radius: float = DISC_RADIUS) -> DrapeResult:
    """Drape a circular specimen of ``fabric`` on the support disc until every point moves
    slower than ``settle_speed`` (m/s) or the drape coefficient stays within ``dc_tolerance``
    over half a second, or ``max_seconds`` of simulated time."""
    outline = circle(specimen_radius, max(64, int(2 * math.pi * specimen_radius / h)))
    model = build_cloth([Panel(outline, name="specimen",
                               placement=horizontal(DISC_HEIGHT + 0.003))], fabric=fabric, h=h)
    state = State.from_model(model)
    rng = np.random.default_rng(seed)  # a little roughness, so the folds choose their places
    state.positions[:, 1] += rng.uniform(0.0, 0.0005, model.n_points)
    clamped = np.hypot(state.positions[:, 0], state.positions[:, 2]) <= disc_radius
    state.positions[clamped, 1] = DISC_HEIGHT + DISC_THICKNESS
    state.pinned[clamped] = True
    # (the disc under the rest: cloth folding back under the clamp stays outside it)
    disc = DiscCollider((0.0, DISC_HEIGHT, 0.0), disc_radius, thickness=DISC_THICKNESS)
    solver = Solver(model, method, extra_air=extra_air)
    chunk = 0.05
    settled = False
    history = []
    while state.time < max_seconds - 1e-9:
        solver.step(model, state, disc, chunk)
        if state.time > 0.5 and solver.last_speed(state) < settle_speed:
            settled = True
            break
        # the ordered pass leaves a little jitter in soft cloth: also call it settled when
        # the drape coefficient has stopped changing (three checks 0.25 s apart within 0.003)
        if state.time > 1.0 and round(state.time / chunk) % 5 == 0:
            history.append(drape_coefficient(model, state.positions, specimen_radius,
                                             disc_radius))
            if len(history) >= 3 and max(history[-3:]) - min(history[-3:]) < dc_tolerance:
                settled = True
                break
    dc = drape_coefficient(model, state.positions, specimen_radius, disc_radius)
    return DrapeResult(model.fabric.id, dc, h, state.time, state.steps, settled, model, state,
                       drape_nodes(state.positions[model.boundary]))


@numba.njit(cache=True, error_model="numpy")
def _shadow_kernel(x, z, tris, lo_x, lo_z, pixel, nx, nz):
    """Area covered by the triangles' projection on the XZ plane, by rasterising them on an
    ``nx`` × ``nz`` grid of square pixels (side ``pixel``) from (lo_x, lo_z); pixel centres."""
    cover = np.zeros((nz, nx), dtype=np.uint8)
    for t in range(tris.shape[0]):
        a = tris[t, 0]
        b = tris[t, 1]
        c = tris[t, 2]
        ax = (x[a] - lo_x) / pixel
        az = (z[a] - lo_z) / pixel
        bx = (x[b] - lo_x) / pixel
        bz = (z[b] - lo_z) / pixel
        cx = (x[c] - lo_x) / pixel
        cz = (z[c] - lo_z) / pixel
        area = (bx - ax) * (cz - az) - (bz - az) * (cx - ax)
        if area == 0.0:
            continue
        i0 = max(int(np.floor(min(ax, bx, cx))), 0)
        i1 = min(int(np.ceil(max(ax, bx, cx))), nx - 1)
        j0 = max(int(np.floor(min(az, bz, cz))), 0)
        j1 = min(int(np.ceil(max(az, bz, cz))), nz - 1)
        for j in range(j0, j1 + 1):
            pz = j + 0.5
            for i in range(i0, i1 + 1):
                px = i + 0.5
                w0 = (bx - px) * (cz - pz) - (bz - pz) * (cx - px)
                w1 = (cx - px) * (az - pz) - (cz - pz) * (ax - px)
                w2 = (ax - px) * (bz - pz) - (az - pz) * (bx - px)
                if area > 0:
                    if w0 >= 0 and w1 >= 0 and w2 >= 0:
                        cover[j, i] = 1
                elif w0 <= 0 and w1 <= 0 and w2 <= 0:
                    cover[j, i] = 1
    total = 0
    for j in range(nz):
        for i in range(nx):
            total += cover[j, i]
    return total * pixel * pixel
