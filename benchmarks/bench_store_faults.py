"""kill -9 and deletion of the store's files at random moments under a writer (issue 48, item 4).

Each run: a fresh private home, a writer that creates one numbered node per statement for
`--seconds` through the real driver (re-opening the store after an error, as the next sg3d command
would), and one fault at a random moment: kill -9 of the daemon, `rm -rf` of the store folder,
deletion of the database's bucket files (an age-based tmp cleaner), or kill -9 then deletion of the
files. Then a fresh command: the store either refuses to start and says why, or every write it
acknowledged is there. A started store that lacks an acknowledged write is a silent loss.

    python -m benchmarks.bench_store_faults --runs 10 --seconds 20
"""
from __future__ import annotations

import argparse
import json
import os
import random
import shutil
import signal
import tempfile
import time
from pathlib import Path

from benchmarks.common import load_cypher

FAULTS = ("kill9", "rm_store", "rm_files", "kill9_rm_files")


def _fault(kind: str, server) -> None:
    pid = server.status().info.pid
    if kind.startswith("kill9"):
        os.kill(pid, signal.SIGKILL)
        while os.path.exists(f"/proc/{pid}") and server.daemon_pids():
            time.sleep(0.01)
    if kind == "rm_store":
        shutil.rmtree(server.home, ignore_errors=True)
    if kind.endswith("rm_files"):
        for path in server.database_dir.glob("*.bucket"):
            path.unlink(missing_ok=True)


def _writer(home: Path, seconds: float, fault_at: float, kind: str) -> dict:
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.settings import Settings

    server, acked, errors, after = EmbeddedServer(home), [], 0, 0
    store, n, faulted, t0 = None, 0, None, time.monotonic()
    while time.monotonic() - t0 < seconds:
        if faulted is None and time.monotonic() - t0 >= fault_at:
            _fault(kind, server)
            faulted = time.monotonic()
        try:
            if store is None:
                store = Settings(home=home).store()
            store.run_raw(load_cypher("probe_create"), {"n": n}, write=True)
            acked.append(n)
            after += faulted is not None
        except Exception:  # noqa: BLE001 - a refused or dead store: the writer goes on trying
            errors += 1
            if store is not None:
                store.close()
            store = None
            time.sleep(0.2)
        n += 1
    if store is not None:
        store.close()
    return {"acked": acked, "errors": errors, "acked_after_fault": after}


def _afterwards(home: Path, acked: list[int]) -> dict:
    from sg3d.graphdb.embedded import EmbeddedServer, EmbeddedStoreError
    from sg3d.settings import Settings

    EmbeddedServer(home).stop()
    try:
        store = Settings(home=home).store()
    except EmbeddedStoreError as exc:
        return {"outcome": "refused", "why": str(exc)[:160]}
    try:
        _, rows = store.run_raw(load_cypher("probe_numbers"))
    finally:
        store.close()
    present = {r[0] for r in rows}
    missing = [n for n in acked if n not in present]
    return {"outcome": "kept" if not missing else ("silently empty" if not present else "lost writes"),
            "present": len(present), "missing": len(missing)}


def one_run(kind: str, seconds: float, rng: random.Random) -> dict:
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.settings import Settings

    home = Path(tempfile.mkdtemp(prefix="sg3d-faults-")) / "home"
    try:
        Settings(home=home).store().close()
        fault_at = rng.uniform(0.1 * seconds, 0.9 * seconds)
        w = _writer(home, seconds, fault_at, kind)
        result = _afterwards(home, w["acked"])
        EmbeddedServer(home).stop()
        return {"fault": kind, "fault_at_s": round(fault_at, 1), "acked": len(w["acked"]),
                "acked_after_fault": w["acked_after_fault"], **result}
    finally:
        EmbeddedServer(home).stop()
        shutil.rmtree(home.parent, ignore_errors=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--seed", type=int, default=48)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    results = []
    for i in range(args.runs):
        results.append(one_run(FAULTS[i % len(FAULTS)], args.seconds, rng))
        print(json.dumps(results[-1]), flush=True)
    silent = sum(r["outcome"] in ("silently empty", "lost writes") for r in results)
    print(json.dumps({"runs": len(results), "kept": sum(r["outcome"] == "kept" for r in results),
                      "refused": sum(r["outcome"] == "refused" for r in results), "silent_losses": silent}))


if __name__ == "__main__":
    main()
