"""`sg3d serve` under load: p10/p50/p95 latency of POST /ask (room-scoped questions, one client: httpx,
and the standard library's http.client, whose own cost per request is smaller), the same questions
answered in this process through `sg3d.app.ask`, interleaved with them (the service's overhead is the
ratio, measured in the same run), then C concurrent clients x Q questions each (errors, requests/s),
the questions drawn from the docs' question list (every `sg3d ask "..." --room kitchen` example of the
README and docs/asking.md), then again with every request distinct (each its own `viewpoint`
position, which only left/right questions read: the same work, no answer-cache hit); one table of
both crowds: requests/s, p50, p95, errors, the server's answer-cache hits and misses (its
/metrics) and the machine's 1-minute load average before and after each.

    python -m benchmarks.bench_serve --home DIR --crowd-only --workers 2   # the crowds only, 2 workers

    python -m benchmarks.bench_serve                       # scratch store, builds the real kitchen
    python -m benchmarks.bench_serve --home DIR --room kitchen   # a store you built already
    python -m benchmarks.bench_serve --tiny                # scratch store, a 10-object kitchen via /ingest
    python -m benchmarks.bench_serve --tiny --trust        # only the service's trust figures (below)

--trust: a burst of 200 concurrent POST /ask (`--call health`: GET /health), 65 s of quiet
(`--quiet-s`), then 100 concurrent calls: answered and p95 of each; then GET /health from one client, alone and while another
client POSTs a 15 MB body to /health without a token in a loop: p50/p95/max of each.

The server is the real command (`python -m sg3d serve`) in its own process; clients are httpx
(an asyncio client per simulated robot, each with its own connection) in this process.
"""
from __future__ import annotations

import argparse
import asyncio
import http.client
import json
import os
import re
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import httpx

REPO = Path(__file__).resolve().parents[1]
KITCHEN = Path(os.environ.get("SG3D_SHARED", REPO.parent / "shared")) / "data" / "7scenes-redkitchen"
# the docs' question list: every `sg3d ask "..." --room kitchen` example of the README and docs/asking.md
DOCS_ASKED = re.compile(r'sg3d ask "([^"]+)" --room kitchen')


def docs_questions() -> list[str]:
    found: list[str] = []
    for page in (REPO / "README.md", REPO / "docs" / "asking.md"):
        found += DOCS_ASKED.findall(page.read_text())
    return list(dict.fromkeys(found))


QUESTIONS = docs_questions()


def sg3d(home: Path, *args: str, **kw) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "sg3d", "--home", str(home), *args], check=True, **kw)


def start_server(home: Path, port: int, workers: int = 1) -> subprocess.Popen:
    more = ["--workers", str(workers)] if workers > 1 else []
    proc = subprocess.Popen([sys.executable, "-m", "sg3d", "--home", str(home), "serve", "--port", str(port), *more],
                            stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        try:
            if httpx.get(f"http://127.0.0.1:{port}/health").status_code == 200:
                return proc
        except httpx.TransportError:
            pass
        if proc.poll() is not None:
            raise SystemExit("sg3d serve exited")
        time.sleep(0.2)
    proc.terminate()
    raise SystemExit("sg3d serve did not become healthy in 120 s")


class StdlibClient:
    """POST /ask over one keep-alive connection with the standard library's http.client: a client
    that costs a fraction of httpx's per request, so the figure is closer to the service alone."""

    def __init__(self, url: str, token: str) -> None:
        host, _, port = url.removeprefix("http://").partition(":")
        self.conn = http.client.HTTPConnection(host, int(port), timeout=60)
        self.headers = {"Authorization": f"Bearer {token}", "Content-Type": "application/json"}

    def ask(self, question: str, room: str) -> None:
        self.conn.request("POST", "/ask", json.dumps({"question": question, "room": room}), self.headers)
        reply = self.conn.getresponse()
        body = reply.read()
        if reply.status != 200:
            raise SystemExit(f"POST /ask answered {reply.status}: {body[:200]!r}")

    def close(self) -> None:
        self.conn.close()


def latencies(url: str, token: str, home: Path, room: str, repeat: int) -> dict[str, list[float]]:
    """Per question, in turn: POST /ask with httpx, POST /ask with http.client, and the same
    question through the application layer in this process (the reader store, the dict the route
    encodes, thumbnail inlined). Interleaved, so load that drifts during the run meets all three
    alike; what the service adds is the difference."""
    from sg3d.app import ask as app_ask
    from sg3d.settings import Settings

    store = Settings(home=home).reader()
    hx = httpx.Client(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=60)
    std = StdlibClient(url, token)
    ways = {"httpx": lambda q: hx.post("/ask", json={"question": q, "room": room}).raise_for_status(),
            "stdlib": lambda q: std.ask(q, room),
            "in process": lambda q: app_ask.ask(store, q, room=room).to_json(inline_thumbnail=True)}
    ms: dict[str, list[float]] = {name: [] for name in ways}
    try:
        for q in QUESTIONS:       # warm-up: taxonomy, label vectors, connections
            for way in ways.values():
                way(q)
        for _ in range(repeat):
            for q in QUESTIONS:
                for name, way in ways.items():
                    t0 = time.perf_counter()
                    way(q)
                    ms[name].append((time.perf_counter() - t0) * 1000)
    finally:
        hx.close()
        std.close()
        store.close()
    return ms


async def crowd(url: str, token: str, room: str, clients: int, per_client: int,
                distinct: bool = False) -> tuple[int, int, float, list[float]]:
    errors, done, ms = 0, 0, []

    async def robot(i: int) -> None:
        nonlocal errors, done
        async with httpx.AsyncClient(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=120) as c:
            for k in range(per_client):
                t0 = time.perf_counter()
                try:
                    body: dict = {"question": QUESTIONS[(i + k) % len(QUESTIONS)], "room": room}
                    if distinct:
                        body["viewpoint"] = {"position": [float(i), float(k), 0.0]}
                    r = await c.post("/ask", json=body)
                    ok = r.status_code == 200 and "answer" in r.json()
                except httpx.HTTPError:
                    ok = False
                ms.append((time.perf_counter() - t0) * 1000)
                done += 1
                errors += 0 if ok else 1

    t0 = time.perf_counter()
    await asyncio.gather(*(robot(i) for i in range(clients)))
    return done, errors, time.perf_counter() - t0, ms


async def calls_at_once(url: str, token: str, room: str, n: int, call: str = "ask") -> tuple[int, list[float]]:
    """`n` concurrent calls, each on its own connection: POST /ask (`call` "ask") or GET /health
    (each runs its store call in the service's worker pool): (how many were answered 200, ms each)."""
    async def one(c: httpx.AsyncClient, i: int) -> tuple[bool, float]:
        t0 = time.perf_counter()
        try:
            if call == "ask":
                r = await c.post("/ask", json={"question": QUESTIONS[i % len(QUESTIONS)], "room": room})
            else:
                r = await c.get("/health")
            ok = r.status_code == 200
        except httpx.HTTPError:
            ok = False
        return ok, (time.perf_counter() - t0) * 1000

    # one client, one connection per call (no pool limit): the client's own cost stays small
    async with httpx.AsyncClient(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=400,
                                 limits=httpx.Limits(max_connections=None, max_keepalive_connections=0)) as c:
        done = await asyncio.gather(*(one(c, i) for i in range(n)))
    return sum(ok for ok, _ in done), [ms for _, ms in done]


def burst_then_quiet(url: str, token: str, room: str, burst: int, quiet_s: float, after: int,
                     call: str = "ask") -> bool:
    """A burst of `burst` concurrent calls, `quiet_s` of nothing, then `after` concurrent calls;
    prints answered and p95 of each; True when every call was answered."""
    what = "POST /ask" if call == "ask" else "GET /health"
    asyncio.run(calls_at_once(url, token, room, 1, call))     # warm-up: the label model, taxonomy, connections
    answered, ms = asyncio.run(calls_at_once(url, token, room, burst, call))
    print(f"burst: {burst} concurrent {what}: {answered} answered, p95 {pct(ms, 95):.0f} ms", flush=True)
    time.sleep(quiet_s)
    answered_after, ms = asyncio.run(calls_at_once(url, token, room, after, call))
    print(f"after {quiet_s:g} s of quiet: {after} concurrent {what}: {answered_after} answered, "
          f"p95 {pct(ms, 95):.0f} ms, max {max(ms):.0f} ms", flush=True)
    return answered == burst and answered_after == after


def post_raw(url: str, path: str, body: bytes) -> int:
    """POST `body` to `path` without a token on a fresh connection: the reply's status (0: none)."""
    host, _, port = url.removeprefix("http://").partition(":")
    head = (f"POST {path} HTTP/1.1\r\nHost: {host}\r\nContent-Type: application/json\r\n"
            f"Content-Length: {len(body)}\r\n\r\n").encode()
    with socket.create_connection((host, int(port)), timeout=120) as sock:
        try:
            sock.sendall(head + body)
        except OSError:
            pass                      # answered and closed before the whole body went
        try:
            reply = sock.recv(4096)
        except OSError:
            return 0
    return int(reply.split()[1]) if reply.startswith(b"HTTP/") else 0


def health_under_flood(url: str, seconds: float, mb: int) -> None:
    """GET /health every 50 ms from one client for `seconds`, alone and then while another client
    POSTs `mb` MB of JSON to /health without a token in a loop: p50/p95/max of each."""
    body = b"[" + b"1," * (mb * 500_000 - 1) + b"1]"
    failed = [0]

    def sample() -> list[float]:
        ms = []
        with httpx.Client(base_url=url, timeout=120) as c:
            c.get("/health")
            end = time.monotonic() + seconds
            while time.monotonic() < end:
                t0 = time.perf_counter()
                failed[0] += c.get("/health").status_code != 200
                ms.append((time.perf_counter() - t0) * 1000)
                time.sleep(0.05)
        return ms

    alone = sample()
    stop, statuses = threading.Event(), []

    def poster() -> None:
        while not stop.is_set():
            statuses.append(post_raw(url, "/health", body))

    flood = threading.Thread(target=poster, daemon=True)
    flood.start()
    try:
        flooded = sample()
    finally:
        stop.set()
        flood.join(300)
    print(f"GET /health, one client alone: {len(alone)} calls, p50 {pct(alone, 50):.1f} ms, "
          f"p95 {pct(alone, 95):.1f} ms, max {max(alone):.1f} ms")
    if failed[0]:
        print(f"  {failed[0]} of the GET /health calls were not 200")
    print(f"GET /health while another client POSTs {len(body) / 1e6:.0f} MB to /health without a token in a loop "
          f"({len(statuses)} posts, answered {sorted(set(statuses))}): {len(flooded)} calls, "
          f"p50 {pct(flooded, 50):.1f} ms, p95 {pct(flooded, 95):.1f} ms, max {max(flooded):.1f} ms", flush=True)


def cache_counts(url: str) -> dict[str, float]:
    """The server's answer-cache hits and misses from /metrics (empty for a server without it)."""
    r = httpx.get(url + "/metrics", timeout=30)
    if r.status_code != 200:
        return {}
    from prometheus_client.parser import text_string_to_metric_families

    return {s.labels["result"]: s.value for f in text_string_to_metric_families(r.text)
            if f.name == "sg3d_answer_cache" for s in f.samples if s.name.endswith("_total")}


def crowds(url: str, token: str, room: str, clients: int, per_client: int) -> int:
    """The crowd with the docs' questions, then with every request distinct: one table (errors of both)."""
    errors_all, lines = 0, []
    for distinct in (False, True):
        before, load = cache_counts(url), os.getloadavg()[0]
        done, errors, wall, cms = asyncio.run(crowd(url, token, room, clients, per_client, distinct))
        after = cache_counts(url)
        hits, misses = (f"{after.get(k, 0) - before.get(k, 0):.0f}" if after else "-" for k in ("hit", "miss"))
        mode = "every question distinct" if distinct else f"the docs' {len(QUESTIONS)} questions"
        lines.append(f"| {clients} x {per_client}, {mode} | {done} | {errors} | {done / wall:.1f} | {pct(cms, 50):.0f} ms "
                     f"| {pct(cms, 95):.0f} ms | {hits} | {misses} | {load:.2f} → {os.getloadavg()[0]:.2f} |")
        errors_all += errors
    print("| crowd | requests | errors | requests/s | p50 | p95 | cache hits | cache misses | load (1 min) |")
    print("|---|---|---|---|---|---|---|---|---|")
    print("\n".join(lines), flush=True)
    return errors_all


def pct(values: list[float], p: float) -> float:
    return statistics.quantiles(values, n=100, method="inclusive")[int(p) - 1] if len(values) > 1 else values[0]


def spread(ms: list[float]) -> str:
    """p10 (the requests least disturbed by other load on the machine), p50 and p95."""
    return f"p10 {pct(ms, 10):.1f} ms, p50 {pct(ms, 50):.1f} ms, p95 {pct(ms, 95):.1f} ms"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--home", type=Path, help="an existing store's home (default: a scratch store)")
    ap.add_argument("--room", default="kitchen")
    ap.add_argument("--tiny", action="store_true", help="ingest a 10-object kitchen instead of building the real one")
    ap.add_argument("--repeat", type=int, default=20, help="rounds of the questions for the latency figures")
    ap.add_argument("--clients", type=int, default=100)
    ap.add_argument("--per-client", type=int, default=20)
    ap.add_argument("--workers", type=int, default=1, help="sg3d serve --workers")
    ap.add_argument("--crowd-only", action="store_true", help="only the two crowds, not the one-client latency rounds")
    ap.add_argument("--trust", action="store_true", help="only the burst/quiet and /health-under-flood figures")
    ap.add_argument("--burst", type=int, default=200, help="--trust: concurrent calls in the burst (0: none, only the /health figures)")
    ap.add_argument("--quiet-s", type=float, default=65.0, help="--trust: seconds of quiet after the burst")
    ap.add_argument("--after", type=int, default=100, help="--trust: concurrent calls after the quiet")
    ap.add_argument("--call", choices=["ask", "health"], default="ask",
                    help="--trust: the burst's calls, POST /ask or GET /health (both run in the worker pool)")
    ap.add_argument("--flood-mb", type=int, default=15, help="--trust: MB per unauthenticated POST /health")
    ap.add_argument("--flood-s", type=float, default=20.0, help="--trust: seconds of /health sampling, each way")
    args = ap.parse_args()
    if args.tiny and args.home:
        ap.error("--tiny ingests a hand-made kitchen into the store: use it without --home (a scratch store)")

    from sg3d.graphdb.embedded import EmbeddedServer, free_port

    scratch = None if args.home else tempfile.TemporaryDirectory(prefix="sg3d-bench-serve-")
    home = Path(scratch.name) if scratch is not None else args.home
    port = free_port()
    server = None
    try:
        if not args.home and not args.tiny:
            if not KITCHEN.exists():
                raise SystemExit(f"no kitchen at {KITCHEN}: use --tiny or --home")
            print("building the kitchen into a scratch store ...", flush=True)
            sg3d(home, "build", str(KITCHEN), "--room", args.room, "--json", stdout=subprocess.DEVNULL)
        server = start_server(home, port, args.workers)
        from sg3d.server.auth import token_path

        url, token = f"http://127.0.0.1:{port}", token_path(home).read_text().strip()
        if args.tiny:
            from sg3d.testing import kitchen_body

            httpx.post(url + "/ingest", json=kitchen_body(building="default", room=args.room),
                       headers={"Authorization": f"Bearer {token}"}, timeout=120).raise_for_status()
        if args.trust:
            print(f"load average (1 min) {os.getloadavg()[0]:.2f} at the start", flush=True)
            ok = args.burst == 0 or burst_then_quiet(url, token, args.room, args.burst, args.quiet_s, args.after,
                                                     args.call)
            health_under_flood(url, args.flood_s, args.flood_mb)
            print(f"load average (1 min) {os.getloadavg()[0]:.2f} at the end")
            if not ok:
                raise SystemExit(1)
            return
        if args.crowd_only:
            asyncio.run(calls_at_once(url, token, args.room, 8))     # warm-up: the label model, taxonomy, connections
            if crowds(url, token, args.room, args.clients, args.per_client):
                raise SystemExit(1)
            return
        load_before = os.getloadavg()[0]
        ms = latencies(url, token, home, args.room, args.repeat)
        print(f"load average (1 min) {load_before:.2f} before the latency rounds, {os.getloadavg()[0]:.2f} after")
        local = pct(ms["in process"], 50)
        print(f"the questions in process: {len(ms['in process'])} answers, {spread(ms['in process'])}")
        for client in ("httpx", "stdlib"):
            print(f"POST /ask, room-scoped, one {client} client: {spread(ms[client])}; "
                  f"service / in-process p50 = {pct(ms[client], 50) / local:.2f}")
        if crowds(url, token, args.room, args.clients, args.per_client):
            raise SystemExit(1)
    finally:
        if server is not None:
            server.terminate()
            server.wait(20)
        if scratch is not None:
            EmbeddedServer(home).stop()
            scratch.cleanup()


if __name__ == "__main__":
    main()
