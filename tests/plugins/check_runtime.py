#!/usr/bin/python3
"""Checks the report of tests/plugins/bad-runtime.json (ctest plugin.bad.runtime, docs/plugins.md):
a plugin returning NaN is `diverged`, one refusing a step `solve-failed`, one writing past
z_next[dim) or before z_next[0] `error` with the guard-cell message, one writing z_next[0] only,
one writing into z and one calling grad_T (a callback outside its plain form) after t = 0.45 each
`error` with its message (never "ok"); and the plugin-Jacobian path of E_n: for the
identity step with the identity Jacobian, E_n relative = e^{2 dGamma} - 1 = e^{2 gamma h} - 1.

    /usr/bin/python3 tests/plugins/check_runtime.py REPORT.json     (exit 0 = as expected)
"""
import json
import math
import sys


def error_says(run, text):
    return run["status"] == "error" and text in run.get("error", "")


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
        "bad-underflow error": error_says(runs["bad-underflow"], "wrote before z_next[0]"),
        "bad-partial error": error_says(runs["bad-partial"],
                                        "returned success without writing z_next[1]"),
        "bad-writes-z error": error_says(runs["bad-writes-z"], "wrote into its input z"),
        "bad-late-grad-t error": error_says(runs["bad-late-grad-t"],
                                            "called the host callback grad_T"),
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
