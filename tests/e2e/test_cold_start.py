"""Cold start: household words are resolved from the shipped label vectors, without
loading the label model (sg3d.core.minilm) or torch, and the shipped files stay in step with the
vocabulary they were made from."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]


def test_shipped_vectors_cover_the_vocabulary_and_are_unit_vectors():
    from sg3d.core.embedding import shipped_vectors
    sys.path.insert(0, str(REPO / "scripts"))
    from make_label_vectors import words

    vecs = shipped_vectors()
    assert sorted(vecs) == words(), "run scripts/make_label_vectors.py after editing the word lists"
    norms = np.linalg.norm(np.stack(list(vecs.values())), axis=1)
    assert np.allclose(norms, 1.0, atol=1e-2) and len(vecs) > 800


def test_a_household_word_outside_the_categories_needs_no_torch(tmp_path):
    code = ("import sys\n"
            "from sg3d.queries.lexicon import resolve\n"
            "for w in ('plates', 'kettles', 'coffee tables', 'armchairs', 'cupboard'):\n"
            "    t, why = resolve(w)\n"
            "    assert t is not None, why\n"
            "assert 'torch' not in sys.modules and 'sentence_transformers' not in sys.modules\n"
            "assert 'transformers' not in sys.modules and 'safetensors' not in sys.modules\n"
            "assert 'sg3d.core.minilm' not in sys.modules      # the model is not even loaded\n"
            "print('ok')\n")
    env = dict(os.environ, SG3D_CACHE=str(tmp_path), PYTHONPATH=str(REPO))
    res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, cwd=REPO)
    assert res.returncode == 0 and res.stdout.strip() == "ok", res.stderr
    assert res.stderr == ""


def test_the_label_cache_survives_labels_named_like_savez_arguments(tmp_path):
    from sg3d.core.embedding import _DiskCachedEmbedding

    class Fixed(_DiskCachedEmbedding):
        name = "fixed"

        def _encode(self, labels):
            return np.ones((len(labels), 4), np.float32)

    Fixed(tmp_path).vectors(["file", "allow_pickle", "cup"])        # np.savez(file, ...) clashed on "file"
    again = Fixed(tmp_path)
    again._encode = None                                              # must come from disk now
    assert set(again.vectors(["file", "cup"])) == {"file", "cup"}


def test_the_label_cache_lives_in_sg3d_home(tmp_path):
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if k not in ("SG3D_CACHE",)}
    env["SG3D_HOME"] = str(tmp_path)
    out = subprocess.run([sys.executable, "-c", "from sg3d.core.embedding import default_embedding as d; "
                                                "print(d()._cache_file)"],
                         capture_output=True, text=True, env=env, cwd=str(Path(__file__).resolve().parents[2]))
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().startswith(str(tmp_path / "sg3d-cache"))


def test_the_shipped_question_tables_are_current():
    """The parser tables a cold `sg3d ask` loads ship for the grammar and the lark of this
    checkout (else every cold ask builds the tables: 0.7 s)."""
    from sg3d.queries.reader.grammar import build_parser, parser, parser_grammar, shipped_tables

    grammar = parser_grammar()
    hint = "run python scripts/make_query_tables.py after editing the grammar or upgrading lark"
    assert shipped_tables(grammar).is_file(), hint
    built = build_parser(grammar)

    def outcome(lark_parser, text):
        try:
            return lark_parser.parse(text)
        except Exception as exc:  # noqa: BLE001 - the same refusal, at the same place, is the same outcome
            return type(exc).__name__, getattr(exc, "pos_in_stream", None)

    for text in ("how many cups are on the table", "is there a sink", "which chair is the closest to the tv",
                 "how far is the cup from the sink", "what is in the room", "how many is there the"):
        assert outcome(parser(), text) == outcome(built, text), text


def test_a_cold_ask_loads_only_its_command_and_the_shipped_tables(tmp_path):
    """`sg3d ask` imports its own command (not build's or frames' ingest stages) and reads the
    question with the shipped parser tables: nothing is built into the empty label cache."""
    code = ("import sys, click\n"
            "from sg3d.cli import cli\n"
            "assert cli.get_command(click.Context(cli), 'ask') is not None\n"
            "from sg3d.queries.reader.grammar import read\n"
            "read('how many cups are on the table')\n"
            "loaded = sorted(m for m in sys.modules if m.startswith(('sg3d.ingest', 'sg3d.commands.')))\n"
            "assert loaded == ['sg3d.commands.ask'], loaded\n"
            "print('ok')\n")
    env = dict(os.environ, SG3D_CACHE=str(tmp_path), PYTHONPATH=str(REPO))
    res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, cwd=REPO)
    assert res.returncode == 0 and res.stdout.strip() == "ok", res.stderr
    assert res.stderr == ""
    assert list(tmp_path.glob("question-parser-tables-*")) == []


def test_the_command_keeps_pandas_from_the_driver_only():
    """`sg3d` (its `main`) refuses pandas to the neo4j driver's optional-dependency probe, and to
    nothing else: pandas stays importable in the same process."""
    import pytest

    pytest.importorskip("pandas")
    code = ("import sys\n"
            "from sg3d.cli import _DriverWithoutPandas\n"
            "sys.meta_path.insert(0, _DriverWithoutPandas())\n"
            "import neo4j\n"
            "assert 'pandas' not in sys.modules\n"
            "import pandas\n"
            "assert pandas.DataFrame({'a': [1]}).shape == (1, 1)\n"
            "print('ok')\n")
    res = subprocess.run([sys.executable, "-c", code], env=dict(os.environ, PYTHONPATH=str(REPO)),
                         capture_output=True, text=True, cwd=REPO)
    assert res.returncode == 0 and res.stdout.strip() == "ok", res.stderr


def test_the_common_words_are_picked_once_into_the_cache(tmp_path):
    """The typo fixer's common-word list is picked from pyspellchecker's list once and kept whole
    in sg3d's cache; the next process reads the kept file (the same words)."""
    code = ("from sg3d.queries.reader.typos import common_words\n"
            "w = common_words()\n"
            "assert {'sitting', 'cutting', 'kitchen'} <= w\n"
            "print(len(w))\n")
    env = dict(os.environ, SG3D_CACHE=str(tmp_path), PYTHONPATH=str(REPO))
    first = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, cwd=REPO)
    assert first.returncode == 0, first.stderr
    kept = list(tmp_path.glob("common-words-*.txt"))
    assert len(kept) == 1 and kept[0].stat().st_size > 0
    assert not list(tmp_path.glob(".common-words-*"))          # no temporary file left behind
    kept[0].write_text("sitting\ncutting\nkitchen\n")        # the next process reads the kept file
    second = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, cwd=REPO)
    assert second.returncode == 0, second.stderr
    assert second.stdout.strip() == "3" and first.stdout.strip() != "3"
