"""The SHA-256 of a matplotlib function's source: the guard of every module here that reasons
about matplotlib 3.6.3's internals (textcache, tickmemo, layoutcache, tickclone, legendmemo,
render.reuse_renderer); with another version's code they change nothing."""

import hashlib
import inspect
from typing import Any, Callable, Iterable, Tuple


def source_hash(function: Any) -> str:
    return hashlib.sha256(inspect.getsource(function).encode()).hexdigest()


def install_once(owner: Any, flag: str, guards: Iterable[Tuple[Any, str]],
                 patch: Callable[[], None]) -> bool:
    """Patches matplotlib once: True at once when `owner` carries `flag` (installed before);
    False, changing nothing, when the source of any guarded function is not the one (its SHA-256)
    the patch was written against; else runs `patch`, marks `owner` and returns True."""
    if getattr(owner, flag, False):
        return True
    if any(source_hash(function) != expected for function, expected in guards):
        return False
    patch()
    setattr(owner, flag, True)
    return True
