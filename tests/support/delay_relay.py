#!/usr/bin/env python3
"""A TCP relay that delays every byte by half a round trip in each direction: a stand-in for netem's delay where
the kernel has no netem. Workers connect to LISTEN; each connection is forwarded to TARGET (the coordinator's job
port). Bytes keep their order: each chunk read is written on the other side once RTT/2 has passed since it was
read, so a request and its answer cross the relay in RTT plus the peers' own time. Bandwidth is not limited and
nothing is lost, reordered or duplicated. An end of stream is passed on after the same delay (half-close); a
connection that fails on one side is closed on both.

    python3 tests/support/delay_relay.py --listen 127.0.0.1:0 --target 127.0.0.1:5555 --rtt-ms 50

Prints "listening HOST:PORT" on stdout once it accepts connections (port 0: a free port), and on SIGINT or
SIGTERM closes every connection and prints what it carried: "relayed CONNECTIONS connections, UP bytes to the
target, DOWN bytes from it" (down: what the target sent, i.e. the coordinator's outgoing bytes).
"""
import argparse
import asyncio
import signal
import sys

CHUNK = 1 << 16


class Totals:
    """What the relay carried, for the line printed at the end."""

    def __init__(self):
        self.connections = 0
        self.up = 0  # client -> target
        self.down = 0  # target -> client


async def pump(reader, writer, delay_s, count):
    """Copies reader to writer, each chunk delayed by delay_s after it was read; ends after the end of stream."""
    loop = asyncio.get_running_loop()
    queue = asyncio.Queue()

    async def read():
        try:
            while True:
                data = await reader.read(CHUNK)
                await queue.put((loop.time() + delay_s, data))
                if not data:
                    return
        except (ConnectionError, OSError):
            await queue.put((loop.time() + delay_s, b""))

    async def write():
        while True:
            due, data = await queue.get()
            wait = due - loop.time()
            if wait > 0:
                await asyncio.sleep(wait)
            if not data:
                if writer.can_write_eof():
                    writer.write_eof()
                return
            writer.write(data)
            count(len(data))
            await writer.drain()

    reading = asyncio.ensure_future(read())
    try:
        await write()
    finally:
        reading.cancel()


async def serve(args, totals, stop):
    delay_s = args.rtt_ms / 2000.0
    target_host, target_port = args.target.rsplit(":", 1)
    connections = set()

    async def handle(client_reader, client_writer):
        totals.connections += 1
        try:
            target_reader, target_writer = await asyncio.open_connection(target_host, int(target_port))
        except OSError as e:
            print(f"delay_relay: cannot reach {args.target}: {e}", file=sys.stderr)
            client_writer.close()
            return
        task = asyncio.current_task()
        connections.add(task)

        def up(n):
            totals.up += n

        def down(n):
            totals.down += n

        pumps = [asyncio.ensure_future(pump(client_reader, target_writer, delay_s, up)),
                 asyncio.ensure_future(pump(target_reader, client_writer, delay_s, down))]
        try:
            # both directions to their end of stream, or the first failure of either
            done, pending = await asyncio.wait(pumps, return_when=asyncio.FIRST_EXCEPTION)
            for p in pending:
                p.cancel()
        except asyncio.CancelledError:
            for p in pumps:
                p.cancel()
        finally:
            for w in (client_writer, target_writer):
                w.close()
            for w in (client_writer, target_writer):
                try:
                    await w.wait_closed()
                except (ConnectionError, OSError, asyncio.CancelledError):
                    pass
            connections.discard(task)

    host, port = args.listen.rsplit(":", 1)
    server = await asyncio.start_server(handle, host, int(port))
    bound = server.sockets[0].getsockname()
    print(f"listening {bound[0]}:{bound[1]}", flush=True)
    await stop.wait()
    server.close()
    await server.wait_closed()
    for task in list(connections):
        task.cancel()
    if connections:
        await asyncio.wait(list(connections), timeout=2)


def main():
    parser = argparse.ArgumentParser(description="A TCP relay that delays each direction by RTT/2.")
    parser.add_argument("--listen", required=True, help="HOST:PORT to accept connections on (port 0: any free)")
    parser.add_argument("--target", required=True, help="HOST:PORT to forward each connection to")
    parser.add_argument("--rtt-ms", type=float, required=True, help="round-trip time to add, in milliseconds")
    args = parser.parse_args()
    if args.rtt_ms < 0:
        parser.error("--rtt-ms must be at least 0")

    totals = Totals()

    async def run():
        stop = asyncio.Event()
        loop = asyncio.get_running_loop()
        for s in (signal.SIGINT, signal.SIGTERM):
            loop.add_signal_handler(s, stop.set)
        await serve(args, totals, stop)

    try:
        asyncio.run(run())
    except OSError as e:
        print(f"delay_relay: {e}", file=sys.stderr)
        return 1
    print(f"relayed {totals.connections} connections, {totals.up} bytes to the target, {totals.down} bytes from it",
          flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
