"""The service while requests are long to check (``gestplay serve --profile inmoov`` on
sim://, docs/service.md): POSIX, ~2 min.

Each long request is sent from a thread while the main thread asks ``GET /api/pose``
every 50 ms: how long the long one took to be answered, its status, and how long the
pose took (median, worst). The requests: a 62 KB text of 2,500 unknown gesture calls;
40 different 940-character ``say`` lines (refused: a request may say 180 s); ten
requests that each say 150 s of new sounds (the service's memory after each); an hour
of whole-robot motion checked for contacts, then SIGTERM one second into another such
check (how long the service takes to end).

    python benchmarks/service_limits.py
"""

from __future__ import annotations

import http.client
import json
import re
import signal
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

WORDS = ["the", "quick", "brown", "fox", "jumps", "over", "a", "lazy", "dog", "while",
         "robots", "wave", "their", "hands", "and", "sing", "about", "the", "sea"]


def start() -> tuple[subprocess.Popen, int]:
    service = subprocess.Popen([sys.executable, "-m", "inmoov_dsl.cli.gestplay", "serve",
                                "--profile", "inmoov", "--port", "sim://?boot=0", "--http",
                                "127.0.0.1:0"], stderr=subprocess.PIPE, text=True)
    while not (found := re.search(r"127\.0\.0\.1:(\d+)/ drives", service.stderr.readline())):
        pass
    return service, int(found[1])


def call(port: int, method: str, path: str, body=None) -> tuple[int, dict]:
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=600)
    conn.request(method, path, None if body is None else json.dumps(body),
                 {"Content-Type": "application/json"})
    answer = conn.getresponse()
    status, data = answer.status, answer.read()
    conn.close()
    return status, json.loads(data) if data[:1] == b"{" else {}


def rss(pid: int) -> float:
    """Resident memory of ``pid``, MB."""
    return int(re.search(r"VmRSS:\s+(\d+)", Path(f"/proc/{pid}/status").read_text())[1]) / 1024


def while_checked(port: int, body: dict) -> str:
    """``body`` sent while the pose is asked every 50 ms: what was measured."""
    got: dict = {}

    def post() -> None:
        t0 = time.perf_counter()
        got["status"], got["answer"] = call(port, "POST", "/api/play", body)
        got["took"] = time.perf_counter() - t0

    thread = threading.Thread(target=post)
    thread.start()
    poses = []
    while thread.is_alive():
        t0 = time.perf_counter()
        call(port, "GET", "/api/pose")
        poses.append((time.perf_counter() - t0) * 1000)
        time.sleep(0.05)
    thread.join()
    return (f"{got['status']} after {got['took']:.2f} s "
            f"({got['answer'].get('error', '')[:60]}); /api/pose meanwhile: "
            f"{len(poses)} answers, median {statistics.median(poses):.1f} ms, "
            f"worst {max(poses):.1f} ms")


def speech(seed: int, characters: int) -> str:
    words = [WORDS[(seed * 7 + k * 3) % len(WORDS)] for k in range(characters // 3)]
    return f"{seed} " + " ".join(words)[:characters - 6]


HOUR = ("g:\n  repeat 1000:\n    r_index 90, r_middle 90, rothead 60, r_bicep 20, "
        "l_shoulder 40 over 1.5s\n    r_index 0, r_middle 0, rothead 100, r_bicep 5, "
        "l_shoulder 30 over 1.5s\n")


def main() -> None:
    service, port = start()
    try:
        print("memory at start:", f"{rss(service.pid):.0f} MB")
        unknown = "g:\n" + "\n".join(f"  unknown_gesture_{i:05d}" for i in range(2500))
        print(f"{len(unknown):,} characters of unknown calls:", while_checked(
            port, {"text": unknown}))
        says = "g:\n" + "\n".join(f'  say "{speech(i, 940)}"' for i in range(40))
        print("40 say lines of 940 characters:", while_checked(port, {"text": says}))
        for n in range(10):  # five sounds of ~30 s each, new ones each time
            text = "g:\n" + "\n".join(f'  say "{speech(100 + 5 * n + k, 450)}"'
                                      for k in range(5))
            status, _ = call(port, "POST", "/api/play", {"text": text})
            call(port, "POST", "/api/stop")
            print(f"say request {n + 1}: {status}, memory {rss(service.pid):.0f} MB")
        print("an hour of motion, checked for contacts:", while_checked(port, {"text": HOUR}))
        threading.Thread(target=call, args=(port, "POST", "/api/play", {"text": HOUR}),
                         daemon=True).start()
        time.sleep(1)
        t0 = time.perf_counter()
        service.send_signal(signal.SIGTERM)
        service.wait(60)
        print(f"SIGTERM one second into a check: ended after "
              f"{time.perf_counter() - t0:.2f} s, status {service.returncode}")
    finally:
        if service.poll() is None:
            service.kill()


if __name__ == "__main__":
    main()
