"""Rate limits: requests counted under a name — a shop's publishable key, a shopper on a shop
— in a window of so many seconds that opens with the first of them, and refused past a limit
until the window closes (then a new one opens with the next request).

With a Redis broker (``CATWALK_BROKER_URL=redis://…``) the counts are kept in Redis, so every
API process shares them (several API hosts behind a load balancer count together); otherwise
(the embedded default: one API process) in this process's memory. A count that cannot be taken
(Redis away) lets the request through: a limit is a brake, not a lock, and the broker's own
outage is answered elsewhere.
"""

from __future__ import annotations

import json
import logging
import threading
import time

from catwalk.config import Config

log = logging.getLogger("catwalk.api")

#: names kept in memory before the ended windows are swept out
_SWEEP_AT = 10_000


class _Memory:
    def __init__(self):
        self.counts: dict[str, tuple[int, float]] = {}   # name → (count, window closes)
        self.lock = threading.Lock()

    async def incr(self, name: str, seconds: float) -> tuple[int, float]:
        with self.lock:
            now = time.monotonic()
            if len(self.counts) > _SWEEP_AT:
                self.counts = {k: v for k, v in self.counts.items() if v[1] > now}
            count, closes = self.counts.get(name, (0, 0.0))
            if closes <= now:
                count, closes = 0, now + seconds
            self.counts[name] = (count + 1, closes)
            return count + 1, closes - now


class _Redis:
    def __init__(self, url: str):
        import redis.asyncio  # deferred: only a Redis broker's API process counts there

        self.client = redis.asyncio.Redis.from_url(url, socket_timeout=1.0,
                                                   socket_connect_timeout=1.0)

    async def incr(self, name: str, seconds: float) -> tuple[int, float]:
        key = f"catwalk:rate:{name}"
        async with self.client.pipeline(transaction=True) as pipe:
            pipe.incr(key)
            pipe.expire(key, int(seconds), nx=True)
            pipe.pttl(key)
            count, _, left_ms = await pipe.execute()
        return int(count), max(0, int(left_ms)) / 1000


class RateLimits:
    """``await limits.hit(name, limit, seconds)``: count one request under ``name`` in its
    window of ``seconds``; the seconds until the window closes when the count is over
    ``limit``, else None."""

    def __init__(self, config: Config):
        url = config.broker_url or ""
        self.store = _Redis(url) if url.startswith(("redis://", "rediss://")) else _Memory()

    async def hit(self, name: str, limit: int, seconds: float) -> float | None:
        try:
            count, left = await self.store.incr(f"{name}:{int(seconds)}", seconds)
        except Exception as exc:   # the store away: the request goes through (and is logged)
            log.warning(json.dumps({"event": "rate_limit_unavailable",
                                    "error": type(exc).__name__}))
            return None
        return None if count <= limit else max(1.0, left)
