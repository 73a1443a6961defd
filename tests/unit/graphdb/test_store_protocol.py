"""The store handle has every member of the GraphStore protocol, with the same parameters."""
from __future__ import annotations

import inspect

from sg3d.graphdb.protocol import GraphStore
from sg3d.graphdb.store import Store


def protocol_methods() -> list[str]:
    return [n for n, v in vars(GraphStore).items() if inspect.isfunction(v) and not n.startswith("_")]


def test_the_store_has_every_method_with_the_protocols_parameters():
    assert {"read", "write", "session", "ensure_schema"} <= set(protocol_methods())
    for name in protocol_methods():
        want = list(inspect.signature(getattr(GraphStore, name)).parameters)
        got = list(inspect.signature(getattr(Store, name)).parameters)
        assert got == want, (name, got, want)


def test_the_protocols_attributes_are_set_by_the_store():
    source = inspect.getsource(Store.__init__)
    for attribute in GraphStore.__annotations__:
        assert f"self.{attribute}" in source, attribute
