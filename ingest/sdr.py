"""Spurious detection rejection (paper Sec. IV-C), after the detector's own NMS.

1. irrelevant classes: objects that cannot belong to a persistent indoor scene graph;
2. repetition: an object must be seen in >= MIN_FRAMES frames of its keyframe group;
3. relation voting over the frames of a keyframe group (ties keep all);
4. the relation prior of Eq. 7 from a curated dictionary (`data/relation_prior.json`).
"""
from __future__ import annotations

import json
import math
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, Mapping, Optional, Sequence, Union

import numpy as np

from ingest.detect import Detection
from ingest.model import RelationObservation
from ingest.tracks import Track

RELATION_PRIOR_FILE = Path(__file__).resolve().parent / "data" / "relation_prior.json"

# Authors' code: an object must be detected at least twice.
MIN_FRAMES = 2
# Paper Sec. VII-A: relations with probability below 0.5 are rejected.
RELATION_PROB_THRESHOLD = 0.5

# COCO classes that cannot be part of a persistent indoor scene graph: outdoor things and
# things that move by themselves (the paper's "road, sky, building, moving objects"). Pets and
# people move away between visits, so a graph that keeps them would hold stale entries.
IRRELEVANT_CLASSES = frozenset({
    "person",
    "bicycle", "car", "motorcycle", "airplane", "bus", "train", "truck", "boat",
    "traffic light", "fire hydrant", "stop sign", "parking meter",
    "bird", "cat", "dog", "horse", "sheep", "cow", "elephant", "bear", "zebra", "giraffe",
    "skis", "snowboard", "kite", "surfboard", "frisbee",
})

# Predicates that answer the same question about a pair compete in the vote; predicates of
# different families (ON and SMALLER_THAN) both hold for a cup on a table and must not.
PREDICATE_GROUPS = (
    ("IN", "CONTAINS_OBJ", "ON", "UNDER", "ABOVE", "BELOW"),
    ("NEXT_TO", "NEAR"),
    ("IN_FRONT_OF", "BEHIND", "LEFT_OF", "RIGHT_OF"),
    ("BIGGER_THAN", "SMALLER_THAN"),
)


# --------------------------------------------------------------------------- objects

def reject_irrelevant(detections: Iterable[Detection],
                      irrelevant: Iterable[str] = IRRELEVANT_CLASSES) -> list[Detection]:
    """Drop detections whose best label is irrelevant; strip irrelevant alternatives from the
    others (a box that is most likely a person must not survive as its second guess)."""
    banned = set(irrelevant)
    kept = []
    for d in detections:
        if not d.labels or d.labels[0] in banned:
            continue
        pairs = [(label, score) for label, score in zip(d.labels, d.scores) if label not in banned]
        kept.append(Detection(d.box, [p[0] for p in pairs], [p[1] for p in pairs]))
    return kept


def reject_rare_tracks(tracks: Iterable[Track], min_frames: int = MIN_FRAMES) -> list[Track]:
    """Keep the tracks seen in at least `min_frames` distinct frames of their keyframe group."""
    return [t for t in tracks if t.n_frames >= min_frames]


# --------------------------------------------------------------------------- relation voting

def _group_of(predicate: str, groups: Optional[Sequence[Sequence[str]]]) -> int:
    if groups is None:
        return 0
    for i, group in enumerate(groups):
        if predicate in group:
            return i
    return len(groups)       # an ungrouped predicate competes with the other ungrouped ones


def vote_relations(per_frame_relations: Sequence[Sequence[RelationObservation]],
                   groups: Optional[Sequence[Sequence[str]]] = PREDICATE_GROUPS) -> list[RelationObservation]:
    """Sec. IV-C: per ordered pair, keep the predicates found in the most frames; a tie keeps
    all the top-ranked ones. Votes are counted within each predicate family of `groups`
    (`groups=None`: one vote over all predicates of a pair, the paper's literal rule).
    A predicate counts once per frame; the kept relation's score is its mean over the frames
    that found it."""
    votes: dict[tuple, dict[str, list[float]]] = defaultdict(lambda: defaultdict(list))
    for frame_relations in per_frame_relations:
        seen: dict[tuple[str, str, str], float] = {}
        for r in frame_relations:
            key = (r.subject, r.predicate, r.object)
            seen[key] = max(seen.get(key, 0.0), float(r.score))
        for (s, p, o), score in seen.items():
            votes[(s, o, _group_of(p, groups))][p].append(score)
    kept = []
    for (s, o, _), by_predicate in votes.items():
        top = max(len(v) for v in by_predicate.values())
        for p, scores in by_predicate.items():
            if len(scores) == top:
                kept.append(RelationObservation(s, p, o, sum(scores) / len(scores)))
    return kept


# --------------------------------------------------------------------------- relation prior

def gaussian_pdf(k: float, mu: float, sigma: float) -> float:
    """phi_{mu, sigma^2}(k) of Eq. 7."""
    return math.exp(-0.5 * ((k - mu) / sigma) ** 2) / math.sqrt(2.0 * math.pi * sigma ** 2)


def relation_prior_probability(pr_dict: float, d_pixel: float, mu: float, sigma: float) -> float:
    """Eq. 7: Pr(r | d) = Pr_dict(r | d) * phi_{mu,sigma^2}(d) / phi_{mu,sigma^2}(mu).

    `pr_dict` is the dictionary frequency of the triple; the Gaussian (mu, sigma) describes the
    distances at which the triple makes sense, normalised to 1 at d = mu. The paper measures
    d in pixels; any unit works as long as d, mu and sigma share it (this project's dictionary
    uses metres between 3-D object centres).
    """
    return pr_dict * gaussian_pdf(d_pixel, mu, sigma) / gaussian_pdf(mu, mu, sigma)


@dataclass(frozen=True)
class PriorEntry:
    pr: float
    mu: Optional[float] = None         # metres; None = the triple has no distance model
    sigma: Optional[float] = None

    def probability(self, distance: float) -> float:
        if self.mu is None or self.sigma is None:
            return self.pr
        return relation_prior_probability(self.pr, distance, self.mu, self.sigma)


class RelationPrior:
    """The curated relation dictionary. Lookup order for (s, p, o): exact, (s, p, *),
    (*, p, o), (*, p, *), then the file's `default`."""

    WILDCARD = "*"

    def __init__(self, entries: Mapping[tuple[str, str, str], PriorEntry], default: PriorEntry):
        self.entries = dict(entries)
        self.default = default

    @classmethod
    def load(cls, path: Union[str, Path, None] = None) -> "RelationPrior":
        data = json.loads(Path(path or RELATION_PRIOR_FILE).read_text(encoding="utf-8"))
        entries = {}
        for e in data["relations"]:
            entries[(e["subject"], e["predicate"], e["object"])] = PriorEntry(
                float(e["pr"]), e.get("mu"), e.get("sigma"))
        d = data.get("default", {})
        return cls(entries, PriorEntry(float(d.get("pr", 0.6)), d.get("mu"), d.get("sigma")))

    def lookup(self, subject: str, predicate: str, obj: str) -> PriorEntry:
        w = self.WILDCARD
        for key in ((subject, predicate, obj), (subject, predicate, w), (w, predicate, obj), (w, predicate, w)):
            if key in self.entries:
                return self.entries[key]
        return self.default

    def probability(self, subject: str, predicate: str, obj: str, distance: float) -> float:
        return self.lookup(subject, predicate, obj).probability(distance)


_DEFAULT_PRIOR: Optional[RelationPrior] = None


def default_prior() -> RelationPrior:
    global _DEFAULT_PRIOR
    if _DEFAULT_PRIOR is None:
        _DEFAULT_PRIOR = RelationPrior.load()
    return _DEFAULT_PRIOR


def filter_relations(
    relations: Iterable[RelationObservation],
    labels: Mapping[str, str],
    positions: Mapping[str, Sequence[float]],
    prior: Optional[RelationPrior] = None,
    threshold: float = RELATION_PROB_THRESHOLD,
) -> list[RelationObservation]:
    """Delete relations whose Eq. 7 probability is below `threshold`.

    `labels`: local_id -> best label; `positions`: local_id -> world centre (metres)."""
    prior = prior or default_prior()
    kept = []
    for r in relations:
        distance = float(np.linalg.norm(np.asarray(positions[r.subject], dtype=np.float64)
                                        - np.asarray(positions[r.object], dtype=np.float64)))
        if prior.probability(labels[r.subject], r.predicate, labels[r.object], distance) >= threshold:
            kept.append(r)
    return kept
