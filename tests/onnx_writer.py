"""A tiny ONNX writer: protobuf wire format by hand (no `onnx` package needed) for test models."""
from __future__ import annotations

import numpy as np

FLOAT = 1  # TensorProto.DataType.FLOAT
INT64 = 7


def _varint(n: int) -> bytes:
    out = bytearray()
    n &= (1 << 64) - 1
    while True:
        byte = n & 0x7F
        n >>= 7
        if n:
            out.append(byte | 0x80)
        else:
            out.append(byte)
            return bytes(out)


def _key(field: int, wire: int) -> bytes:
    return _varint(field << 3 | wire)


def _int(field: int, value: int) -> bytes:
    return _key(field, 0) + _varint(value)


def _bytes(field: int, data: bytes) -> bytes:
    return _key(field, 2) + _varint(len(data)) + data


def _str(field: int, text: str) -> bytes:
    return _bytes(field, text.encode("utf-8"))


def tensor(name: str, array: np.ndarray) -> bytes:
    """TensorProto: dims=1, data_type=2, name=8, raw_data=9 (little-endian)."""
    array = np.asarray(array)
    dtype = FLOAT if array.dtype.kind == "f" else INT64
    raw = array.astype("<f4" if dtype == FLOAT else "<i8").tobytes()
    return b"".join(_int(1, d) for d in array.shape) + _int(2, dtype) + _str(8, name) + _bytes(9, raw)


def value_info(name: str, shape) -> bytes:
    """ValueInfoProto{name=1, type=2: TypeProto{tensor_type=1: {elem_type=1, shape=2}}}."""
    dims = b"".join(_bytes(1, _int(1, d)) for d in shape)
    return _str(1, name) + _bytes(2, _bytes(1, _int(1, FLOAT) + _bytes(2, dims)))


def attr_ints(name: str, values) -> bytes:
    """AttributeProto{name=1, ints=8, type=20 (INTS=7)}."""
    return _str(1, name) + b"".join(_int(8, v) for v in values) + _int(20, 7)


def attr_int(name: str, value: int) -> bytes:
    """AttributeProto{name=1, i=3, type=20 (INT=2)}."""
    return _str(1, name) + _int(3, value) + _int(20, 2)


def node(op: str, inputs, outputs, *attributes: bytes) -> bytes:
    """NodeProto{input=1, output=2, name=3, op_type=4, attribute=5}."""
    return (b"".join(_str(1, i) for i in inputs) + b"".join(_str(2, o) for o in outputs)
            + _str(3, outputs[0]) + _str(4, op) + b"".join(_bytes(5, a) for a in attributes))


def model(nodes, initializers, inputs, outputs, opset: int = 13) -> bytes:
    """ModelProto{ir_version=1, producer_name=2, graph=7, opset_import=8}."""
    graph = (b"".join(_bytes(1, n) for n in nodes) + _str(2, "test")
             + b"".join(_bytes(5, t) for t in initializers)
             + b"".join(_bytes(11, v) for v in inputs) + b"".join(_bytes(12, v) for v in outputs))
    return _int(1, 7) + _str(2, "sg3d-tests") + _bytes(7, graph) + _bytes(8, _str(1, "") + _int(2, opset))
