"""mplsource.install_once, the guard of every patch of matplotlib's internals: with the source of
a guarded function other than the one written against (a hash off by one character), nothing is
patched and the owner is not marked; with the right one the patch runs once, however often the
module installs."""

from typing import Any, List

from dampfig import mplsource


def guarded(x: int) -> int:
    return x + 1


class Owner:
    pass


def install(owner: Any, expected: str, calls: List[int]) -> bool:
    return mplsource.install_once(owner, "_patched", [(guarded, expected)],
                                  lambda: calls.append(1))


def test_a_changed_source_patches_nothing() -> None:
    right = mplsource.source_hash(guarded)
    wrong = right[:-1] + ("0" if right[-1] != "0" else "1")
    calls: List[int] = []
    owner = Owner()
    assert not install(owner, wrong, calls)
    assert calls == [] and not hasattr(owner, "_patched")


def test_the_written_against_source_patches_once() -> None:
    calls: List[int] = []
    owner = Owner()
    right = mplsource.source_hash(guarded)
    assert install(owner, right, calls) and install(owner, right, calls)
    assert calls == [1] and owner._patched  # type: ignore[attr-defined]


def test_every_module_guard_holds_for_this_matplotlib() -> None:
    from dampfig import layoutcache, legendmemo, textcache, tickclone, tickmemo
    for module in (layoutcache, legendmemo, textcache, tickclone, tickmemo):
        assert module.install(), module.__name__
