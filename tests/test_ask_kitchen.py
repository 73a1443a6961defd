"""The compositional questions of benchmarks/questions_kitchen.txt and a second person's
paraphrases (benchmarks/paraphrases_kitchen.txt) on the real kitchen, built fresh, each judged by
an oracle over the built graph (benchmarks/questions_kitchen.py)."""
from __future__ import annotations

import pytest

from benchmarks.questions_kitchen import load_questions, run
from tests.cli_helpers import sg3d


@pytest.fixture(scope="module")
def kitchen_store(tmp_path_factory, kitchen_dir):
    from sg3d.graphdb.embedded import EmbeddedServer
    from sg3d.graphdb.store import Store

    home = tmp_path_factory.mktemp("ask-kitchen")
    out = sg3d(home, "build", kitchen_dir, "--room", "kitchen")
    assert out.returncode == 0, out.stderr
    server = EmbeddedServer(home)
    info = server.ensure_running()
    store = Store(info.uri, (info.user, info.password), info.database)
    yield store
    store.close()
    server.stop()


def test_compositional_questions_on_the_kitchen(kitchen_store):
    rows = run(kitchen_store, "default/kitchen", "kitchen", load_questions())
    assert len(rows) >= 40 and sum(r["paraphrase"] for r in rows) >= 15
    wrong = [(r["question"], r["answer"], r["truth"]) for r in rows if not r["right"]]
    assert len(wrong) <= len(rows) // 10, wrong
    # nothing read silently: every answer that passed over words says so, and none is a number
    # answer to a question the grammar refused
    assert sum(r["answer"].startswith("refused") for r in rows) <= 2, wrong
