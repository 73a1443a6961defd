"""Spurious detection rejection: classes, repetition, relation voting, Eq. 7 prior."""
from __future__ import annotations

import math

import pytest

from sg3d.core.model import RELATION_TYPES
from sg3d.core.model import RelationObservation as Rel
from sg3d.ingest.detect.irrelevant import IRRELEVANT_CLASSES, reject_irrelevant
from sg3d.ingest.detect.models import Detection
from sg3d.ingest.relate.sdr import (
    VOTE_MAJORITY,
    PriorEntry,
    RelationPrior,
    default_prior,
    filter_relations,
    relation_prior_probability,
    vote_relations,
)


def det(labels, scores, box=(0, 0, 10, 10)):
    return Detection(box, list(labels), list(scores))


def test_irrelevant_classes_are_rejected_and_stripped():
    dets = [
        det(["person", "chair"], [0.9, 0.3]),
        det(["car"], [0.5]),
        det(["chair", "person", "bench"], [0.8, 0.2, 0.1]),
        det(["cup"], [0.6]),
    ]
    kept = reject_irrelevant(dets)
    assert [d.labels for d in kept] == [["chair", "bench"], ["cup"]]
    assert kept[0].scores == [0.8, 0.1]
    assert {"person", "car", "bus", "truck", "bird", "horse", "traffic light"} <= IRRELEVANT_CLASSES
    assert not {"cup", "chair", "dining table", "tv", "refrigerator"} & IRRELEVANT_CLASSES
    # the list is configurable
    assert [d.label for d in reject_irrelevant(dets, irrelevant={"cup"})] == ["person", "car", "chair"]


def as_set(relations):
    return {(r.subject, r.predicate, r.object) for r in relations}


def test_vote_keeps_the_majority_statement_in_stored_form():
    frames = [
        [Rel("cup", "ON", "table", 0.9), Rel("cup", "SMALLER_THAN", "table", 0.8)],
        [Rel("cup", "ON", "table", 0.7), Rel("cup", "SMALLER_THAN", "table", 0.8)],
        [Rel("cup", "ABOVE", "table", 0.5), Rel("table", "BELOW", "cup", 0.5),
         Rel("table", "BIGGER_THAN", "cup", 0.8)],
    ]
    kept = vote_relations(frames)
    # ON and ABOVE say the same side (the cup over the table): the more voted one is kept, alone;
    # the size statement is stored as its two edges
    assert as_set(kept) == {("cup", "ON", "table"), ("cup", "SMALLER_THAN", "table"),
                            ("table", "BIGGER_THAN", "cup")}
    on = next(r for r in kept if r.predicate == "ON")
    assert on.score == pytest.approx(0.8)


def test_vote_resolves_contradictions():
    frames = [[Rel("a", "ON", "b")]] * 4 + [[Rel("b", "ON", "a")]]
    assert as_set(vote_relations(frames)) == {("a", "ON", "b")}
    frames = [[Rel("a", "ABOVE", "b"), Rel("b", "BELOW", "a")]] * 3 + [[Rel("a", "BELOW", "b")]]
    assert as_set(vote_relations(frames)) == {("a", "ABOVE", "b"), ("b", "BELOW", "a")}
    # ON the wrong way round vs UNDER: "b UNDER a" says a is over b, as does "a ON b"
    frames = [[Rel("a", "ON", "b")]] * 2 + [[Rel("b", "UNDER", "a")]] + [[Rel("a", "UNDER", "b")]]
    assert as_set(vote_relations(frames)) == {("a", "ON", "b")}
    # next to in most frames, stacked in one: side by side
    frames = [[Rel("a", "NEXT_TO", "b")]] * 3 + [[Rel("a", "ON", "b")]]
    assert as_set(vote_relations(frames)) == {("a", "NEXT_TO", "b")}
    # bigger one way in most frames
    frames = [[Rel("a", "BIGGER_THAN", "b")]] * 3 + [[Rel("b", "BIGGER_THAN", "a")]]
    assert as_set(vote_relations(frames)) == {("a", "BIGGER_THAN", "b"), ("b", "SMALLER_THAN", "a")}


def test_vote_drops_relations_that_flip_between_views():
    assert vote_relations([[Rel("a", "ON", "b")]] * 3 + [[Rel("b", "ON", "a")]] * 3) == []
    # 5 of 9 frames (56 %) is below the majority share
    assert VOTE_MAJORITY > 5 / 9
    assert vote_relations([[Rel("a", "ON", "b")]] * 5 + [[Rel("a", "UNDER", "b")]] * 4) == []
    # a relation seen in 2 of the 12 frames where the pair was co-observed is not kept ...
    frames = [[Rel("a", "ON", "b")]] * 2
    assert vote_relations(frames, co_observed={("a", "b"): 12}) == []
    # ... but is when those were the only shared views
    assert as_set(vote_relations(frames, co_observed={("a", "b"): 2})) == {("a", "ON", "b")}


def test_vote_stores_symmetric_relations_once_without_clutter():
    frames = [
        [Rel("b", "NEXT_TO", "a", 0.6)],
        [Rel("a", "NEXT_TO", "b", 0.8), Rel("b", "NEXT_TO", "a", 0.8)],
        [Rel("a", "NEAR", "b", 0.7)],
        [Rel("a", "ON", "c", 0.9)],
    ]
    kept = vote_relations(frames)
    assert as_set(kept) == {("a", "NEXT_TO", "b"), ("a", "ON", "c")}
    # a tie between NEXT_TO and NEAR keeps the more specific NEXT_TO, never both
    tie = [[Rel("a", "NEXT_TO", "b")], [Rel("b", "NEAR", "a")]]
    assert as_set(vote_relations(tie)) == {("a", "NEXT_TO", "b")}


def test_vote_never_keeps_viewpoint_relations():
    frames = [[Rel("a", "IN_FRONT_OF", "b"), Rel("b", "BEHIND", "a"), Rel("a", "LEFT_OF", "b")]] * 3
    assert vote_relations(frames) == []


def test_vote_counts_a_predicate_once_per_frame():
    frames = [[Rel("a", "NEAR", "b"), Rel("a", "NEAR", "b"), Rel("b", "NEAR", "a")],
              [Rel("a", "NEXT_TO", "b")], [Rel("a", "NEXT_TO", "b")]]
    assert as_set(vote_relations(frames)) == {("a", "NEXT_TO", "b")}


def test_eq7_on_hand_made_numbers():
    # Pr = 0.8 * phi(1.5) / phi(1.0) with mu = 1, sigma = 0.5: exp(-0.5 * 1^2) = 0.60653...
    assert relation_prior_probability(0.8, 1.5, 1.0, 0.5) == pytest.approx(0.8 * 0.6065306597, rel=1e-9)
    # at the mean the distance term is 1
    assert relation_prior_probability(0.9, 2.0, 2.0, 0.3) == pytest.approx(0.9)
    # symmetric, two sigmas away: exp(-2) = 0.135335...
    assert relation_prior_probability(1.0, 40.0, 100.0, 30.0) == pytest.approx(0.1353352832, rel=1e-9)
    assert relation_prior_probability(1.0, 160.0, 100.0, 30.0) == pytest.approx(0.1353352832, rel=1e-9)


def test_relation_prior_lookup_order_and_default():
    prior = RelationPrior({
        ("cup", "ON", "dining table"): PriorEntry(0.9, 0.7, 0.5),
        ("dining table", "ON", "*"): PriorEntry(0.1),
        ("*", "ON", "cup"): PriorEntry(0.3),
        ("*", "BIGGER_THAN", "*"): PriorEntry(0.7),
    }, default=PriorEntry(0.6))
    assert prior.probability("cup", "ON", "dining table", 0.7) == pytest.approx(0.9)
    assert prior.probability("cup", "ON", "dining table", 1.2) == pytest.approx(0.9 * math.exp(-0.5))
    assert prior.probability("dining table", "ON", "cup", 0.5) == pytest.approx(0.1)   # (s, p, *) first
    assert prior.probability("spoon", "ON", "cup", 0.1) == pytest.approx(0.3)
    assert prior.probability("cup", "BIGGER_THAN", "spoon", 9.0) == pytest.approx(0.7)
    assert prior.probability("vase", "NEAR", "clock", 9.0) == pytest.approx(0.6)


def test_shipped_dictionary_is_valid_and_covers_kitchen_triples():
    prior = default_prior()
    assert len(prior.entries) > 50
    for (s, p, o), e in prior.entries.items():
        assert p in RELATION_TYPES
        assert 0.0 <= e.pr <= 1.0
        assert (e.mu is None) == (e.sigma is None)
        assert e.sigma is None or e.sigma > 0
    for s in ("cup", "bowl", "bottle", "wine glass", "fork", "knife", "spoon"):
        assert (s, "ON", "dining table") in prior.entries
    assert ("chair", "NEXT_TO", "dining table") in prior.entries
    assert prior.default.pr > 0.5 and prior.default.mu is None


def test_filter_relations_with_the_shipped_prior():
    labels = {"c": "cup", "t": "dining table", "k": "chair", "v": "vase", "w": "clock"}
    positions = {"c": (0.3, 0.2, 0.8), "t": (0.0, 0.0, 0.375), "k": (0.0, 0.8, 0.45),
                 "v": (5.0, 5.0, 1.0), "w": (9.0, 5.0, 1.0)}
    relations = [
        Rel("c", "ON", "t"),            # plausible at 0.5 m: kept
        Rel("t", "ON", "c"),            # implausible triple: deleted
        Rel("k", "NEXT_TO", "t"),       # plausible: kept
        Rel("v", "NEAR", "w"),          # unlisted: neutral default keeps it
    ]
    kept = filter_relations(relations, labels, positions)
    assert as_set(kept) == {("c", "ON", "t"), ("k", "NEXT_TO", "t"), ("v", "NEAR", "w")}
    # the same ON at an implausible 3 m distance is deleted by the Gaussian term
    far = dict(positions, c=(3.0, 0.0, 0.8))
    assert as_set(filter_relations([Rel("c", "ON", "t")], labels, far)) == set()


def test_filter_reads_symmetric_relations_both_ways_and_keeps_inverse_pairs_whole():
    prior = RelationPrior({
        ("chair", "NEXT_TO", "dining table"): PriorEntry(0.9),
        ("dining table", "NEXT_TO", "*"): PriorEntry(0.1),
        ("tv", "ABOVE", "shelf"): PriorEntry(0.9),
        ("shelf", "BELOW", "tv"): PriorEntry(0.2),
    }, default=PriorEntry(0.6))
    labels = {"a": "dining table", "b": "chair", "t": "tv", "s": "shelf"}
    positions = {k: (0.0, 0.0, 0.0) for k in labels}
    # stored from the smaller id "a" (the table): the chair->table entry still applies
    assert as_set(filter_relations([Rel("a", "NEXT_TO", "b")], labels, positions, prior)) == {("a", "NEXT_TO", "b")}
    pair = [Rel("t", "ABOVE", "s"), Rel("s", "BELOW", "t")]
    assert as_set(filter_relations(pair, labels, positions, prior)) == {("t", "ABOVE", "s"), ("s", "BELOW", "t")}


def test_whole_sequence_placement_overrules_a_voted_beside_and_fills_silence():
    from sg3d.ingest.relate.sdr import with_whole_geometry

    voted = [Rel("book", "NEXT_TO", "table", 0.6),             # partial table boxes: "beside"
             Rel("cup", "ON", "table", 0.8),                     # the views saw it on the table
             Rel("chair", "NEAR", "cup", 0.5)]
    whole = [Rel("book", "ON", "table", 0.7),                   # the fused boxes: on the table
             Rel("cup", "NEXT_TO", "table", 0.9),               # swollen boxes: overruled by the views
             Rel("chair", "NEXT_TO", "cup", 0.9),               # same side as the vote: the vote stands
             Rel("chair", "NEXT_TO", "table", 0.8)]             # never stated by a frame: taken
    kept = as_set(with_whole_geometry(voted, whole))
    assert kept == {("book", "ON", "table"), ("cup", "ON", "table"), ("chair", "NEAR", "cup"),
                    ("chair", "NEXT_TO", "table")}
    # an inverse pair arrives whole: one statement, both of its edges
    both = as_set(with_whole_geometry([], [Rel("tv", "ABOVE", "shelf", 0.7), Rel("shelf", "BELOW", "tv", 0.7)]))
    assert both == {("tv", "ABOVE", "shelf"), ("shelf", "BELOW", "tv")}


# --------------------------------------------------------------------------- each threshold, on both sides

def _frames(on: int, under: int, silent: int = 0):
    """Frames stating the cup ON the table, frames stating it UNDER, frames stating nothing."""
    return [[Rel("cup", "ON", "table", 0.9)]] * on + [[Rel("cup", "UNDER", "table", 0.9)]] * under + [[]] * silent


def test_a_side_is_kept_when_it_holds_in_60_percent_of_the_frames_that_stated_one():   # VOTE_MAJORITY
    assert as_set(vote_relations(_frames(13, 7))) == {("cup", "ON", "table")}           # 65 %
    assert vote_relations(_frames(11, 9)) == []                                          # 55 %


def test_a_relation_must_hold_in_a_quarter_of_the_frames_that_saw_the_pair():   # VOTE_MIN_SUPPORT
    seen_together = {("cup", "table"): 20}
    assert as_set(vote_relations(_frames(6, 0, 14), seen_together)) == {("cup", "ON", "table")}   # 30 %
    assert vote_relations(_frames(4, 0, 16), seen_together) == []                                # 20 %


def test_the_prior_keeps_relations_of_probability_one_half_and_more():   # RELATION_PROB_THRESHOLD
    labels, positions = {"c": "cup", "t": "dining table"}, {"c": (0, 0, 1), "t": (0, 0, 0)}

    def kept(pr):
        prior = RelationPrior({}, default=PriorEntry(pr))
        return as_set(filter_relations([Rel("c", "ON", "t")], labels, positions, prior))
    assert kept(0.52) == {("c", "ON", "t")}
    assert kept(0.48) == set()
