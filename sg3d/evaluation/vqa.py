"""VQA accuracy of `sg3d.queries.vqa.answer` against ground-truth questions (`sg3d eval`).

Only questions the annotator marked `sure` are scored. A question counts as unsupported when
the VQA module is absent, raises, or returns no answer; unsupported questions are listed, never
counted as right. Answers are compared by form: numbers exactly, yes/no exactly, one-word answers
(a colour) as a word of the reply; longer free-text GT answers are scored only when they cite GT
object ids and the reply names graph nodes, which the matching turns into GT ids.
"""
from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any, Callable, Optional

from sg3d.evaluation.ground_truth import GroundTruth, GTQuestion
from sg3d.evaluation.matching import Matching
from sg3d.graphdb.values import jsonable

if TYPE_CHECKING:
    from sg3d.graphdb.protocol import GraphStore

YES_NO = {"yes": "yes", "no": "no", "true": "yes", "false": "no"}


def load_answerer() -> Optional[Callable]:
    try:
        from sg3d.queries.vqa import answer  # written separately; may not exist yet
    except ImportError:
        return None
    return answer


def _reply_value(reply: Any) -> Any:
    """The answer inside whatever the VQA returns: a value, a dict, an object with .answer, or
    `sg3d.queries.vqa.Answer` (its .value; a refusal, ok=False, is no answer)."""
    if isinstance(reply, dict):
        return reply.get("answer", reply.get("value"))
    if hasattr(reply, "ok") and hasattr(reply, "value"):
        return reply.value if reply.ok else None
    return getattr(reply, "answer", reply)


def _reply_nodes(reply: Any) -> list[str]:
    for key in ("nodes", "node_ids", "ids", "objects"):
        value = reply.get(key) if isinstance(reply, dict) else getattr(reply, key, None)
        if isinstance(value, (list, tuple)):
            return [v if isinstance(v, str) else str(v.get("id")) if isinstance(v, dict) else str(v) for v in value]
    return []


def _as_number(value: Any) -> Optional[float]:
    if isinstance(value, bool):
        return None
    if isinstance(value, (int, float)):
        return float(value)
    m = re.fullmatch(r"\s*(-?\d+(?:\.\d+)?)\s*", str(value))
    return float(m.group(1)) if m else None


def score(question: GTQuestion, reply: Any, matching: Matching, gt_ids: set[str]) -> Optional[bool]:
    """True/False, or None when this GT answer cannot be compared automatically."""
    expected, got = question.answer, _reply_value(reply)
    if isinstance(expected, (int, float)) and not isinstance(expected, bool):
        n = _as_number(got)
        return n is not None and n == float(expected)
    text = str(expected).strip().lower()
    if isinstance(expected, bool) or text in YES_NO:
        want = YES_NO.get(text, "yes" if expected is True else "no")
        said = YES_NO.get(str(got).strip().lower()) if not isinstance(got, bool) else ("yes" if got else "no")
        return said == want
    if re.fullmatch(r"[a-z-]+", text):
        return text in re.findall(r"[a-z-]+", str(got).lower())
    cited = {t for t in re.findall(r"[A-Za-z0-9_-]+", str(expected)) if t in gt_ids}
    nodes = _reply_nodes(reply)
    if cited and nodes:
        return {matching.node_to_gt.get(n) for n in nodes} == cited
    return None


def vqa_metrics(store: GraphStore, gt: GroundTruth, matching: Matching, room: str, building: str,
                answerer: Optional[Callable] = None) -> dict:
    answerer = answerer if answerer is not None else load_answerer()
    sure = [q for q in gt.questions if q.sure]
    rows, gt_ids = [], set(gt.by_id)
    for q in sure:
        row = {"question": q.text, "kind": q.kind, "expected": q.answer}
        if answerer is None:
            row.update(status="unsupported", reason="VQA not available")
        else:
            try:
                reply = answerer(store, q.text, room=room, building=building)
            except Exception as exc:  # noqa: BLE001 - any failure means "not supported", listed with why
                reply, row["reason"] = None, f"{type(exc).__name__}: {exc}"
            if reply is None or _reply_value(reply) is None:
                row.setdefault("reason", "no answer" + (f": {reply.text}" if isinstance(getattr(reply, "text", None), str) else ""))
                row["status"] = "unsupported"
            else:
                row["got"] = jsonable(_reply_value(reply))
                if isinstance(getattr(reply, "text", None), str):
                    row["answer"] = reply.text       # what a person reads: objects by name, no ids
                verdict = score(q, reply, matching, gt_ids)
                row["status"] = {True: "right", False: "wrong", None: "not scorable"}[verdict]
        rows.append(row)
    scored = [r for r in rows if r["status"] in ("right", "wrong")]
    right = sum(r["status"] == "right" for r in scored)
    return {
        "available": answerer is not None,
        "sure_questions": len(sure),
        "unsure_questions_skipped": len(gt.questions) - len(sure),
        "scored": len(scored),
        "right": right,
        "accuracy": right / len(scored) if scored else None,
        # unsupported and unscorable questions count as wrong here: the honest headline number
        "accuracy_all_sure": right / len(sure) if sure else None,
        "questions": rows,
    }
