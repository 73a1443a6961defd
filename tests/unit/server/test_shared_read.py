"""`SharedRead`: the revision read that the asks arriving together share on the event loop, under
the rule "a read that began after the request arrived" (no store: the read is a counter)."""
from __future__ import annotations

import asyncio

import pytest

from sg3d.server.dispatch import SharedRead


class Reads:
    """A read whose result is the number of reads begun before it ended (the 'revision' it saw)
    and which ends when the test lets it."""

    def __init__(self):
        self.begun = 0
        self.gates: list[asyncio.Event] = []
        self.fail_next = False

    async def read(self) -> int:
        self.begun += 1
        seen = self.begun
        gate = asyncio.Event()
        self.gates.append(gate)
        await gate.wait()
        if self.fail_next:
            self.fail_next = False
            raise RuntimeError("store down")
        return seen

    def finish(self) -> None:
        self.gates.pop(0).set()


async def _settle():
    for _ in range(20):
        await asyncio.sleep(0)


def test_asks_arriving_while_a_read_runs_get_the_next_one_begun_after_them():
    async def main():
        reads = Reads()
        shared = SharedRead(reads.read)
        first = asyncio.ensure_future(shared.get())     # no read running: it starts one
        await _settle()
        later = [asyncio.ensure_future(shared.get()) for _ in range(50)]   # arrived while read 1 runs
        await _settle()
        assert reads.begun == 1
        reads.finish()
        await _settle()
        assert first.result() == 1
        assert reads.begun == 2 and not any(f.done() for f in later)      # read 1 began before them
        reads.finish()
        await _settle()
        assert {f.result() for f in later} == {2} and shared.reads == 2
        assert asyncio.ensure_future(shared.get()) and (await _settle()) is None and reads.begun == 3
        reads.finish()
    asyncio.run(main())


def test_a_failed_read_fails_every_ask_waiting_on_it_and_the_next_ask_reads_again():
    async def main():
        reads = Reads()
        shared = SharedRead(reads.read)
        waiting = [asyncio.ensure_future(shared.get())]
        await _settle()
        waiting += [asyncio.ensure_future(shared.get()) for _ in range(3)]
        await _settle()
        reads.fail_next = True
        reads.finish()          # read 1 fails: its ask fails; the three after it wait for read 2
        await _settle()
        with pytest.raises(RuntimeError, match="store down"):
            waiting[0].result()
        reads.fail_next = True
        reads.finish()
        await _settle()
        for f in waiting[1:]:
            with pytest.raises(RuntimeError, match="store down"):
                f.result()
        again = asyncio.ensure_future(shared.get())
        await _settle()
        reads.finish()
        assert await again == 3
    asyncio.run(main())


def test_an_ask_that_goes_away_leaves_the_read_to_the_others():
    async def main():
        reads = Reads()
        shared = SharedRead(reads.read)
        gone = asyncio.ensure_future(shared.get())
        await _settle()
        stays = asyncio.ensure_future(shared.get())
        await _settle()
        gone.cancel()
        await _settle()
        reads.finish()             # read 1 ends with no one waiting for it; read 2 starts for `stays`
        await _settle()
        reads.finish()
        assert await stays == 2 and gone.cancelled()
    asyncio.run(main())
