"""Wall-clock time of each collider pass in `catwalk bench paper`'s hybrid walk (the paper's
dress, 2 s), walked with each of the given thread counts in turn, alternating:

    .venv/bin/python tools/profile/passes.py [--threads 1 2] [--repeat 2] [--first]

Prints, per walk, each pass's ms a recorded frame (the blend into the walk left out), calls
a frame and points a call: the edge fallback (``all-edge``: the points the maps leave, every
part) and the again pass (``all-again``: the points a limb pushed, every part), the limbs'
pass (``limbs``), the frame kept's look again (``recheck-all``, or ``recheck-limbs`` without
the edge fallback) and the image pass (``image``), and the walk's own ms_per_frame split;
``--first`` splits each pass's figures between a frame's first response (``@first``: the
points' clearances over the frame's swept boxes start again there) and the others. The edge
fallback is told from the again pass by its mask (the hybrid collider's ``_edge``).
docs/collide.md "Both cores" quotes it. A development tool: it wraps the passes' ``run``
methods to time them; the product does not import it."""

import argparse
import collections
import time

from catwalk.bench.paper import paper_dressed
from catwalk.collide import image_pass as IP
from catwalk.collide import object_pass as OP
from catwalk.simulate.walking import blend_frame_count, walk


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--first", action="store_true",
                    help="split each pass between a frame's first response and the others")
    args = ap.parse_args()
    body, motion, settings, dressed = paper_dressed(2.0)
    acc = collections.defaultdict(lambda: [0, 0.0, 0])
    o_run, i_run = OP.ObjectPass.run, IP.ImagePass.run
    first_of = {}   # the frame → its first response's time
    # the collider's frames before this one blend the rest pose into the walk: not recorded,
    # and left out as the walk's own ms_per_frame leaves them
    recorded = blend_frame_count(settings, motion.fps) + 1

    def at(col, s) -> str | None:
        if col._frame < recorded:
            return None
        first = first_of.setdefault(col._frame, s.alpha) == s.alpha
        return "@first" if args.first and first else ""

    def orun(self, col, s, held, active, pts, only, recheck=False):
        if not active[0]:
            key = "limbs"
        else:
            key = "all-edge" if len(only) and only is col._edge else "all-again"
        when = at(col, s)
        t = time.perf_counter()
        r = o_run(self, col, s, held, active, pts, only, recheck)
        if when is None:
            return r
        part = "all" if active[0] else "limbs"
        a = acc[(f"recheck-{part}" if recheck else key) + when]
        a[0] += 1
        a[1] += time.perf_counter() - t
        a[2] += int(only.sum()) if len(only) else len(s.pos)
        return r

    def irun(self, col, s, *rest):
        t = time.perf_counter()
        r = i_run(self, col, s, *rest)
        when = at(col, s)
        if when is None:
            return r
        a = acc["image" + when]
        a[0] += 1
        a[1] += time.perf_counter() - t
        a[2] += len(s.pos)
        return r

    OP.ObjectPass.run, IP.ImagePass.run = orun, irun
    walk(body, motion, dressed, settings.with_(collider="hybrid"))   # compiled, warm
    n = motion.frames
    for _ in range(args.repeat):
        for threads in args.threads:
            acc.clear()
            first_of.clear()
            w = walk(body, motion, dressed, settings.with_(collider="hybrid", threads=threads))
            parts = "; ".join(f"{k} {v[1] / n * 1e3:.2f} ms, {v[0] / n:.1f} calls, "
                              f"{v[2] / max(v[0], 1):.0f} points a call"
                              for k, v in sorted(acc.items()))
            print(f"threads {threads}: {parts} | ms_per_frame {w.stats['ms_per_frame']}")


if __name__ == "__main__":
    main()
