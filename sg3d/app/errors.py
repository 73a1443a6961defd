"""Failures of the application layer that a caller can act on; each front end shows them its way
(the CLI as one line with exit status 2, HTTP as 400/404 with a detail, MCP as a tool error)."""
from __future__ import annotations

from sg3d.core.errors import Sg3dError


class AppError(Sg3dError, ValueError):
    """Bad input or a request the store cannot answer (HTTP 400)."""


class NotFound(AppError):
    """The room, building or object asked for is not in the store (HTTP 404)."""


class Refused(AppError):
    """A request this path will not run, e.g. a writing statement on the read-only path (HTTP 403)."""


class MapError(AppError):
    """Bad input to a live map (`sg3d map`): a source that cannot be followed, a room it may not write."""


class RoomBusy(AppError):
    """Another writer (a build, a live map, an ingest) holds the room (HTTP 409)."""
