"""Seeded bad HTTP and WebSocket input against a running ``gestplay serve``: every request
is answered with a status below 500 (or the client goes first), every WebSocket frame
is read or the socket closed, the service goes on answering, and its log holds no
traceback: a line of its own per problem at most."""

from __future__ import annotations

import json
import random
import socket
import struct

from test_service import answer, serving

METHODS = [b"GET", b"POST", b"PUT", b"DELETE", b"OPTIONS", b"HEAD", b"G\xc3\xa9T", b"",
           b"POST POST"]
PATHS = [b"/api/play", b"/api/stop", b"/api/relax", b"/api/pose", b"/api/gestures",
         b"/api/events", b"/", b"/openapi.json", b"/api/../../etc/passwd", b"/%00",
         b"/api/play?x=" + b"%ff" * 20, b"*", b"/" + b"a" * 3000, b"/\xc3\xa9"]
BODIES = [b"", b"{}", b'{"gesture": "peace"}', b'{"steps": "index 90"}', b'{"steps": 9}',
          b'{"gesture": "peace", "loop": -1}', b"[" * 500, b'{"steps": "\xff"}', b"null",
          b'{"gesture": "' + b"x" * 5000 + b'"}', b"\x00" * 10, b'{"after": "maybe"}']
HEADERS = [b"Content-Type: application/json", b"Content-Type: text/plain",
           b"Origin: http://evil.example", b"Content-Length: -1",
           b"Content-Length: 99999999999", b"Transfer-Encoding: chunked",
           b"Authorization: Bearer \xc3\xa9", b"X-\x01: y", b"Connection: Upgrade",
           b"Upgrade: websocket", b"Sec-WebSocket-Version: 13",
           b"Sec-WebSocket-Key: \xff\xfe==", b"Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ=="]


def request(rng: random.Random, host: bytes) -> tuple[bytes, bool, bool]:
    """A request of random parts; whether the client goes before the answer; whether
    it is whole (else the service may wait for the rest)."""
    body = rng.choice(BODIES)
    lines = [rng.choice(METHODS) + b" " + rng.choice(PATHS) + b" " +
             rng.choice([b"HTTP/1.1", b"HTTP/1.0", b"HTTP/9.9", b"JUNK"])]
    lines.append(b"Host: " + (host if rng.random() < 0.8 else rng.choice([b"x", b""])))
    lines += rng.sample(HEADERS, rng.randint(0, 4))
    more = rng.choice([0, 0, 0, 5, -3]) if rng.random() < 0.7 else None
    if more is not None:
        lines.append(b"Content-Length: %d" % (len(body) + more))
    whole = not more or more < 0
    data = b"\r\n".join(lines) + b"\r\n\r\n" + body
    if rng.random() < 0.1:
        data, whole = data[:rng.randrange(len(data))], False
    return data, rng.random() < 0.1, whole and b"Content-Length: 9999" not in data


def frame(rng: random.Random) -> bytes:
    """A client's WebSocket frame, mostly malformed: any opcode, masked or not, any
    length (said and sent), text that is not UTF-8."""
    opcode = rng.choice([0x0, 0x1, 0x2, 0x3, 0x8, 0x9, 0xA, 0xF])
    payload = rng.choice([b"", b"hi", b"\xff\xfe", json.dumps({"x": 1}).encode(),
                          bytes(rng.randrange(256) for _ in range(rng.randrange(2000)))])
    head = bytes([(0x80 if rng.random() < 0.8 else 0) | (rng.randrange(8) << 4 if
                                                          rng.random() < 0.1 else 0) | opcode])
    n = len(payload)
    said = n if rng.random() < 0.8 else rng.choice([0, 1, 125, 126, 65535, 2 ** 40])
    mask = 0x80 if rng.random() < 0.9 else 0
    if said < 126:
        head += bytes([mask | said])
    elif said < 65536:
        head += bytes([mask | 126]) + struct.pack(">H", said)
    else:
        head += bytes([mask | 127]) + struct.pack(">Q", said)
    key = bytes(rng.randrange(256) for _ in range(4)) if mask else b""
    body = bytes(b ^ key[i % 4] for i, b in enumerate(payload)) if mask else payload
    return head + key + body


def socket_frames(host: str, port: int, rng: random.Random) -> None:
    """An events socket opened properly, then sent random frames until it closes."""
    handshake = (f"GET /api/events HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket"
                 f"\r\nConnection: Upgrade\r\nSec-WebSocket-Version: 13\r\n"
                 f"Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n").encode()
    with socket.create_connection((host, port), timeout=30) as s:
        s.sendall(handshake)
        assert s.recv(12) == b"HTTP/1.1 101"
        try:
            for _ in range(rng.randint(1, 6)):
                s.sendall(frame(rng))
        except (BrokenPipeError, ConnectionResetError):
            pass  # the service closed it: a frame it refused


def test_random_requests_and_frames_get_answers_never_a_500_or_a_traceback():
    rng = random.Random(35)
    with serving() as service:
        host = f"{service.host}:{service.port}".encode()
        statuses = []
        for k in range(300):
            data, leave, whole = request(rng, host)
            got = answer(service.host, service.port, data, leave, whole)
            if got:
                assert got.startswith(b"HTTP/1."), (k, data[:200], got)
                status = int(got.split()[1])
                assert status < 500, (k, data[:300], got)
                statuses.append(status)
        for _ in range(60):
            socket_frames(service.host, service.port, rng)
        assert service.call("GET", "/api/pose")[0] == 200
        _, log = service.stop()
    assert len(set(statuses)) >= 4  # a mix: accepted, refused, not found, forbidden...
    assert "Traceback" not in log, log[-3000:]
    lines = [line for line in log.splitlines() if line]
    assert all(line.startswith("gestplay serve") for line in lines), \
        [line for line in lines if not line.startswith("gestplay serve")][:5]
