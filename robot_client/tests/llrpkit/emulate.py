"""Runs llrpkit's LLRP reader emulator for the robot's tests, with the tag population they give.

    emulate.py '{"tags": [{"epc": "E200...", "antennas": [1], "rssi_dbm": -45}], "reads_per_sec": 400}'

Prints `port N` once the emulator listens on 127.0.0.1, then obeys one command per line on stdin,
answering each with one line:

    disconnect A [AFTER_MS]   pull antenna A's cable (now, or AFTER_MS later): `ok`
    connect A                 plug it back: `ok`
    drop MESSAGE              swallow the next MESSAGE (an llrpkit message class name): `ok`
    keepalive                 send a KEEPALIVE and wait up to 2 s for its ACK: `ack` or `no ack`
    acks                      how many KEEPALIVE_ACKs arrived: a number
    active                    whether a ROSpec runs (an inventory round): `yes` or `no`

It exits when stdin closes. Only llrpkit speaks LLRP here; this file only drives it.
"""

import asyncio
import json
import sys

from llrpkit.emulator import EmulatedTag, LLRPEmulator
from llrpkit.protocol import messages


async def main() -> None:
    config = json.loads(sys.argv[1])
    tags = [
        EmulatedTag(
            epc=bytes.fromhex(t["epc"]),
            antennas=tuple(t.get("antennas", [1])),
            rssi_dbm=float(t["rssi_dbm"]),
            weight=float(t.get("weight", 1.0)),
        )
        for t in config["tags"]
    ]
    emulator = LLRPEmulator(
        tags=tags,
        reads_per_sec=float(config.get("reads_per_sec", 400)),
        antenna_count=int(config.get("antenna_count", 4)),
        seed=int(config.get("seed", 1)),
    )
    await emulator.start()
    print(f"port {emulator.port}", flush=True)
    loop = asyncio.get_running_loop()
    pending = set()
    try:
        while True:
            line = await loop.run_in_executor(None, sys.stdin.readline)
            if not line:
                break
            words = line.split()
            if not words:
                continue
            command, args = words[0], words[1:]
            if command == "disconnect":
                antenna = int(args[0])
                if len(args) > 1:
                    delay = int(args[1]) / 1000.0

                    async def later(antenna=antenna, delay=delay):
                        await asyncio.sleep(delay)
                        await emulator.set_antenna_connected(antenna, False)

                    task = loop.create_task(later())
                    pending.add(task)
                    task.add_done_callback(pending.discard)
                else:
                    await emulator.set_antenna_connected(antenna, False)
                reply = "ok"
            elif command == "connect":
                await emulator.set_antenna_connected(int(args[0]), True)
                reply = "ok"
            elif command == "drop":
                emulator.drop_next(getattr(messages, args[0]))
                reply = "ok"
            elif command == "keepalive":
                await emulator.send_keepalive()
                try:
                    await emulator.wait_keepalive_ack(2.0)
                    reply = "ack"
                except TimeoutError:
                    reply = "no ack"
            elif command == "acks":
                reply = str(emulator.keepalive_acks)
            elif command == "active":
                # llrpkit keeps the ROSpecs' states to itself; the tests need to know one runs.
                running = any(state == "Active" for _, state in emulator._rospecs.values())
                reply = "yes" if running else "no"
            else:
                reply = f"unknown command {command}"
            print(reply, flush=True)
    finally:
        await emulator.stop()


asyncio.run(main())
