"""Cold start: household words are resolved from the shipped label vectors, without
loading the label model (sg3d.core.minilm) or torch, and the shipped files stay in step with the
vocabulary they were made from."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]


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
                         capture_output=True, text=True, env=env, cwd=str(Path(__file__).resolve().parents[1]))
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().startswith(str(tmp_path / "sg3d-cache"))
