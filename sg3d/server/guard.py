"""The door of `sg3d serve`, before any route runs: the token is checked before a byte of the
body is read, a body larger than `max_body` is refused with 413 without being kept, and a JSON
body must be strict JSON (no NaN/Infinity literals) nested at most `bounds.MAX_JSON_DEPTH` deep.

A pure ASGI middleware: it buffers at most `max_body` bytes, then hands the same bytes to the
application, so routes see the body unchanged.
"""
from __future__ import annotations

import json

from sg3d.app import bounds
from sg3d.server.auth import token_matches

OPEN_PATHS = frozenset({"/health", "/openapi.json", "/docs", "/docs/oauth2-redirect", "/redoc"})
TOKEN_HINT = ("missing or wrong token: send Authorization: Bearer <token> "
              "(the token is in $SG3D_HOME/api-token; `sg3d serve` prints where)")


def _reject_constant(name: str):
    raise ValueError(f"{name} is not a JSON number")


def json_problem(body: bytes):
    """Why `body` is not acceptable JSON (a short reason that never repeats it), or None."""
    try:
        value = json.loads(body, parse_constant=_reject_constant)
    except RecursionError:
        return f"the JSON body nests deeper than {bounds.MAX_JSON_DEPTH} levels"
    except ValueError as exc:   # JSONDecodeError is a ValueError; its message names a position only
        return f"the body is not valid JSON: {str(exc)[:120]}"
    if bounds.nesting_depth(value) > bounds.MAX_JSON_DEPTH:
        return f"the JSON body nests deeper than {bounds.MAX_JSON_DEPTH} levels"
    return None


class Guard:
    """ASGI middleware: authentication, then the body size limit, then strict JSON."""

    def __init__(self, app, token: str, max_body: int = bounds.DEFAULT_MAX_BODY):
        self.app = app
        self.token = token
        self.max_body = max_body

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope.get("headers", ())}
        if scope["path"] not in OPEN_PATHS and not token_matches(self.token, headers.get("authorization")):
            return await _reply(send, 401, TOKEN_HINT, [(b"www-authenticate", b"Bearer")])
        declared = headers.get("content-length")
        if declared is not None:
            if not declared.isdigit():
                return await _reply(send, 400, "Content-Length must be a number")
            if int(declared) > self.max_body:
                return await _reply(send, 413, self._too_large())
        if scope["method"] not in ("POST", "PUT", "PATCH"):
            return await self.app(scope, receive, send)
        chunks, size = [], 0
        while True:
            message = await receive()
            if message["type"] == "http.disconnect":
                return
            chunk = message.get("body", b"")
            size += len(chunk)
            if size > self.max_body:
                return await _reply(send, 413, self._too_large())
            chunks.append(chunk)
            if not message.get("more_body", False):
                break
        body = b"".join(chunks)
        if body and "json" in headers.get("content-type", "json"):
            problem = json_problem(body)
            if problem:
                return await _reply(send, 422, problem)
        return await self.app(scope, _replay(body, receive), send)

    def _too_large(self) -> str:
        return f"the request body is larger than {self.max_body} bytes (sg3d serve --max-body)"


def _replay(body: bytes, receive):
    sent = False

    async def again():
        nonlocal sent
        if sent:
            return await receive()
        sent = True
        return {"type": "http.request", "body": body, "more_body": False}
    return again


async def _reply(send, status: int, detail: str, extra_headers=()) -> None:
    payload = json.dumps({"detail": detail}).encode()
    await send({"type": "http.response.start", "status": status,
                "headers": [(b"content-type", b"application/json"),
                            (b"content-length", str(len(payload)).encode()),
                            (b"connection", b"close"), *extra_headers]})
    await send({"type": "http.response.body", "body": payload})
