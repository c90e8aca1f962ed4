"""How a shopper's body is made: from measurements or from a scan, in the API's own process
pool (its records: :mod:`catwalk.service.bodies`).

The heavy part (fitting the MakeHuman body: 1–3 s of CPU; registering it to a scan: ≈ 10 s for
300 k faces) runs in a process
of the API's own pool (:class:`BodyMaker`), never on the API's event loop, and writes
``bodies/<id>/body.glb``; the database row is added only once the files are there. A scan
becomes the MakeHuman template registered to the scan's surface (``"fit": "surface"``,
:mod:`catwalk.body.from_scan`): the shopper's own shape walks.

A scan and its measurements are personal data: they are never logged (log lines carry the
body's id and the outcome only), never listed, and :func:`catwalk.service.bodies.delete`
removes the scan, the body, every try-on made from it and every result no other body shares.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import multiprocessing
import shutil
from pathlib import Path

from catwalk.body.from_scan import body_from_scan
from catwalk.body.make import make_body
from catwalk.body.rig import measured_base_body
from catwalk.body.types import MEASUREMENTS as SHOWN  # shown for a body, in this order
from catwalk.exchange.gltf import glb_bytes
from catwalk.exchange.scan import load_scan
from catwalk.service.children import die_with_parent
from catwalk.service.store.files import Storage

MEASUREMENT_FIELDS = ("height", "bust", "waist", "hips")


def shown(measured: dict) -> dict:
    """The measurements shown for a body, metres rounded to 0.1 mm."""
    return {k: round(float(measured[k]), 4) for k in SHOWN
            if isinstance(measured.get(k), (int, float))}


def _write_body(body, out: Path) -> None:
    """The body's .glb, written whole, readable by the service's user only."""
    Storage(out.parent).write(out, glb_bytes(body))


def make_from_measurements(out: str, sex: str, values: dict) -> dict:
    """(In a pool process.) Make the body, write it to ``out``; its measured girths."""
    body = make_body(sex=sex, **{k: values[k] for k in MEASUREMENT_FIELDS})
    _write_body(body, Path(out))
    return {"model_measurements": shown(body.meta["measured"])}


def make_from_scan(scan_path: str, out: str, sex: str | None) -> dict:
    """(In a pool process.) Register the template to the scan, write the body."""
    scan = load_scan(scan_path, name="scan")
    body, report = body_from_scan(scan, sex=sex)
    _write_body(body, Path(out))
    both = report["measurements"]
    return {"sex": report["sex"], "sex_inferred": sex is None,
            "measurements": shown({k: v["scan"] for k, v in both.items()}),
            "model_measurements": shown({k: v["body"] for k, v in both.items()}),
            "scan": {"units": scan.units, "up_axis": scan.up, "forward_axis": scan.forward,
                     "vertices": int(len(scan.vertices)), "faces": int(len(scan.faces)),
                     "holes": scan.holes,
                     "surface_distance_mm": {"scan_to_body": report["scan_to_body_mm"],
                                             "body_to_scan": report["body_to_scan_mm"]}}}


def _warm() -> bool:
    measured_base_body(0.0)
    return True


class BodyMaker:
    """The API's pool of body-making processes (spawned, so they hold no API state)."""

    def __init__(self, processes: int = 1):
        self.processes = max(1, processes)
        self._pool: concurrent.futures.ProcessPoolExecutor | None = None

    def _get(self) -> concurrent.futures.ProcessPoolExecutor:
        if self._pool is None:
            self._pool = concurrent.futures.ProcessPoolExecutor(
                self.processes, mp_context=multiprocessing.get_context("spawn"),
                initializer=die_with_parent)   # gone with the API, even if it is killed
        return self._pool

    def warm(self) -> None:
        """Load the body kernels in the pool now (in the background)."""
        self._get().submit(_warm)

    async def run(self, fn, *args, timeout: float):
        """``fn(*args)`` in a pool process. Over ``timeout``: :class:`TimeoutError`, and the
        process making it is stopped (so it writes nothing afterwards) — other requests that
        were waiting in the pool are sent to a fresh one, not failed."""
        loop = asyncio.get_running_loop()
        deadline = loop.time() + timeout
        for _ in range(3):
            pool = self._get()
            fut = pool.submit(fn, *args)
            try:
                return await asyncio.wait_for(asyncio.wrap_future(fut, loop=loop),
                                              max(0.0, deadline - loop.time()))
            except TimeoutError:
                if not fut.cancel():        # it was running: stop the process running it
                    self._reset(pool)
                raise
            except (concurrent.futures.process.BrokenProcessPool,
                    concurrent.futures.CancelledError):
                self._reset(pool)          # another request's reset, or a crash: try again
            except asyncio.CancelledError:
                # the pool's future cancelled by another request's reset reaches this await as
                # asyncio's CancelledError: try again, unless this request itself is cancelled
                task = asyncio.current_task()
                if not fut.cancelled() or (task is not None and task.cancelling()):
                    raise
        raise TimeoutError("the body pool kept failing")

    def _reset(self, pool) -> None:
        """Stop ``pool``'s processes now; the next request gets a fresh pool."""
        if self._pool is pool:
            self._pool = None
        for proc in list(getattr(pool, "_processes", {}).values()):
            proc.terminate()
        pool.shutdown(wait=False, cancel_futures=True)

    def close(self) -> None:
        """Stop the pool's processes (the API is stopping)."""
        if self._pool is not None:
            self._reset(self._pool)


def remove_tree(path: Path) -> None:
    shutil.rmtree(path, ignore_errors=True)
