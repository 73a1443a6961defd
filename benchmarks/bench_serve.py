"""`sg3d serve` under load: p10/p50/p95 latency of POST /ask (room-scoped questions, one client: httpx,
and the standard library's http.client, whose own cost per request is smaller), the same questions
answered in this process through `sg3d.app.ask`, interleaved with them (the service's overhead is the
ratio, measured in the same run), then C concurrent clients x Q questions each (errors, requests/s),
the questions drawn from the docs' question list (every `sg3d ask "..." --room kitchen` example of the
README and docs/asking.md), then again with every request distinct (each its own `viewpoint`
position, which only left/right questions read: the same work, no answer-cache hit); one table of
both crowds: requests/s, p50, p95, errors, the server's answer-cache hits and misses (its
/metrics), the CPU each process spent per request (the clients, the server's workers, the store
daemon) and the machine's 1-minute load average before and after each. The crowd's clients are
aiohttp's where it is installed (`--client httpx` for httpx's, which cost about seven times the
CPU per request, 2.2 ms against 0.3: on a 2-core machine the client's CPU is taken from the
service under test).

    python -m benchmarks.bench_serve --home DIR --crowd-only --compare REV [--rounds 2]

--compare: the same crowds against `sg3d serve` of git revision REV (its `sg3d` package, from `git
archive`) and of this tree, both serving the one store, taking turns crowd by crowd (the order
alternating from round to round): one table with a column for each and the load over the runs.

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
import contextlib
import http.client
import importlib.util
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
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

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


def start_server(home: Path, port: int, workers: int = 1, tree: Path = REPO,
                 threads: Optional[int] = None) -> subprocess.Popen:
    """`sg3d serve` of the `sg3d` package in `tree` (this checkout, or another revision's)."""
    more = ["--workers", str(workers)] if workers > 1 else []
    more += ["--threads", str(threads)] if threads else []
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(tree), os.environ.get("PYTHONPATH")]))}
    proc = subprocess.Popen([sys.executable, "-m", "sg3d", "--home", str(home), "serve", "--port", str(port), *more],
                            stderr=subprocess.DEVNULL, cwd=tree, env=env)
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
                distinct: bool = False, salt: int = 0) -> tuple[int, int, float, list[float]]:
    """`clients` httpx clients asking `per_client` questions each; with `distinct`, each request
    its own viewpoint (`salt` tells one run's from another's: a server's cache keeps them all)."""
    errors, done, ms = 0, 0, []

    async def robot(i: int) -> None:
        nonlocal errors, done
        async with httpx.AsyncClient(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=120) as c:
            for k in range(per_client):
                t0 = time.perf_counter()
                try:
                    body = _crowd_body(i, k, room, distinct, salt)
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


def _crowd_body(i: int, k: int, room: str, distinct: bool, salt: int) -> dict:
    """Robot i's k-th POST /ask body: the docs' questions in turn, each made distinct (a viewpoint
    no other ask has: no cache hit) when `distinct`."""
    body: dict = {"question": QUESTIONS[(i + k) % len(QUESTIONS)], "room": room}
    if distinct:
        body["viewpoint"] = {"position": [float(i), float(k), float(salt)]}
    return body


async def crowd_aiohttp(url: str, token: str, room: str, clients: int, per_client: int,
                        distinct: bool = False, salt: int = 0) -> tuple[int, int, float, list[float]]:
    """`crowd` with aiohttp's client (its HTTP parser in C): a seventh of httpx's CPU per request,
    which on a small machine is CPU the service under test does not have to share."""
    import aiohttp

    errors, done, ms = 0, 0, []

    async def robot(i: int) -> None:
        nonlocal errors, done
        async with aiohttp.ClientSession(url, headers={"Authorization": f"Bearer {token}"},
                                         connector=aiohttp.TCPConnector(limit=1),
                                         timeout=aiohttp.ClientTimeout(total=120)) as c:
            for k in range(per_client):
                t0 = time.perf_counter()
                try:
                    body = _crowd_body(i, k, room, distinct, salt)
                    async with c.post("/ask", json=body) as r:
                        ok = r.status == 200 and "answer" in await r.json()
                except (aiohttp.ClientError, asyncio.TimeoutError):
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


def cpu_seconds(pid: Optional[int], tree: bool = False) -> float:
    """User + system CPU seconds of process `pid` (with `tree`, and of its children: the worker
    processes of `sg3d serve --workers N`); 0 where /proc does not say."""
    def one(p: int) -> float:
        try:
            fields = Path(f"/proc/{p}/stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            return 0.0
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")

    if pid is None:
        return 0.0
    total = one(pid)
    if tree:
        for child in Path(f"/proc/{pid}/task/{pid}/children").read_text().split() if Path(
                f"/proc/{pid}/task/{pid}/children").exists() else ():
            total += cpu_seconds(int(child), tree=True)
    return total


def store_pid(home: Path) -> Optional[int]:
    """The embedded store daemon's process (its server.json), or None."""
    try:
        return int(json.loads((home / "server.json").read_text())["pid"])
    except (OSError, ValueError, KeyError):
        return None


@dataclass
class Served:
    """One `sg3d serve` under test: its label in the table, its process and address."""
    label: str
    proc: subprocess.Popen
    url: str


def one_crowd(server: Served, token: str, room: str, clients: int, per_client: int, distinct: bool,
              client: str, home: Path, salt: int = 0) -> dict:
    """One crowd against `server`: requests/s, p50, p95, errors, cache hits and misses, the CPU
    each process spent per request (client: this process; server: every worker; store: the
    embedded daemon) and the 1-minute load before and after."""
    run = crowd_aiohttp if client == "aiohttp" else crowd
    before, load = cache_counts(server.url), os.getloadavg()[0]
    pids = (os.getpid(), server.proc.pid, store_pid(home))
    cpu0 = [cpu_seconds(p, tree=i == 1) for i, p in enumerate(pids)]
    done, errors, wall, ms = asyncio.run(run(server.url, token, room, clients, per_client, distinct, salt))
    cpu1 = [cpu_seconds(p, tree=i == 1) for i, p in enumerate(pids)]
    after = cache_counts(server.url)
    hits, misses = (f"{after.get(k, 0) - before.get(k, 0):.0f}" if after else "-" for k in ("hit", "miss"))
    return {"done": done, "errors": errors, "rate": done / wall, "p50": pct(ms, 50), "p95": pct(ms, 95),
            "hits": hits, "misses": misses, "load": (load, os.getloadavg()[0]),
            "cpu": [(b - a) / max(done, 1) * 1000 for a, b in zip(cpu0, cpu1)]}


def crowds(servers: list[Served], token: str, room: str, clients: int, per_client: int, client: str = "aiohttp",
           home: Optional[Path] = None, rounds: int = 1) -> int:
    """The crowd with the docs' questions, then with every request distinct, against each server in
    turn (with two, their order alternating from round to round, so load that drifts meets both
    alike): one table; the errors of all."""
    results: dict[tuple[bool, str], list[dict]] = {}
    for r in range(rounds):
        for distinct in (False, True):
            for server in (servers if r % 2 == 0 else servers[::-1]):
                results.setdefault((distinct, server.label), []).append(
                    one_crowd(server, token, room, clients, per_client, distinct, client, home or Path("."), r))
    print(f"{clients} clients x {per_client} questions each, the {client} client, {rounds} round(s); "
          f"CPU ms per request of this client / the server (all workers) / the store daemon")
    if len(servers) == 1:
        print_crowds(results, servers[0].label, clients, per_client)
    else:
        print_compared(results, [s.label for s in servers])
    return sum(x["errors"] for rows in results.values() for x in rows)


def _mode(distinct: bool) -> str:
    return "every question distinct" if distinct else f"the docs' {len(QUESTIONS)} questions"


def print_crowds(results: dict, label: str, clients: int, per_client: int) -> None:
    print("| crowd | requests | errors | requests/s | p50 | p95 | cache hits | cache misses | CPU ms/request "
          "client / server / store | load (1 min) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for (distinct, _), rows in results.items():
        for x in rows:
            cpu = " / ".join(f"{c:.2f}" for c in x["cpu"])
            print(f"| {clients} x {per_client}, {_mode(distinct)} | {x['done']} | {x['errors']} | {x['rate']:.1f} "
                  f"| {x['p50']:.0f} ms | {x['p95']:.0f} ms | {x['hits']} | {x['misses']} | {cpu} "
                  f"| {x['load'][0]:.2f} → {x['load'][1]:.2f} |")
    sys.stdout.flush()


def print_compared(results: dict, labels: list[str]) -> None:
    """One row per crowd and measure, one column per server (the median of the rounds), and the
    load range over the crowd's runs."""
    measures = (("requests/s", "rate", "{:.1f}"), ("p50 ms", "p50", "{:.0f}"), ("p95 ms", "p95", "{:.0f}"),
                ("errors", "errors", "{:.0f}"), ("cache hits", "hits", "{}"), ("cache misses", "misses", "{}"),
                ("server CPU ms/request", 1, "{:.2f}"),
                ("store CPU ms/request", 2, "{:.2f}"), ("client CPU ms/request", 0, "{:.2f}"))
    print("| crowd | measure | " + " | ".join(labels) + " | load (1 min) over the runs |")
    print("|---|---|" + "---|" * len(labels) + "---|")
    for distinct in (False, True):
        loads = [v for label in labels for x in results[(distinct, label)] for v in x["load"]]
        for name, key, fmt in measures:
            cells = []
            for label in labels:
                values = [x["cpu"][key] if isinstance(key, int) else x[key] for x in results[(distinct, label)]]
                numbers = all(isinstance(v, (int, float)) for v in values)
                cells.append(fmt.format(statistics.median(values)) if numbers else " / ".join(map(str, values)))
            print(f"| {_mode(distinct)} | {name} | " + " | ".join(cells) + f" | {min(loads):.2f}–{max(loads):.2f} |")
    sys.stdout.flush()


def tree_of(rev: str, into: Path) -> Path:
    """The `sg3d` package of git revision `rev` of this checkout, written under `into`."""
    archive = subprocess.run(["git", "-C", str(REPO), "archive", rev, "sg3d"], check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive, check=True)
    return into


def pct(values: list[float], p: float) -> float:
    return statistics.quantiles(values, n=100, method="inclusive")[int(p) - 1] if len(values) > 1 else values[0]


def spread(ms: list[float]) -> str:
    """p10 (the requests least disturbed by other load on the machine), p50 and p95."""
    return f"p10 {pct(ms, 10):.1f} ms, p50 {pct(ms, 50):.1f} ms, p95 {pct(ms, 95):.1f} ms"


def arguments() -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--home", type=Path, help="an existing store's home (default: a scratch store)")
    ap.add_argument("--room", default="kitchen")
    ap.add_argument("--tiny", action="store_true", help="ingest a 10-object kitchen instead of building the real one")
    ap.add_argument("--repeat", type=int, default=20, help="rounds of the questions for the latency figures")
    ap.add_argument("--clients", type=int, default=100)
    ap.add_argument("--per-client", type=int, default=20)
    ap.add_argument("--workers", type=int, default=1, help="sg3d serve --workers")
    ap.add_argument("--threads", type=int, help="sg3d serve --threads (default: its own)")
    ap.add_argument("--crowd-only", action="store_true", help="only the two crowds, not the one-client latency rounds")
    ap.add_argument("--client", choices=["aiohttp", "httpx"],
                    default="aiohttp" if importlib.util.find_spec("aiohttp") else "httpx",
                    help="the crowd's HTTP client (aiohttp, where installed: a seventh of httpx's CPU per request)")
    ap.add_argument("--compare", metavar="REV", help="the crowds against `sg3d serve` of git revision REV too "
                    "(before) and of this tree (after), alternating: one table with a column each")
    ap.add_argument("--rounds", type=int, default=1, help="times each crowd runs against each server")
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
    if args.compare and (args.trust or not args.crowd_only):
        ap.error("--compare runs the crowds only: use it with --crowd-only")
    return args


def main() -> None:
    args = arguments()
    from sg3d.graphdb.embedded import EmbeddedServer, free_port

    scratch = None if args.home else tempfile.TemporaryDirectory(prefix="sg3d-bench-serve-")
    home = Path(scratch.name) if scratch is not None else args.home
    servers: list[Served] = []
    with contextlib.ExitStack() as stack:
        if scratch is not None:
            stack.callback(scratch.cleanup)
            stack.callback(lambda: EmbeddedServer(home).stop())
        if not args.home and not args.tiny:
            if not KITCHEN.exists():
                raise SystemExit(f"no kitchen at {KITCHEN}: use --tiny or --home")
            print("building the kitchen into a scratch store ...", flush=True)
            sg3d(home, "build", str(KITCHEN), "--room", args.room, "--json", stdout=subprocess.DEVNULL)
        trees = [("after (this tree)", REPO)]
        if args.compare:
            old = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="sg3d-bench-before-")))
            trees.insert(0, (f"before ({args.compare})", tree_of(args.compare, old)))
        else:
            trees = [("this tree", REPO)]
        for label, tree in trees:
            port = free_port()
            proc = start_server(home, port, args.workers, tree, args.threads)
            stack.callback(stop, proc)
            servers.append(Served(label, proc, f"http://127.0.0.1:{port}"))
        from sg3d.server.auth import token_path

        token = token_path(home).read_text().strip()
        if not measure(args, home, token, servers):
            raise SystemExit(1)


def stop(proc: subprocess.Popen) -> None:
    proc.terminate()
    proc.wait(20)


def measure(args: argparse.Namespace, home: Path, token: str, servers: list[Served]) -> bool:
    """The figures the arguments ask for, against `servers` (one, or before and after with
    --compare); False when a call failed."""
    url = servers[0].url
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
        return ok
    if not args.crowd_only:
        load_before = os.getloadavg()[0]
        ms = latencies(url, token, home, args.room, args.repeat)
        print(f"load average (1 min) {load_before:.2f} before the latency rounds, {os.getloadavg()[0]:.2f} after")
        local = pct(ms["in process"], 50)
        print(f"the questions in process: {len(ms['in process'])} answers, {spread(ms['in process'])}")
        for client in ("httpx", "stdlib"):
            print(f"POST /ask, room-scoped, one {client} client: {spread(ms[client])}; "
                  f"service / in-process p50 = {pct(ms[client], 50) / local:.2f}")
    for server in servers:          # warm-up: the label model, taxonomy, connections
        asyncio.run(calls_at_once(server.url, token, args.room, 8))
    return crowds(servers, token, args.room, args.clients, args.per_client, args.client, home, args.rounds) == 0


if __name__ == "__main__":
    main()
