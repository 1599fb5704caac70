"""The Python diagnostics registry (verify/diagnostics) covers every diagnostic dampsym knows:
the names of dampsym's own registry (`dampsym list --json`, read from src/diagnostics; the case
schema does not repeat them), one module each, named after the diagnostic."""
from __future__ import annotations

import json
import os
import subprocess
from typing import List

from verify import diagnostics

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def dampsym_diagnostics(binary: str) -> List[str]:
    """The diagnostics of dampsym's registry, in its order (the run record is not one)."""
    out = subprocess.run([binary, "list", "--json"], capture_output=True, text=True, check=True)
    return [d["id"] for d in json.loads(out.stdout)["diagnostics"] if d["id"] != "run"]


def test_every_dampsym_diagnostic_is_registered(dampsym_bin: str) -> None:
    missing = sorted(set(dampsym_diagnostics(dampsym_bin)) - set(diagnostics.REGISTRY))
    assert missing == [], "diagnostics without a module in verify/diagnostics: %s" % missing


def test_no_registered_diagnostic_unknown_to_dampsym(dampsym_bin: str) -> None:
    extra = sorted(set(diagnostics.REGISTRY) - set(dampsym_diagnostics(dampsym_bin)))
    assert extra == [], "registered but unknown to dampsym: %s" % extra


def test_listing_says_what_each_measures(dampsym_bin: str) -> None:
    """`dampsym list` carries what a newcomer would look up in the docs: each diagnostic's
    measure and needs come from its own file, so no docs table repeats them."""
    out = subprocess.run([dampsym_bin, "list", "--json"], capture_output=True, text=True,
                         check=True)
    for d in json.loads(out.stdout)["diagnostics"]:
        assert d["what"], "%s: no description in its info()" % d["id"]
    order = next(d for d in json.loads(out.stdout)["diagnostics"] if d["id"] == "order")
    assert "dt_ladder of at least 3" in order["needs"]


def test_schema_leaves_names_to_the_registry() -> None:
    """The case schema accepts any well-formed name (the parser refuses unknown ones, naming the
    closest): adding a diagnostic does not edit the schema."""
    with open(os.path.join(ROOT, "schema", "case.schema.json")) as fh:
        items = json.load(fh)["properties"]["diagnostics"]["items"]
    assert "enum" not in items and items["type"] == "string"


def test_one_module_per_diagnostic() -> None:
    for name, d in diagnostics.REGISTRY.items():
        assert d.run or d.grid or d.method, "%s registers no recomputation" % name
        path = os.path.join(ROOT, "verify", "diagnostics", name.replace("-", "_") + ".py")
        assert os.path.isfile(path), "%s: no module %s" % (name, path)


def test_implied_diagnostics() -> None:
    assert diagnostics.with_implied(["order"]) == ["order", "error"]
    assert diagnostics.with_implied(["local-order", "order"]) == ["local-order", "order", "error", "local-error"]
    assert diagnostics.with_implied(["error", "order"]) == ["error", "order"]


def conventions_entries(text: str) -> List[str]:
    """The diagnostics that docs/conventions.md §5 defines: its bold entry names."""
    import re
    start = text.index("## §5 ")
    section = text[start:text.index("\n## ", start + 1)]
    return re.findall(r"\*\*([a-z][a-z0-9-]*)\*\*", section)


def test_every_diagnostic_is_defined_in_the_docs(dampsym_bin: str) -> None:
    """Its one docs entry: a bold entry of docs/conventions.md §5 (definition, metrics, problems)."""
    with open(os.path.join(ROOT, "docs", "conventions.md"), encoding="utf-8") as fh:
        defined = set(conventions_entries(fh.read()))
    missing = sorted(set(dampsym_diagnostics(dampsym_bin)) - defined)
    assert missing == [], "no entry in docs/conventions.md §5: %s" % missing


def test_a_missing_docs_entry_is_seen() -> None:
    """Negative control: §5 without precession's entry lacks it."""
    with open(os.path.join(ROOT, "docs", "conventions.md"), encoding="utf-8") as fh:
        text = fh.read()
    assert "precession" in conventions_entries(text)
    assert "precession" not in conventions_entries(text.replace("**precession**", "precession"))


def test_a_missing_module_is_seen(dampsym_bin: str) -> None:
    """Negative control: with one module's registration removed the coverage test would fail."""
    saved = diagnostics.REGISTRY.pop("precession")
    try:
        assert "precession" in set(dampsym_diagnostics(dampsym_bin)) - set(diagnostics.REGISTRY)
    finally:
        diagnostics.REGISTRY["precession"] = saved
