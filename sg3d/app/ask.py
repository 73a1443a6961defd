"""Ask a question of the stored scene graph: the one call `sg3d ask`, `POST /ask` and the MCP
`ask` tool make."""
from __future__ import annotations

import base64
import logging
from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional, Union

from sg3d.app import bounds
from sg3d.app.errors import AppError
from sg3d.core.errors import Sg3dError
from sg3d.graphdb.protocol import GraphStore

if TYPE_CHECKING:              # the CLI imports queries only when it answers
    from sg3d.queries.vqa import Answer


# What a question may hold, and a room or building it names (a name, or a building/room id).
MAX_QUESTION_CHARS = 2000
MAX_SCOPE_CHARS = 2 * bounds.MAX_NAME_CHARS + 1


def input_problem(question: object, room: object = None, building: object = None) -> Optional[str]:
    """Why these cannot be asked, or None: each a text within its length (the reason names the
    length and the limit, never the value)."""
    if question is None:
        return "question must be a text"
    return bounds.length_problem((("question", question, MAX_QUESTION_CHARS), ("room", room, MAX_SCOPE_CHARS),
                                  ("building", building, MAX_SCOPE_CHARS)))


@dataclass
class Asked:
    answer: Answer
    picture: Optional[str] = None       # where the answer's picture was written, if it was

    @property
    def ok(self) -> bool:
        return self.answer.ok

    def to_json(self, inline_thumbnail: bool = False) -> dict:
        """The JSON of `sg3d ask --json`; `inline_thumbnail` adds the stored JPEG as base64
        (for callers on another machine, who cannot open the server's picture file)."""
        data = self.answer.to_json()
        data["thumbnail"] = self.picture
        if inline_thumbnail:
            thumb = self.answer.thumbnail
            data["thumbnail_jpeg_base64"] = base64.b64encode(bytes(thumb)).decode() if thumb else None
        return data


def parse_viewpoint(text: Optional[str]) -> Optional[dict]:
    """"X,Y,Z" -> a point in the room's world frame; text without a comma -> an object's name
    (no name has a comma, so "1,2" or "1,2,z" is a mistyped point: AppError)."""
    if not text:
        return None
    if "," not in text:
        return {"object": text.strip()}
    parts = text.split(",")
    try:
        if len(parts) == 3:
            return {"position": [float(p) for p in parts]}
    except ValueError:
        pass
    raise AppError(f"--viewpoint {text!r}: give a point as X,Y,Z (three numbers, metres) or an object's name")


def ask(store: GraphStore, question: str, room: Optional[str] = None, building: Optional[str] = None,
        picture: Union[bool, str] = False, viewpoint: Optional[dict] = None) -> Asked:
    """Answer `question` (read-only). With `picture` (True: a temporary .png, or a path), a "show
    me"/"which is the biggest" answer's thumbnail is written there. AppError for a bad picture path.
    `viewpoint` ({"pose": 4x4} | {"position": [x, y, z]} | {"object": name}): where "in front
    of / behind / left of / right of" are seen from."""
    problem = input_problem(question, room, building)
    if problem:
        raise AppError(problem)
    from sg3d.queries.answer.picture import write_picture
    from sg3d.queries.vqa import answer

    # the question is read once; one about re-scans (its reading in `Answer.change`) is answered
    # from the scans' history. Every read of the answer goes in one read transaction (`GraphStore.reading`)
    def answered():
        read = answer(store, question, room=room, building=building, viewpoint=viewpoint)
        return read if read.change is None else _from_history(store, question, read, room, building)

    try:
        result = store.reading(answered)
    except Exception as exc:
        if not _question_failure(exc):
            raise
        result = _refused(question, exc)
    path, out = None, picture if isinstance(picture, str) else None
    if (picture is True or out is not None) and result.ok and result.thumbnail:
        try:
            path = write_picture(result.thumbnail, out)
        except ValueError as exc:
            raise AppError(str(exc)) from exc
        except OSError as exc:
            raise AppError(f"cannot write the picture to {out}: {exc.strerror or exc}") from exc
    return Asked(result, path)


def _from_history(store: GraphStore, question: str, read, room: Optional[str], building: Optional[str]):
    """A question about re-scans (`read.change`, as the reader read it) answered from the scans'
    history; a refusal names the words as typed."""
    from sg3d.app.changes import change_answer
    from sg3d.queries.vqa import Refusal, change_query, history_refusal, own_words

    asked = read.change
    try:
        cq = change_query(asked.form)
    except Refusal as exc:
        result = history_refusal(question, asked, exc)
    else:
        result = change_answer(store, question, cq, room=room, building=building)
        result.logical, result.plan = asked.form.form(), "history"
    if not result.ok:
        result.text = own_words(question, asked.phrased, result.text)
    return result


def _question_failure(exc: Exception) -> bool:
    """An exception of the code that reads and answers a question (a bug there: a lark
    VisitError, a StopIteration, a KeyError ...), not an AppError nor a failure of the store,
    its driver or the disk, which keep their own handling in each front end."""
    if isinstance(exc, (AppError, OSError, MemoryError)):
        return False
    module = type(exc).__module__ or ""
    if isinstance(exc, Sg3dError):
        return module.startswith("sg3d.queries")
    return not module.startswith(("sg3d.graphdb", "neo4j"))


def _refused(question: str, exc: Exception) -> "Answer":
    """A question whose reading or answering failed: one line refusing it (the failure is logged
    with its traceback, never shown)."""
    from sg3d.queries.vqa import Answer

    word = getattr(exc, "word", None)
    at = f" past '{word}'" if word else ""
    logging.getLogger("sg3d.queries").warning("answering %r failed: %s: %s", question, exc.__class__.__name__, exc,
                                              exc_info=(type(exc), exc, exc.__traceback__))
    return Answer(question, False, f"I could not read this question{at} ({exc.__class__.__name__}); "
                                   "please rephrase it")
