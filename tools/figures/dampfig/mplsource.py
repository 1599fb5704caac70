"""The SHA-256 of a matplotlib function's source: the guard of every module here that reasons
about matplotlib 3.6.3's internals (textcache, tickmemo, layoutcache, tickclone, legendmemo,
render.reuse_renderer); with another version's code they change nothing."""

import hashlib
import inspect
from typing import Any


def source_hash(function: Any) -> str:
    return hashlib.sha256(inspect.getsource(function).encode()).hexdigest()
