"""Spurious detection rejection (paper Sec. IV-C), the relation side, after the detector's own NMS.

1. irrelevant classes: objects that cannot belong to a persistent indoor scene graph
   (`sg3d.ingest.detect.irrelevant`, applied to each frame's detections);
2. repetition: an object must be seen often enough where it is visible (`sg3d.ingest.objects.existence`);
3. relation voting over frames, contradiction-free: a pair keeps one placement and one size
   statement, symmetric relations once, and a relation that flips between views is dropped;
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

from sg3d.core.model import RelationObservation
from sg3d.core.relation_rules import SYMMETRIC, Statement, edges_of, statement_of

RELATION_PRIOR_FILE = Path(__file__).resolve().parents[1] / "data" / "relation_prior.json"

# Paper Sec. VII-A: relations with probability below 0.5 are rejected.
RELATION_PROB_THRESHOLD = 0.5

# Relation voting (Sec. IV-C, made contradiction-free; `sg3d.core.relation_rules`): per pair and
# family, the side of the winning statement (lo over/in hi, hi over/in lo, side by side; lo
# bigger, hi bigger) must hold in at least this share of the frames that stated any of them,
# else the relation flips between views and is not stored.
VOTE_MAJORITY = 0.6
# With the number of frames in which a pair was co-observed (`co_observed`), the winner must
# also hold in at least this share of them: a relation seen once in twenty shared views is noise.
VOTE_MIN_SUPPORT = 0.25

# --------------------------------------------------------------------------- relation voting

def vote_relations(per_frame_relations: Sequence[Sequence[RelationObservation]],
                   co_observed: Optional[Mapping[tuple[str, str], int]] = None,
                   majority: float = VOTE_MAJORITY,
                   min_support: float = VOTE_MIN_SUPPORT) -> list[RelationObservation]:
    """Sec. IV-C relation voting over the frames of one observation, contradiction-free.

    Every edge is read as the statement it makes about its unordered pair
    (`sg3d.core.relation_rules.statement_of`; viewpoint relations are dropped). A statement counts
    once per frame. Per pair and family: the side with the most frames wins if it holds in
    >= `majority` of the frames that stated anything of that family about the pair (else the
    relation flips between views: nothing is stored); inside the side, the form with the most
    frames (ties: the more specific, IN > ON > UNDER > ABOVE, NEXT_TO > NEAR). `co_observed`
    ((lo, hi) sorted id pair -> frames in which both were seen), when given, also requires the
    winner in >= `min_support` of those frames. The result is in stored form: one placement and
    one size statement per pair at most, symmetric relations once (subject = smaller id),
    ABOVE with BELOW and BIGGER_THAN with SMALLER_THAN. Score: the winner's mean over its frames.
    """
    # (family, lo, hi) -> form -> {frame index: score}
    votes: dict[tuple[str, str, str], dict[str, dict[int, float]]] = defaultdict(lambda: defaultdict(dict))
    for i, frame_relations in enumerate(per_frame_relations):
        for r in frame_relations:
            st = statement_of(r.subject, r.predicate, r.object)
            if st is not None:
                frames = votes[(st.family, st.lo, st.hi)][st.form]
                frames[i] = max(frames.get(i, 0.0), float(r.score))
    kept = []
    for (family, lo, hi), by_form in votes.items():
        forms = [Statement(family, lo, hi, f) for f in by_form]
        stated = set().union(*(by_form[st.form] for st in forms))
        side_frames: dict[int, set[int]] = defaultdict(set)
        for st in forms:
            side_frames[st.side] |= set(by_form[st.form])
        ranked = sorted(side_frames.values(), key=len, reverse=True)
        if len(ranked) > 1 and len(ranked[0]) == len(ranked[1]):
            continue                                     # a tie between sides: it flips
        side = next(k for k, v in side_frames.items() if v is ranked[0])
        if len(ranked[0]) < majority * len(stated):
            continue
        best = max((st for st in forms if st.side == side), key=lambda st: (len(by_form[st.form]), -st.rank))
        scores = by_form[best.form]
        if co_observed is not None and len(scores) < min_support * co_observed.get((lo, hi), len(stated)):
            continue
        kept.extend(edges_of(best, sum(scores.values()) / len(scores)))
    return kept


def with_whole_geometry(voted: Sequence[RelationObservation],
                        whole: Sequence[RelationObservation]) -> list[RelationObservation]:
    """Relations of the fused objects, vetoed by the views: per pair and family (placement,
    size), the frame vote (`voted`, `vote_relations`) where it decided something, except that a
    placement the whole-sequence boxes state (`whole`: `spatial_relations` of the fused objects;
    on, in, under, above) overrules a voted "side by side"; where the frames stated nothing, the
    whole boxes' statement.

    Why both: a frame sees a big support in part (the end of a table, a cup beyond the visible
    edge), so per-frame placement is often silent or says "beside", while the fused box holds
    every part; but fused boxes of neighbours can swell into each other, so what the views that
    saw the pair together agreed on otherwise stands."""
    def statements(relations: Iterable[RelationObservation]) -> dict[tuple[str, str, str], tuple[Statement, float]]:
        out: dict[tuple[str, str, str], tuple[Statement, float]] = {}
        for r in relations:
            st = statement_of(r.subject, r.predicate, r.object)
            if st is not None:
                out[(st.family, st.lo, st.hi)] = (st, float(r.score))
        return out

    decided = statements(voted)
    for key, (st, score) in statements(whole).items():
        vote = decided.get(key)
        if vote is None or (vote[0].side == 0 and st.side != 0):
            decided[key] = (st, score)
    return [e for st, score in decided.values() for e in edges_of(st, score)]


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

    Per statement (`sg3d.core.relation_rules`), not per edge: a symmetric relation (stored from
    the smaller id) is looked up both ways, and an inverse pair (ABOVE with BELOW, BIGGER_THAN
    with SMALLER_THAN) is kept or deleted whole, at the best probability of its edges.
    `labels`: local_id -> best label; `positions`: local_id -> world centre (metres)."""
    prior = prior or default_prior()
    relations = list(relations)

    def probability(s: str, p: str, o: str) -> float:
        distance = float(np.linalg.norm(np.asarray(positions[s], dtype=np.float64)
                                        - np.asarray(positions[o], dtype=np.float64)))
        ways = [(s, o), (o, s)] if p in SYMMETRIC else [(s, o)]
        return max(prior.probability(labels[a], p, labels[b], distance) for a, b in ways)

    best: dict[tuple, float] = {}          # statement (or a viewpoint edge) -> best probability
    for r in relations:
        st = statement_of(r.subject, r.predicate, r.object)
        key = st if st is not None else (r.subject, r.predicate, r.object)
        best[key] = max(best.get(key, 0.0), probability(r.subject, r.predicate, r.object))
    kept = []
    for r in relations:
        st = statement_of(r.subject, r.predicate, r.object)
        if best[st if st is not None else (r.subject, r.predicate, r.object)] >= threshold:
            kept.append(r)
    return kept
