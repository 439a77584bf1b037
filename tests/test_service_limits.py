"""gestplay serve under what a fuzzer found: a body in several TCP segments, requests
whose check is long (while the service goes on answering, and stops on SIGTERM), a
request's sounds, and the limit of a gesture's length on every path. Clients the project
did not write: a raw socket, curl, http.client and the websockets library."""

import json
import socket
import time

from test_service import serving

STEPS = b'{"steps": "index 90 over 0.5s"}'


def segments(host: str, port: int, head: bytes, parts: list[bytes], pause: float = 0.2,
             read_all: bool = True) -> bytes:
    """Send ``head`` (a request's line and headers, with Expect: 100-continue), wait for
    the service's 100 Continue (its handler is reading the body: the event), then each
    of ``parts`` with a pause between; the answer (its first bytes when not
    ``read_all``)."""
    with socket.create_connection((host, port), timeout=30) as s:
        s.sendall(head + b"Expect: 100-continue\r\n\r\n")
        assert s.recv(4096).startswith(b"HTTP/1.1 100 Continue")
        for part in parts:
            s.sendall(part)
            time.sleep(pause)  # the service reads what came so far (on a busy machine
            # perhaps not: then it reads more at once, which it must take too)
        answer = b""
        while chunk := s.recv(65536):
            answer += chunk
            if not read_all or b"\r\n\r\n" in answer and answer.endswith(b"}"):
                break
        return answer


def head(service, more: bytes) -> bytes:
    return (b"POST /api/play HTTP/1.1\r\nHost: %s:%d\r\nContent-Type: application/json\r\n"
            % (service.host.encode(), service.port)) + more


def chunked(data: bytes, size: int) -> list[bytes]:
    """``data`` as HTTP chunks of ``size`` bytes (without the last, empty one)."""
    return [b"%x\r\n%s\r\n" % (len(data[i:i + size]), data[i:i + size])
            for i in range(0, len(data), size)]


def test_a_body_in_several_segments_is_read_whole_and_a_large_one_is_not_read():
    with serving() as service:
        answer = segments(service.host, service.port,
                          head(service, b"Content-Length: %d\r\n" % len(STEPS)),
                          [STEPS[:10], STEPS[10:20], STEPS[20:]])
        assert answer.startswith(b"HTTP/1.1 202 "), answer
        assert json.loads(answer.partition(b"\r\n\r\n")[2])["id"]
        answer = segments(service.host, service.port,
                          head(service, b"Transfer-Encoding: chunked\r\n"),
                          [*chunked(STEPS, 7), b"0\r\n\r\n"])
        assert answer.startswith(b"HTTP/1.1 202 "), answer
        # a body that grows past the limit is refused once the limit is passed: the
        # service answers without waiting for the rest (the last chunk is never sent)
        big = b'{"steps": "' + b"x" * 70_000
        answer = segments(service.host, service.port,
                          head(service, b"Transfer-Encoding: chunked\r\n"),
                          chunked(big, 16_384), pause=0.05, read_all=False)
        assert answer.startswith(b"HTTP/1.1 400 "), answer[:200]
        assert b"the body is larger than 65,536 bytes" in answer
        assert service.call("GET", "/api/pose")[0] == 200
