"""Data-only serialisation of simulation state: FMU states, checkpoints, the monolithic state.

A checkpoint or an FMU state is a file a user may receive: it must never run code when read
(pickle does: a crafted checkpoint ran arbitrary commands on ``wec-cosim resume``). This module
walks a state (nested dicts, lists, tuples, numpy arrays, numbers, strings and the attributes of
the physics objects) into JSON plus raw arrays, and reads it back without importing or calling
anything chosen by the file.

Binary layout, version 1 (all integers little-endian)::

    offset  size  content
    0       8     magic b"WECSTATE"
    8       4     uint32 format version (1)
    12      4     uint32 reserved, 0
    16      8     uint64 H, length of the header
    24      H     header: UTF-8 JSON {"tree": NODE, "arrays": [{"dtype", "shape", "offset", "nbytes"}, ...]}
    24 + H  ...   array data; each array's bytes at its ``offset`` from here (C order)

A NODE is a JSON ``null``, boolean, integer, finite number or string, or a JSON array (a Python
list), or an object tagged by its ``"$"`` key:

* ``{"$": "array", "i": k}``: the k-th array (dtype from a fixed list of numeric types, no objects);
* ``{"$": "tuple" | "set", "items": [...]}``; ``{"$": "dict", "items": [[key, value], ...]}``;
  ``{"$": "deque", "items": [...], "maxlen": n}``;
* ``{"$": "float", "v": "nan" | "inf" | "-inf"}``; ``{"$": "complex", "re": x, "im": y}``;
  ``{"$": "scalar", "i": k}`` (a numpy scalar as a 0-d array);
* ``{"$": "object", "id": n, "class": "module:QualName", "attrs": {name: NODE}}``: an instance;
  with ``"setstate": true`` ``attrs`` is the NODE of what a project class's own ``__getstate__``
  returned, given back to its ``__setstate__`` (e.g. a sparse LU factor rebuilt from its matrix);
  ``{"$": "ref", "id": n}``: the same instance, list or dict again (shared references and cycles);
* ``{"$": "code"}``: a function or method held by an object: not state, the live one is kept;
* ``{"$": "rng", "state": {...}}``: a numpy random generator's bit-generator state.

Reading (:func:`decode`) applies the tree onto a *template*, the live object graph the FMU or
master built from its own specification: an object node is written into the live instance of
the same class (its attributes replaced, attributes the saved instance did not have removed), so
the result equals a deep copy of the saved graph. The file never chooses what gets built: an
instance absent from the template is created (``cls.__new__``, no ``__init__``) only if its class
is on the allow-list of that read, which is

* the classes of the objects in the template itself (the model's own classes), and
* :data:`RESTORABLE`, the project's classes that a model creates as it runs (so a freshly built
  model, the template of a resume, lacks them).

Names are matched against these classes only; nothing is looked up in the modules, imported or
called on the file's say-so, and attribute names of the ``__dunder__`` form are refused. Any other
class named by a file (``subprocess:Popen``, ``os:_wrap_close``, numpy's ``DataSource`` whose
finaliser deletes a folder...) is refused with :class:`StateFormatError`. Functions are never read
from the file.

A formulation or physics object stays serialisable as long as its state is held in attributes of
those kinds: numpy arrays (numeric dtypes), numbers, strings, None, lists/tuples/dicts/sets of
them, and instances of classes defined in the project (or numpy/scipy classes with a ``__dict__``).
Anything else (an open file, a lock, a C object without ``__dict__``) makes :func:`encode` raise
:class:`StateFormatError` naming the attribute path. A class whose instances a model creates
after it is built (a cache filled as it runs) must be added to :data:`RESTORABLE`, or a resumed
run refuses its own state ("not a class of this model").
"""

from __future__ import annotations

import collections
import json
import struct
import sys
import types
from typing import Any

import numpy as np
from scipy.sparse import csc_matrix

MAGIC = b"WECSTATE"
VERSION = 1
_HEAD = struct.Struct("<8sIIQ")
_DTYPES = {"<f8", "<f4", "<i8", "<i4", "<i2", "|i1", "<u8", "<u4", "<u2", "|u1", "|b1", "<c16", "<c8"}
_PROJECT_PACKAGES = ("hydro_fmu", "mbd_fmu", "plain_mbd_fmu", "fmu_base", "orchestrator")
# The project's state-holding classes that a model creates while it runs (absent from a freshly built
# model): the only classes a state may instantiate besides those of the template's own objects.
RESTORABLE = (
    "mbd_fmu.formulations:Factorized",  # the Newton iteration matrix, factorised and kept between steps
    "mbd_fmu.linear_system:ZeroOrderHoldStepper",  # exact discretisations, cached per step size and PTO law
    "mbd_fmu.simulator:FusedBuffers",  # the fused macro step's buffers (saved empty: rebuilt at the next step)
    f"{csc_matrix.__module__}:{csc_matrix.__qualname__}",  # the matrix a sparse Factorized is rebuilt from
)
_CODE = (types.FunctionType, types.BuiltinFunctionType, types.MethodType, types.BuiltinMethodType,
         types.ModuleType, type, np.ufunc, staticmethod, classmethod, property)
_MISSING = object()


class StateFormatError(ValueError):
    """A state cannot be written (an attribute of an unsupported kind) or read (corrupt, foreign, crafted)."""


# ---------------------------------------------------------------------------------------------- writing
def encode(state: Any) -> bytes:
    """The state as bytes in the layout of the module docstring."""
    enc = _Encoder()
    tree = enc.node(state, "state")
    arrays, offset = [], 0
    for a in enc.arrays:
        arrays.append({"dtype": a.dtype.str, "shape": list(a.shape), "offset": offset, "nbytes": a.nbytes})
        offset += a.nbytes
    header = json.dumps({"tree": tree, "arrays": arrays}, separators=(",", ":"), allow_nan=False).encode()
    parts = [_HEAD.pack(MAGIC, VERSION, 0, len(header)), header]
    parts += [np.ascontiguousarray(a).tobytes() for a in enc.arrays]
    return b"".join(parts)


class _Encoder:
    def __init__(self) -> None:
        self.arrays: list[np.ndarray] = []
        self.seen: dict[int, tuple[int, Any]] = {}  # id -> (node id, object kept alive)

    def _array(self, a: np.ndarray, path: str) -> int:
        a = np.asarray(a)
        if a.dtype.byteorder == ">" or a.dtype.str not in _DTYPES:
            native = a.dtype.newbyteorder("<") if a.dtype.kind in "fiucb" else None
            if native is None or native.str not in _DTYPES:
                raise StateFormatError(f"cannot serialise {path}: numpy dtype {a.dtype} is not numeric")
            a = a.astype(native)
        self.arrays.append(a)
        return len(self.arrays) - 1

    def _ref(self, obj: Any) -> dict | None:
        hit = self.seen.get(id(obj))
        return {"$": "ref", "id": hit[0]} if hit is not None else None

    def _remember(self, obj: Any) -> int:
        n = len(self.seen)
        self.seen[id(obj)] = (n, obj)
        return n

    def node(self, obj: Any, path: str) -> Any:  # noqa: C901 - one branch per kind of node
        if obj is None or isinstance(obj, (bool, str)):
            return obj
        if isinstance(obj, (bytes, bytearray)):
            return {"$": "bytes", "i": self._array(np.frombuffer(bytes(obj), dtype=np.uint8), path)}
        if isinstance(obj, int) and not isinstance(obj, np.integer):
            return int(obj)
        if isinstance(obj, float) and not isinstance(obj, np.floating):
            return obj if np.isfinite(obj) else {"$": "float", "v": repr(obj)}
        if isinstance(obj, complex):
            return {"$": "complex", "re": self.node(obj.real, path), "im": self.node(obj.imag, path)}
        if isinstance(obj, np.generic):
            return {"$": "scalar", "i": self._array(np.asarray(obj), path)}
        ref = self._ref(obj)
        if ref is not None:
            return ref
        if isinstance(obj, np.ndarray):
            n = self._remember(obj)
            return {"$": "array", "i": self._array(obj, path), "id": n}
        if isinstance(obj, _CODE) or type(obj).__name__ in ("partial", "cython_function_or_method"):
            return {"$": "code"}
        if isinstance(obj, np.random.Generator):
            self._remember(obj)
            return {"$": "rng", "state": obj.bit_generator.state}
        if isinstance(obj, list):
            n = self._remember(obj)
            return {"$": "list", "id": n, "items": [self.node(v, f"{path}[{i}]") for i, v in enumerate(obj)]}
        if isinstance(obj, tuple):
            return {"$": "tuple", "items": [self.node(v, f"{path}[{i}]") for i, v in enumerate(obj)]}
        if isinstance(obj, (set, frozenset)):
            return {"$": "set", "items": [self.node(v, f"{path}{{}}") for v in sorted(obj, key=repr)]}
        if isinstance(obj, collections.deque):
            n = self._remember(obj)
            return {"$": "deque", "id": n, "maxlen": obj.maxlen,
                    "items": [self.node(v, f"{path}[{i}]") for i, v in enumerate(obj)]}
        if isinstance(obj, dict):
            n = self._remember(obj)
            return {"$": "dict", "id": n, "items": [[self.node(k, f"{path} key"), self.node(v, f"{path}[{k!r}]")]
                                                    for k, v in obj.items()]}
        if isinstance(obj, np.dtype):
            return {"$": "dtype", "str": obj.str}
        cls = type(obj)
        if _custom_state(cls):  # a project class that says itself what its state is (e.g. without a C factor)
            n = self._remember(obj)
            return {"$": "object", "id": n, "class": _class_name(cls), "setstate": True,
                    "attrs": self.node(obj.__getstate__(), f"{path}.__getstate__()")}
        attrs = _attributes(obj)
        if attrs is None:
            raise StateFormatError(f"cannot serialise {path}: {type(obj).__module__}.{type(obj).__qualname__} holds "
                                   "no attributes this format can walk (not a plain data object)")
        n = self._remember(obj)
        return {"$": "object", "id": n, "class": _class_name(cls),
                "attrs": {k: self.node(v, f"{path}.{k}") for k, v in attrs.items()}}


def _custom_state(cls: type) -> bool:
    """A class of this project with its own ``__getstate__`` and ``__setstate__``."""
    return (cls.__module__.split(".")[0] in _PROJECT_PACKAGES and "__setstate__" in _defined(cls)
            and "__getstate__" in _defined(cls))


def _defined(cls: type) -> set[str]:
    return {name for klass in cls.__mro__ if klass is not object for name in vars(klass)}


def _attributes(obj: Any) -> dict[str, Any] | None:
    """Instance attributes (``__dict__`` and ``__slots__``), or None for objects without any."""
    out: dict[str, Any] = {}
    has = False
    if hasattr(obj, "__dict__"):
        out.update(vars(obj))
        has = True
    for klass in type(obj).__mro__:
        for name in getattr(klass, "__slots__", ()):
            if name in ("__dict__", "__weakref__"):
                continue
            has = True
            value = getattr(obj, name, _MISSING)
            if value is not _MISSING:
                out[name] = value
    return out if has else None


# ---------------------------------------------------------------------------------------------- reading
def decode(data: bytes, template: Any = None) -> Any:
    """Read bytes written by :func:`encode`; objects are restored into ``template`` (module docstring).

    Raises :class:`StateFormatError` for anything that is not a valid state of this format.
    """
    header, arrays = read_layout(data)
    dec = _Decoder(arrays, allowed_classes(template))
    try:
        return dec.node(header["tree"], template, "state")
    except StateFormatError:
        raise
    except RecursionError:
        raise StateFormatError("the state is nested too deeply to be a wec-cosim state") from None
    except (KeyError, TypeError, ValueError, IndexError, AttributeError) as exc:
        raise StateFormatError(f"the state's contents are malformed ({type(exc).__name__}: {exc})") from None


def read_layout(data: bytes) -> tuple[dict, list[np.ndarray]]:
    """Check the binary layout and return the header and the arrays (read-only views are copied)."""
    data = bytes(data)
    if len(data) < _HEAD.size:
        raise StateFormatError(f"the state is {len(data)} bytes long, too short for a wec-cosim state")
    magic, version, _, length = _HEAD.unpack_from(data)
    if magic != MAGIC:
        hint = " (an old checkpoint written with pickle: rerun the simulation)" if data[:1] == b"\x80" else ""
        raise StateFormatError(f"not a wec-cosim state: the data does not start with {MAGIC!r}{hint}")
    if version != VERSION:
        raise StateFormatError(f"state format version {version} is not supported (this version reads {VERSION})")
    start = _HEAD.size + length
    if start > len(data):
        raise StateFormatError("the state is truncated (its header runs past the end of the data)")
    try:
        header = json.loads(data[_HEAD.size:start].decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise StateFormatError(f"the state's header is not valid JSON ({type(exc).__name__})") from None
    if not isinstance(header, dict) or not isinstance(header.get("arrays"), list) or "tree" not in header:
        raise StateFormatError("the state's header lacks its 'tree' or 'arrays'")
    arrays = []
    body = memoryview(data)[start:]
    for i, spec in enumerate(header["arrays"]):
        try:
            dtype, shape = spec["dtype"], tuple(int(s) for s in spec["shape"])
            offset, nbytes = int(spec["offset"]), int(spec["nbytes"])
        except (KeyError, TypeError, ValueError):
            raise StateFormatError(f"array {i} of the state has a malformed description") from None
        if dtype not in _DTYPES:
            raise StateFormatError(f"array {i} of the state has dtype {dtype!r}, not one of the numeric types")
        count = int(np.prod(shape, dtype=np.int64)) if shape else 1
        if min(shape, default=0) < 0 or count * np.dtype(dtype).itemsize != nbytes or offset < 0 or \
                offset + nbytes > len(body):
            raise StateFormatError(f"array {i} of the state does not fit its data (shape {shape}, {nbytes} bytes "
                                   f"at {offset}, {len(body)} bytes of data)")
        arrays.append(np.frombuffer(body[offset:offset + nbytes], dtype=dtype).reshape(shape).copy())
    return header, arrays


def peek(data: bytes, key: str) -> Any:
    """The value of a top-level entry ``key`` of a state that is a dict, if it is a plain JSON value
    (None otherwise): lets a reader refuse a foreign state before decoding its objects."""
    header, _ = read_layout(data)
    tree = header["tree"]
    if isinstance(tree, dict) and tree.get("$") == "dict" and isinstance(tree.get("items"), list):
        for pair in tree["items"]:
            if isinstance(pair, list) and len(pair) == 2 and pair[0] == key:
                value = pair[1]
                return value if value is None or isinstance(value, (bool, int, float, str)) else None
    return None


def allowed_classes(template: Any) -> dict[str, type]:
    """The classes a read onto ``template`` may instantiate: those of the template's own objects and
    :data:`RESTORABLE` (among modules already imported), by ``module:QualName``."""
    found: dict[str, type] = {}
    for name in RESTORABLE:
        module_name, _, qualname = name.partition(":")
        cls = getattr(sys.modules.get(module_name), qualname, None)
        if isinstance(cls, type):
            found[name] = cls
    seen: set[int] = set()
    stack = [template]
    while stack:
        obj = stack.pop()
        if obj is None or isinstance(obj, (bool, int, float, complex, str, bytes, np.ndarray, np.generic, np.dtype,
                                           np.random.Generator)) or isinstance(obj, _CODE) or id(obj) in seen:
            continue
        seen.add(id(obj))
        if isinstance(obj, dict):
            stack.extend(obj.keys())
            stack.extend(obj.values())
        elif isinstance(obj, (list, tuple, set, frozenset, collections.deque)):
            stack.extend(obj)
        else:
            attrs = _attributes(obj)
            if attrs is None:
                continue
            found[_class_name(type(obj))] = type(obj)
            if not _custom_state(type(obj)):
                stack.extend(attrs.values())
    return found


class _Decoder:
    def __init__(self, arrays: list[np.ndarray], allowed: dict[str, type]) -> None:
        self.arrays = arrays
        self.allowed = allowed
        self.made: dict[int, Any] = {}  # node id -> object
        self.claimed: set[int] = set()  # ids of live objects already used for some node

    def _array(self, node: dict) -> np.ndarray:
        i = node["i"]
        if not isinstance(i, int) or not 0 <= i < len(self.arrays):
            raise StateFormatError(f"the state refers to array {i!r}, which it does not hold")
        return self.arrays[i].copy()

    def _keep(self, node: dict, obj: Any) -> Any:
        if "id" in node:
            self.made[node["id"]] = obj
        return obj

    def node(self, node: Any, live: Any, path: str) -> Any:  # noqa: C901 - one branch per kind of node
        if node is None or isinstance(node, (bool, int, float, str)):
            return node
        if isinstance(node, list):  # not written by encode (lists are tagged), accepted as a list
            return [self.node(v, None, path) for v in node]
        if not isinstance(node, dict) or "$" not in node:
            raise StateFormatError(f"{path}: unexpected entry in the state")
        kind = node["$"]
        if kind == "ref":
            if node.get("id") not in self.made:
                raise StateFormatError(f"{path}: reference to an entry the state does not define")
            return self.made[node["id"]]
        if kind == "array":
            return self._keep(node, self._array(node))
        if kind == "scalar":
            return self._array(node)[()]
        if kind == "bytes":
            data = self._array(node)
            if data.dtype != np.uint8 or data.ndim != 1:
                raise StateFormatError(f"{path}: bytes stored as {data.dtype} of shape {data.shape}")
            return data.tobytes()
        if kind == "float":
            if node["v"] not in ("nan", "inf", "-inf"):
                raise StateFormatError(f"{path}: bad special float {node['v']!r}")
            return float(node["v"])
        if kind == "complex":
            return complex(float(node["re"]), float(node["im"]))
        if kind == "dtype":
            if node["str"] not in _DTYPES:
                raise StateFormatError(f"{path}: dtype {node['str']!r} is not a numeric type")
            return np.dtype(node["str"])
        if kind == "code":
            if live is _MISSING or live is None:
                raise StateFormatError(f"{path}: the state holds a function where the model has none")
            return live
        if kind == "rng":
            rng = live if isinstance(live, np.random.Generator) else np.random.default_rng()
            try:
                rng.bit_generator.state = node["state"]
            except (TypeError, ValueError, KeyError) as exc:
                raise StateFormatError(f"{path}: bad random generator state ({exc})") from None
            return rng
        if kind in ("list", "tuple", "set", "deque"):
            items = node["items"]
            if not isinstance(items, list):
                raise StateFormatError(f"{path}: malformed {kind}")
            base = list(live) if isinstance(live, (list, tuple, collections.deque)) else []
            if kind == "list":
                out: Any = self._keep(node, [])
                out.extend(self.node(v, base[i] if i < len(base) else None, f"{path}[{i}]")
                           for i, v in enumerate(items))
                return out
            if kind == "deque":
                maxlen = node.get("maxlen")
                if maxlen is not None and not isinstance(maxlen, int):
                    raise StateFormatError(f"{path}: malformed deque")
                out = self._keep(node, collections.deque(maxlen=maxlen))
                out.extend(self.node(v, base[i] if i < len(base) else None, f"{path}[{i}]")
                           for i, v in enumerate(items))
                return out
            values = [self.node(v, base[i] if i < len(base) else None, f"{path}[{i}]") for i, v in enumerate(items)]
            return tuple(values) if kind == "tuple" else set(values)
        if kind == "dict":
            out = self._keep(node, {})
            base = live if isinstance(live, dict) else {}
            for pair in node["items"]:
                if not isinstance(pair, list) or len(pair) != 2:
                    raise StateFormatError(f"{path}: malformed dictionary entry")
                key = self.node(pair[0], None, f"{path} key")
                if isinstance(key, (list, dict, set)):
                    raise StateFormatError(f"{path}: unhashable dictionary key")
                out[key] = self.node(pair[1], base.get(key, None), f"{path}[{key!r}]")
            return out
        if kind == "object":
            return self._object(node, live, path)
        raise StateFormatError(f"{path}: unknown entry kind {kind!r}")

    def _object(self, node: dict, live: Any, path: str) -> Any:
        name = node["class"]
        attrs = node["attrs"]
        if not isinstance(name, str) or not isinstance(attrs, dict) and not node.get("setstate"):
            raise StateFormatError(f"{path}: malformed object")
        if live is not None and live is not _MISSING and _class_name(type(live)) == name:
            if id(live) in self.claimed:  # two saved objects, one live one: work on a copy
                import copy

                live = copy.copy(live)
            obj = live
        else:
            obj = self._new_instance(name, path)
        self.claimed.add(id(obj))
        self._keep(node, obj)
        if node.get("setstate"):
            if not _custom_state(type(obj)):
                raise StateFormatError(f"{path}: class {name!r} does not restore its own state")
            state = self.node(attrs, None, f"{path}.__getstate__()")
            try:
                obj.__setstate__(state)
            except (TypeError, ValueError, KeyError, AttributeError) as exc:
                raise StateFormatError(f"{path}: cannot be restored ({type(exc).__name__}: {exc})") from None
            return obj
        current = _attributes(obj) or {}
        for key, value in attrs.items():
            if not isinstance(key, str) or (key.startswith("__") and key.endswith("__")):
                raise StateFormatError(f"{path}: attribute name {key!r} is not one of a state")
            new = self.node(value, current.get(key, _MISSING), f"{path}.{key}")
            try:
                object.__setattr__(obj, key, new)
            except (AttributeError, TypeError) as exc:
                raise StateFormatError(f"{path}.{key}: cannot be restored ({exc})") from None
        if hasattr(obj, "__dict__"):
            for key in [k for k in vars(obj) if k not in attrs]:
                del vars(obj)[key]
        return obj


    def _new_instance(self, name: str, path: str) -> Any:
        """An empty instance of an allowed class (module docstring); any other name is refused."""
        cls = self.allowed.get(name)
        if cls is None:
            raise StateFormatError(f"{path}: the state names class {name!r}, which is not a class of this model "
                                   "(only the model's own state classes are restored)")
        try:
            return cls.__new__(cls)
        except TypeError as exc:
            raise StateFormatError(f"{path}: class {name!r} cannot be restored ({exc})") from None


def _class_name(cls: type) -> str:
    return f"{cls.__module__}:{cls.__qualname__}"
