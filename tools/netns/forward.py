"""A tiny TCP forwarder: ``forward.py LISTEN_ADDR:PORT TARGET_ADDR:PORT [...]``.

Used by ``two_hosts.sh`` when socat is not installed: it listens only on the given addresses
(the main side of the namespaces' veths) and copies bytes both ways to the target (Redis or
PostgreSQL on 127.0.0.1), so the servers' own configuration stays as it is. Runs until killed.
"""

from __future__ import annotations

import asyncio
import contextlib
import sys


async def _pipe(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
    try:
        while data := await reader.read(65536):
            writer.write(data)
            await writer.drain()
    except (ConnectionError, OSError):
        pass
    finally:
        with contextlib.suppress(Exception):
            writer.close()


def _handler(host: str, port: int):
    async def handle(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            up_reader, up_writer = await asyncio.open_connection(host, port)
        except OSError:
            writer.close()
            return
        await asyncio.gather(_pipe(reader, up_writer), _pipe(up_reader, writer))

    return handle


def _split(spec: str) -> tuple[str, int]:
    host, _, port = spec.rpartition(":")
    return host, int(port)


async def main(pairs: list[tuple[str, str]]) -> None:
    servers = []
    for listen, target in pairs:
        lh, lp = _split(listen)
        th, tp = _split(target)
        servers.append(await asyncio.start_server(_handler(th, tp), lh, lp, reuse_address=True))
        print(f"forward: {listen} -> {target}", flush=True)
    await asyncio.gather(*(s.serve_forever() for s in servers))


if __name__ == "__main__":
    args = sys.argv[1:]
    if not args or len(args) % 2:
        sys.exit("usage: forward.py LISTEN:PORT TARGET:PORT [LISTEN:PORT TARGET:PORT ...]")
    asyncio.run(main(list(zip(args[::2], args[1::2], strict=True))))
