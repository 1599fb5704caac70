"""The Python diagnostics registry (verify/diagnostics) covers every diagnostic dampsym knows:
the names of the case schema's `diagnostics` enum (schema/case.schema.json, tested against the C++
registry on the C++ side), one module each, named after the diagnostic."""
from __future__ import annotations

import json
import os
from typing import List

from verify import diagnostics

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def schema_diagnostics() -> List[str]:
    with open(os.path.join(ROOT, "schema", "case.schema.json")) as fh:
        schema = json.load(fh)
    return list(schema["properties"]["diagnostics"]["items"]["enum"])


def test_every_schema_diagnostic_is_registered() -> None:
    missing = sorted(set(schema_diagnostics()) - set(diagnostics.REGISTRY))
    assert missing == [], "diagnostics without a module in verify/diagnostics: %s" % missing


def test_no_registered_diagnostic_unknown_to_dampsym() -> None:
    extra = sorted(set(diagnostics.REGISTRY) - set(schema_diagnostics()))
    assert extra == [], "registered but not in the case schema: %s" % extra


def test_one_module_per_diagnostic() -> None:
    for name, d in diagnostics.REGISTRY.items():
        assert d.run or d.grid or d.method, "%s registers no recomputation" % name
        path = os.path.join(ROOT, "verify", "diagnostics", name.replace("-", "_") + ".py")
        assert os.path.isfile(path), "%s: no module %s" % (name, path)


def test_implied_diagnostics() -> None:
    assert diagnostics.with_implied(["order"]) == ["order", "error"]
    assert diagnostics.with_implied(["local-order", "order"]) == ["local-order", "order", "error", "local-error"]
    assert diagnostics.with_implied(["error", "order"]) == ["error", "order"]


def test_a_missing_module_is_seen() -> None:
    """Negative control: with one module's registration removed the coverage test would fail."""
    saved = diagnostics.REGISTRY.pop("precession")
    try:
        assert "precession" in set(schema_diagnostics()) - set(diagnostics.REGISTRY)
    finally:
        diagnostics.REGISTRY["precession"] = saved
