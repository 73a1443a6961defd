"""The one base of sg3d's own exceptions.

Every failure sg3d raises on purpose derives from `Sg3dError`, so a caller can catch them all with
one clause; each class keeps its own name and message, and its built-in base (ValueError,
RuntimeError) so existing `except ValueError` clauses still hold.
"""
from __future__ import annotations


class Sg3dError(Exception):
    """A failure sg3d raises on purpose, with a message meant for the person using it."""
