"""Statements that compute inside one row (issue 48, item 6), through `sg3d cypher` and MCP.

A private store started with a statement limit of `--limit` seconds (SG3D_STORE_TIMEOUT_S) and
1,000 nodes; each runaway statement goes through the `sg3d cypher` CLI (a fresh process) and
through the MCP server's cypher tool. Measured per call: seconds until the answer (the limit + 2 s
is the bound; for the CLI less the seconds of a `RETURN 1` process, its start-up), then the daemon's CPU (cores busy, over each second) and resident memory for 5 s.

    python -m benchmarks.bench_runaway --limit 5
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks.common import load_cypher

RUNAWAY = {      # name -> benchmarks/cypher/runaway_<file>.cypher
    "triple reduce": "triple_reduce",
    "string reduce": "string_reduce",
    "nested comprehensions": "nested_comprehensions",
    "nested comprehensions, bound in a variable": "nested_comprehensions_variable",
    "comprehensions over collect": "comprehensions_over_collect",
    "list reduce": "list_reduce",
}


def _cpu_s(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


def _afterwards(pid: int, seconds: int = 5) -> dict:
    """Cores busy and resident MB of the daemon over each of the next `seconds` seconds."""
    cores, rss = [], []
    for _ in range(seconds):
        before = _cpu_s(pid)
        time.sleep(1.0)
        cores.append(round(_cpu_s(pid) - before, 2))
        rss.append(round(_rss_mb(pid)))
    return {"cores": cores, "rss_mb": rss}


def _via_cli(home: Path, statement: str) -> tuple[float, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("SG3D_")}
    env["SG3D_HOME"] = str(home)
    t0 = time.monotonic()
    out = subprocess.run([sys.executable, "-m", "sg3d", "cypher", statement], capture_output=True, text=True,
                         env=env, timeout=600)
    return time.monotonic() - t0, (out.stderr.strip().splitlines() or [out.stdout.strip()])[-1][:120]


def _via_mcp(server, statement: str) -> tuple[float, str]:
    import anyio

    t0 = time.monotonic()
    try:
        result = anyio.run(server.call_tool, "cypher", {"statement": statement})
        answer = str(result)[:120]
    except Exception as exc:  # noqa: BLE001 - the tool error is the answer
        answer = str(exc)[:120]
    return time.monotonic() - t0, answer


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--limit", type=float, default=5.0, help="the store's statement limit (s)")
    args = parser.parse_args()
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.server.mcp import build_server
    from sg3d.settings import Settings

    home = Path(tempfile.mkdtemp(prefix="sg3d-runaway-")) / "home"
    os.environ["SG3D_STORE_TIMEOUT_S"] = str(args.limit)
    store = Settings(home=home).store()
    del os.environ["SG3D_STORE_TIMEOUT_S"]
    store.run_raw(load_cypher("probe_create_many"), {"count": 1000}, write=True)
    pid = EmbeddedServer(home).ensure_running().pid
    mcp = build_server(Settings(home=home), timeouts={"cypher": args.limit + 30, "read": 30.0})
    rows = []
    try:
        # what a `sg3d cypher` process takes besides its statement (start-up, connect): RETURN 1
        overhead = min(_via_cli(home, "RETURN 1 AS x")[0] for _ in range(3))
        for name, statement in ((n, load_cypher(f"runaway_{f}")) for n, f in RUNAWAY.items()):
            for via in ("cli", "mcp"):
                seconds, answer = _via_cli(home, statement) if via == "cli" else _via_mcp(mcp, statement)
                in_store = seconds - overhead if via == "cli" else seconds
                row = {"statement": name, "via": via, "answer_s": round(seconds, 2), "in_store_s": round(in_store, 2),
                       "answer": answer, **_afterwards(pid)}
                row["within_limit_plus_2s"] = in_store <= args.limit + 2
                row["idle_and_under_1gb_within_5s"] = any(c < 0.1 and m < 1024
                                                          for c, m in zip(row["cores"], row["rss_mb"]))
                rows.append(row)
                print(json.dumps(row), flush=True)
    finally:
        store.close()
        EmbeddedServer(home).stop()
        shutil.rmtree(home.parent, ignore_errors=True)
    print(json.dumps({"limit_s": args.limit, "cli_overhead_s": round(overhead, 2), "calls": len(rows),
                      "within_limit_plus_2s": sum(r["within_limit_plus_2s"] for r in rows),
                      "idle_and_under_1gb_within_5s": sum(r["idle_and_under_1gb_within_5s"] for r in rows),
                      "load": os.getloadavg()[0]}))


if __name__ == "__main__":
    main()
