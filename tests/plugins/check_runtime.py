#!/usr/bin/python3
"""Checks the report of tests/plugins/bad-runtime.json (ctest plugin.bad.runtime, docs/plugins.md):
a plugin returning NaN is `diverged`, one refusing a step `solve-failed`, one writing past
z_next[dim) `error` with the guard-cell message; and the plugin-Jacobian path of E_n: for the
identity step with the identity Jacobian, E_n relative = e^{2 dGamma} - 1 = e^{2 gamma h} - 1.

    /usr/bin/python3 tests/plugins/check_runtime.py REPORT.json     (exit 0 = as expected)
"""
import json
import math
import sys


def main():
    r = json.load(open(sys.argv[1]))
    case = r["cases"][0]
    runs = {x["method"]: x for x in case["runs"]}
    g, h = case["problem"]["params"]["gamma"], runs["jac-identity"]["dt"]
    cs = runs["jac-identity"]["metrics"]["conformal-symplectic"]
    expect = math.expm1(2.0 * g * h)
    results = {
        "bad-nan diverged": runs["bad-nan"]["status"] == "diverged",
        "bad-refuse solve-failed": runs["bad-refuse"]["status"] == "solve-failed",
        "bad-oob error": runs["bad-oob"]["status"] == "error"
        and "wrote past z_next[2)" in runs["bad-oob"].get("error", ""),
        "jac-identity ok": runs["jac-identity"]["status"] == "ok",
        "jac-identity E_n from the plugin's Jacobian": cs.get("jacobian") == "plugin-jacobian",
        "jac-identity E_n = e^(2 gamma h) - 1": abs(cs["max_rel"] - expect) <= 1e-12 * expect,
    }
    for k, v in results.items():
        print(("ok   " if v else "FAIL ") + k)
    print("E_n %.17g, expected %.17g" % (cs["max_rel"], expect))
    return 0 if all(results.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
