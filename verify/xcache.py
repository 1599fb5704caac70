"""Cache of the cross-check's OWN results on disk (verify/crosscheck.py --cache DIR).

The negative controls (verify/tests/test_crosscheck_negative.py) cross-check slices of the very
report that crosscheck.default checks, with a fault planted in the C++ side; our side of those
slices is the same computation.  The functions decorated with `memo` below (our integrations,
our DOP853 references, our Newton-count families) are pure functions of their arguments: an
entry's key is a SHA-256 of the function's name, every argument (numbers by their exact bits,
arrays by dtype, shape and bytes, a problem object by its class and every attribute: parameters,
z0, ...) and the digest of the cross-check's own sources and of numpy/scipy/numba's versions.
Nothing of the C++ report is read here: the report enters only as the comparisons that are run
after these functions, on every call, cache or not, so a changed report is compared afresh
(tests/test_xcache.py plants a fault after the cache is written).

Entries are pickles written atomically (a temporary file renamed), so concurrent workers and
concurrent ctests share a directory; an unreadable entry is a miss.  Results larger than
MAX_BYTES are not stored (a few 10^6-step trajectories: reading them back saves little).
"""
from __future__ import annotations

import functools
import hashlib
import os
import pickle
import struct
import sys
import tempfile
from typing import Any, Callable, Dict, Optional, TypeVar

import numpy as np

MAX_BYTES = 8 << 20
STATS: Dict[str, int] = {"hits": 0, "misses": 0, "stored": 0}
_state: Dict[str, Any] = {"dir": None, "sources": None, "write": True}
# attributes a problem object fills in as a side output (a memo of its own, the exact solution's
# round-off estimate): not inputs of any cached function
_OUTPUT_ATTRS = ("_refcache", "exact_estimate")

F = TypeVar("F", bound=Callable[..., Any])


def configure(directory: Optional[str], write: bool = True) -> None:
    """Use `directory` from now on (created when written); None: no cache (every call
    computes); write=False: read its entries, add none."""
    if directory is not None and write:
        os.makedirs(directory, exist_ok=True)
    _state["dir"] = directory
    _state["write"] = write
    for k in STATS:
        STATS[k] = 0


def directory() -> Optional[str]:
    return _state["dir"]


def sources_digest() -> str:
    """SHA-256 of every source file of the package verify (its tests excepted), the Python,
    numpy and scipy versions, whether the compiled loops (numba) are on and a planted tableau."""
    if _state["sources"] is None:
        import scipy
        from . import xjit
        root = os.path.dirname(os.path.abspath(__file__))
        h = hashlib.sha256()
        for dirpath, dirnames, filenames in os.walk(root):
            dirnames[:] = sorted(d for d in dirnames if d not in ("tests", "__pycache__"))
            for name in sorted(f for f in filenames if f.endswith(".py")):
                path = os.path.join(dirpath, name)
                h.update(os.path.relpath(path, root).encode() + b"\0")
                with open(path, "rb") as fh:
                    h.update(fh.read() + b"\0")
        # and the planted tableau fault of the negative control wrongcoef (xmethods.py), and the
        # method files' definitions (verify/xmethodfile.py: a method's id alone is not its method)
        from . import xmethods
        h.update(repr((sys.version, np.__version__, scipy.__version__, xjit.HAVE_NUMBA,
                       os.environ.get("XC_PERTURB_GAUSS"), sorted(xmethods.FILE_DEFS.items()))).encode())
        _state["sources"] = h.hexdigest()
    return str(_state["sources"])


def _feed(h: Any, x: Any) -> None:
    """Every bit of an argument into the hash, tagged by type; TypeError for a type not known
    here (the call is then not cached)."""
    if x is None or isinstance(x, (bool, np.bool_)):
        h.update(b"N" if x is None else (b"T" if x else b"F"))
    elif isinstance(x, (int, np.integer)):
        h.update(b"i" + str(int(x)).encode() + b";")
    elif isinstance(x, float) or (isinstance(x, np.floating) and x.dtype == np.float64):
        h.update(b"f" + struct.pack("<d", float(x)))
    elif isinstance(x, str):
        h.update(b"s" + str(len(x)).encode() + b":" + x.encode())
    elif isinstance(x, (np.ndarray, np.generic)):     # arrays, and scalars of other precisions
        a = np.ascontiguousarray(x)
        if a.dtype.hasobject:
            raise TypeError("an object array is not hashed by value")
        h.update(b"a" + a.dtype.str.encode() + repr(a.shape).encode())
        h.update(a.tobytes())
    elif isinstance(x, (list, tuple)):
        h.update(b"l" + str(len(x)).encode() + b"[")
        for v in x:
            _feed(h, v)
    elif isinstance(x, dict):
        h.update(b"d" + str(len(x)).encode() + b"{")
        for k in sorted(x, key=repr):
            _feed(h, k)
            _feed(h, x[k])
    elif callable(x) and hasattr(x, "__code__"):    # a problem's pair potential (NBody)
        c = x.__code__
        h.update(b"c" + x.__qualname__.encode() + c.co_code + repr((c.co_names, c.co_consts)).encode())
    elif type(x).__module__ == __package__ + ".xproblems":
        h.update(b"o" + type(x).__qualname__.encode())
        _feed(h, {k: v for k, v in vars(x).items() if k not in _OUTPUT_ATTRS})
    else:
        raise TypeError("not a cacheable argument: %s" % type(x).__name__)


def sources_changed() -> None:
    """The digest is computed again at the next key (a method file was registered)."""
    _state["sources"] = None


def key(name: str, args: Any, kwargs: Dict[str, Any]) -> str:
    h = hashlib.sha256(sources_digest().encode() + name.encode() + b"\0")
    _feed(h, list(args))
    _feed(h, kwargs)
    return h.hexdigest()


def _path(k: str) -> str:
    return os.path.join(str(_state["dir"]), k[:2], k + ".pkl")


def _load(k: str) -> Any:
    """(True, value) for a readable entry of key k, else (False, None)."""
    try:
        with open(_path(k), "rb") as fh:
            stored_key, value = pickle.load(fh)
    except (OSError, EOFError, pickle.UnpicklingError, ValueError, TypeError, AttributeError, ImportError):
        return False, None
    return (True, value) if stored_key == k else (False, None)


def _array_bytes(x: Any) -> int:
    """The bytes of the arrays in a result (a large one is not pickled only to be dropped)."""
    if isinstance(x, np.ndarray):
        return int(x.nbytes)
    if isinstance(x, dict):
        return sum(_array_bytes(v) for v in x.values())
    if isinstance(x, (list, tuple)):
        return sum(_array_bytes(v) for v in x)
    return 0


def _store(k: str, value: Any) -> None:
    if not _state["write"] or _array_bytes(value) > MAX_BYTES:
        return
    blob = pickle.dumps((k, value), protocol=pickle.HIGHEST_PROTOCOL)
    if len(blob) > MAX_BYTES:
        return
    path = _path(k)
    try:
        os.makedirs(os.path.dirname(path), exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path), suffix=".tmp")
        with os.fdopen(fd, "wb") as fh:
            fh.write(blob)
        os.replace(tmp, path)
        STATS["stored"] += 1
    except OSError:
        pass        # a full or read-only disk: the result is still returned, just not kept


def memo(fn: F) -> F:
    """`fn` cached in the configured directory (a pure function of its arguments)."""
    name = fn.__module__ + "." + fn.__qualname__

    @functools.wraps(fn)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        if _state["dir"] is None:
            return fn(*args, **kwargs)
        try:
            k = key(name, args, kwargs)
        except TypeError:
            return fn(*args, **kwargs)
        found, value = _load(k)
        if found:
            STATS["hits"] += 1
            return value
        STATS["misses"] += 1
        value = fn(*args, **kwargs)
        _store(k, value)
        return value
    return wrapper  # type: ignore[return-value]
