"""`sg3d serve` under load: p50/p95 latency of POST /ask (room-scoped questions, one client), the
same questions answered in this process through `app.ask` (the service's overhead is the ratio,
measured in the same run), then C concurrent clients x Q questions each (errors, requests/s).

    python -m benchmarks.bench_serve                       # scratch store, builds the real kitchen
    python -m benchmarks.bench_serve --home DIR --room kitchen   # a store you built already
    python -m benchmarks.bench_serve --tiny                # scratch store, a 10-object kitchen via /ingest

The server is the real command (`python -m sg3d serve`) in its own process; clients are httpx
(an asyncio client per simulated robot, each with its own connection) in this process.
"""
from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import httpx

REPO = Path(__file__).resolve().parents[1]
KITCHEN = Path(os.environ.get("SG3D_SHARED", REPO.parent / "shared")) / "data" / "7scenes-redkitchen"
QUESTIONS = [
    "how many cups are in the room?",
    "is there a sink?",
    "what is on the table?",
    "how many chairs are there?",
    "where is the microwave?",
    "which cup is the biggest?",
    "how many objects are on the table?",
    "is the cup on the table?",
]


def sg3d(home: Path, *args: str, **kw) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "sg3d", "--home", str(home), *args], check=True, **kw)


def start_server(home: Path, port: int) -> subprocess.Popen:
    proc = subprocess.Popen([sys.executable, "-m", "sg3d", "--home", str(home), "serve", "--port", str(port)],
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


def latency(url: str, token: str, room: str, repeat: int) -> list[float]:
    ms = []
    with httpx.Client(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=60) as c:
        for q in QUESTIONS:       # warm-up: taxonomy, label vectors, connection
            c.post("/ask", json={"question": q, "room": room}).raise_for_status()
        for _ in range(repeat):
            for q in QUESTIONS:
                t0 = time.perf_counter()
                c.post("/ask", json={"question": q, "room": room}).raise_for_status()
                ms.append((time.perf_counter() - t0) * 1000)
    return ms


def in_process(home: Path, room: str, repeat: int) -> list[float]:
    """The same questions through the application layer in this process (the reader store, the
    JSON the route returns, thumbnail inlined): what the service adds is the rest."""
    from app import ask as app_ask
    from sg3d.settings import Settings

    store = Settings(home=home).reader()
    ms = []
    try:
        for q in QUESTIONS:       # warm-up, as for the service
            app_ask.ask(store, q, room=room).to_json(inline_thumbnail=True)
        for _ in range(repeat):
            for q in QUESTIONS:
                t0 = time.perf_counter()
                app_ask.ask(store, q, room=room).to_json(inline_thumbnail=True)
                ms.append((time.perf_counter() - t0) * 1000)
    finally:
        store.close()
    return ms


async def crowd(url: str, token: str, room: str, clients: int, per_client: int) -> tuple[int, int, float, list[float]]:
    errors, done, ms = 0, 0, []

    async def robot(i: int) -> None:
        nonlocal errors, done
        async with httpx.AsyncClient(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=120) as c:
            for k in range(per_client):
                t0 = time.perf_counter()
                try:
                    r = await c.post("/ask", json={"question": QUESTIONS[(i + k) % len(QUESTIONS)], "room": room})
                    ok = r.status_code == 200 and "answer" in r.json()
                except httpx.HTTPError:
                    ok = False
                ms.append((time.perf_counter() - t0) * 1000)
                done += 1
                errors += 0 if ok else 1

    t0 = time.perf_counter()
    await asyncio.gather(*(robot(i) for i in range(clients)))
    return done, errors, time.perf_counter() - t0, ms


def pct(values: list[float], p: float) -> float:
    return statistics.quantiles(values, n=100)[int(p) - 1] if len(values) > 1 else values[0]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--home", type=Path, help="an existing store's home (default: a scratch store)")
    ap.add_argument("--room", default="kitchen")
    ap.add_argument("--tiny", action="store_true", help="ingest a 10-object kitchen instead of building the real one")
    ap.add_argument("--repeat", type=int, default=20, help="rounds of the questions for the latency figures")
    ap.add_argument("--clients", type=int, default=100)
    ap.add_argument("--per-client", type=int, default=20)
    args = ap.parse_args()

    from graphdb.embedded import EmbeddedServer, free_port

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
        server = start_server(home, port)
        from sg3d.server.auth import token_path

        url, token = f"http://127.0.0.1:{port}", token_path(home).read_text().strip()
        if args.tiny:
            from sg3d.testing import kitchen_body

            httpx.post(url + "/ingest", json=kitchen_body(building="default", room=args.room),
                       headers={"Authorization": f"Bearer {token}"}, timeout=120).raise_for_status()
        ms = latency(url, token, args.room, args.repeat)
        local = in_process(home, args.room, args.repeat)
        ms_again = latency(url, token, args.room, args.repeat)     # interleaved: load drifts between them
        ms += ms_again
        print(f"POST /ask, room-scoped, one client: {len(ms)} requests, p50 {pct(ms, 50):.1f} ms, "
              f"p95 {pct(ms, 95):.1f} ms")
        print(f"the same questions in process: p50 {pct(local, 50):.1f} ms, p95 {pct(local, 95):.1f} ms; "
              f"service / in-process p50 = {pct(ms, 50) / pct(local, 50):.2f}")
        done, errors, wall, cms = asyncio.run(crowd(url, token, args.room, args.clients, args.per_client))
        print(f"{args.clients} concurrent clients x {args.per_client} questions: {done} requests, {errors} errors, "
              f"{done / wall:.1f} requests/s, p50 {pct(cms, 50):.0f} ms, p95 {pct(cms, 95):.0f} ms")
        if errors:
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
