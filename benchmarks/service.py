"""The service under load (``gestplay serve``, docs/service.md): POSIX, ~3 min.

A gestsim board on a pty logs every byte it receives with the monotonic clock. First,
requests one at a time: the time from sending a ``POST /api/play`` to its first byte
at the board (the hand at rest). Then 20 clients send 500 requests each, a mix of
valid gestures, inline steps, bad sources, garbage bodies and oversize bodies, while
another client listens to the events: every request must get an answer (never a 500), the service's
memory must stay flat, and at the end the board's own DUMP must equal the pose the
service gives after the last request.

    python benchmarks/service.py
"""

from __future__ import annotations

import asyncio
import json
import os
import random
import re
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import aiohttp
from common import arrivals

CLIENTS, EACH, LATENCY_RUNS = 20, 500, 100
GESTURES = ["peace", "fist", "count", "wiggle", "ok", "rockon", "wave", "point"]


def start(log: Path):
    board = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestsim", "--quiet",
                              "--boot", "0.1", "--log", str(log)], stdout=subprocess.PIPE,
                             text=True)
    pty = board.stdout.readline().strip()
    service = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "serve",
                                "--port", pty, "--http", "127.0.0.1:0"],
                               stderr=subprocess.PIPE, text=True)
    while not (found := re.search(r"(http://\S+)/ drives", service.stderr.readline())):
        pass  # a warning first (no sound output here, say)
    url = found[1]
    return board, pty, service, url


def rss(pid: int) -> int:
    """Resident memory of ``pid``, kB."""
    text = Path(f"/proc/{pid}/status").read_text()
    return int(re.search(r"VmRSS:\s+(\d+)", text)[1])


def post(sock: socket.socket, host: str, port: str, steps: str) -> float:
    """Send a play request on ``sock``; when its last byte left this program."""
    body = json.dumps({"steps": steps}).encode()
    head = (f"POST /api/play HTTP/1.1\r\nHost: {host}:{port}\r\nContent-Type: "
            f"application/json\r\nContent-Length: {len(body)}\r\n\r\n").encode()
    sock.sendall(head + body)
    t0 = time.monotonic()
    answer = sock.recv(65536)
    assert answer.startswith(b"HTTP/1.1 202"), answer
    return t0


def first(log: Path, seen: int, byte: int) -> float:
    """When the first ``byte`` logged after line ``seen`` reached the board."""
    deadline = time.monotonic() + 5
    while not (new := [t for t, b in arrivals(log)[seen:] if b == byte]):
        assert time.monotonic() < deadline, f"no byte {byte} reached the board"
        time.sleep(0.0005)
    return new[0] + 1 / 960  # the log says when a byte starts on the wire


def latency(url: str, log: Path) -> list[float]:
    """Seconds from a play request's last byte leaving this program (a plain socket,
    kept alive, so no client library's work is counted) to its first byte reaching the
    board (the CANCEL its stream opens with), one at a time, the hand at rest."""
    host, port = url[len("http://"):].rsplit(":", 1)
    out = []
    with socket.create_connection((host, int(port))) as sock:
        for k in range(LATENCY_RUNS):
            time.sleep(0.4)  # the last move has ended: the link is quiet
            seen = len(arrivals(log))
            t0 = post(sock, host, port, f"index {k % 2 * 90} over 0.3s")
            out.append(first(log, seen, 255) - t0)
    return out


def request(rng: random.Random) -> tuple[str, bytes, dict]:
    kind = rng.choice(["gesture", "steps", "bad source", "garbage", "oversize", "after"])
    json_type = {"Content-Type": "application/json"}
    if kind == "gesture":
        return kind, json.dumps({"gesture": rng.choice(GESTURES)}).encode(), json_type
    if kind == "after":
        return kind, json.dumps({"steps": "wait 0.1s", "when": "after"}).encode(), json_type
    if kind == "steps":
        return kind, json.dumps({"steps": f"index {rng.randrange(181)}, middle "
                                          f"{rng.randrange(181)} over 0.4s"}).encode(), json_type
    if kind == "bad source":
        return kind, json.dumps({"steps": rng.choice(["indx 90", "index 900", "index 90 ovr 1s",
                                                      "peace.gest", "&&&"])}).encode(), json_type
    if kind == "garbage":
        return kind, rng.randbytes(rng.randrange(1, 200)), json_type
    return kind, b'{"steps": "' + b"a" * 70_000 + b'"}', json_type


async def client(url: str, seed: int, answers: Counter, times: list[float]) -> None:
    rng = random.Random(seed)
    async with aiohttp.ClientSession() as http:
        for _ in range(EACH):
            kind, body, headers = request(rng)
            t0 = time.perf_counter()
            async with http.post(f"{url}/api/play", data=body, headers=headers) as r:
                await r.read()
                answers[(kind, r.status)] += 1
            times.append(time.perf_counter() - t0)


async def listener(url: str, events: Counter, stop: asyncio.Event) -> None:
    async with aiohttp.ClientSession() as http, http.ws_connect(f"{url}/api/events") as ws:
        while not stop.is_set():
            try:
                message = await asyncio.wait_for(ws.receive(), 0.5)
            except TimeoutError:
                continue
            if message.type == aiohttp.WSMsgType.TEXT:
                event = json.loads(message.data)
                events[event["event"]] += 1
                if event["event"] == "error":
                    events["error: " + event["diagnostics"][0]["message"]] += 1


async def load(url: str, pid: int) -> dict:
    answers, events, times, memory = Counter(), Counter(), [], [rss(pid)]
    stop = asyncio.Event()
    listening = asyncio.ensure_future(listener(url, events, stop))

    async def sample():
        while not stop.is_set():
            await asyncio.sleep(1)
            memory.append(rss(pid))

    sampling = asyncio.ensure_future(sample())
    t0 = time.perf_counter()
    await asyncio.gather(*(client(url, seed, answers, times) for seed in range(CLIENTS)))
    elapsed = time.perf_counter() - t0
    async with aiohttp.ClientSession() as http:
        async with http.post(f"{url}/api/play", json={"gesture": "peace"}) as r:
            assert r.status == 202
        while True:  # the last request played through
            await asyncio.sleep(0.2)
            async with http.get(f"{url}/api/pose") as r:
                pose = await r.json()
            if pose["playing"] is None and not any(s["moving"]
                                                   for s in pose["servos"].values()):
                break
    stop.set()
    await asyncio.gather(listening, sampling)
    return {"answers": answers, "events": events, "times": times, "elapsed": elapsed,
            "memory": memory, "pose": {n: s["value"] for n, s in pose["servos"].items()}}


def dump(pty: str) -> dict:
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "dump", "--port",
                           pty], capture_output=True, text=True, timeout=60, check=True)
    return {w[0]: int(w[-1]) for w in map(str.split, done.stdout.splitlines()[1:])}


def main() -> None:
    log = Path(tempfile.mkdtemp()) / "received.log"
    board, pty, service, url = start(log)
    try:
        waits = latency(url, log)
        result = asyncio.run(load(url, service.pid))
        service.terminate()
        service.wait(timeout=20)
        held = dump(pty)
    finally:
        for proc in (service, board):
            if proc.poll() is None:
                proc.kill()
    answers, total = result["answers"], CLIENTS * EACH
    got = sum(answers.values())
    print(f"### The service under load ({os.cpu_count()} cores)\n")
    ms = sorted(1000 * w for w in waits)
    print(f"- POST /api/play to its first byte at the board (arrived), the hand at rest, "
          f"one at a time ({LATENCY_RUNS} runs): median {statistics.median(ms):.2f} ms, "
          f"p99 {ms[int(0.99 * len(ms)) - 1]:.2f} ms, max {ms[-1]:.2f} ms")
    print(f"- {CLIENTS} clients x {EACH} requests: {got:,} of {total:,} answered in "
          f"{result['elapsed']:.1f} s, {got / result['elapsed']:.0f} requests/s; "
          f"answer time median {1000 * statistics.median(result['times']):.1f} ms, "
          f"p99 {1000 * sorted(result['times'])[int(0.99 * got) - 1]:.1f} ms")
    print("- answers: " + ", ".join(f"{kind} {status}: {n:,}"
                                    for (kind, status), n in sorted(answers.items())))
    print("- events heard: " + ", ".join(f"{k} {n:,}" for k, n in
                                          sorted(result["events"].items())
                                          if not k.startswith("error: ")))
    for k, n in sorted(result["events"].items()):
        if k.startswith("error: "):
            print(f"  - {n:,} x {k}")
    memory = result["memory"]
    quarters = [memory[len(memory) * q // 4] / 1024 for q in range(4)] + [memory[-1] / 1024]
    print("- the service's memory (MB) at the start, after each quarter of the load: "
          + ", ".join(f"{m:.1f}" for m in quarters))
    print(f"- the board's DUMP after the last request equals the service's pose: "
          f"{held == result['pose']} ({held})")
    assert got == total and not any(status == 500 for _, status in answers)
    assert held == result["pose"]


if __name__ == "__main__":
    main()
