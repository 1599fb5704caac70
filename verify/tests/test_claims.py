#!/usr/bin/python3
"""Checks the claims register docs/claims.md against a default-suite report.json.

    python3 -m pytest verify/tests/test_claims.py::test_register --register REGISTER \
        --report REPORT [--report REPORT...]       passes when the register agrees
    ... ::test_negative ...                          passes when every planted defect is detected
    python3 -m verify.tests.test_claims [--negative] REGISTER REPORT [REPORT...]   (exit 0/1/2)

The first REPORT is the default suite's; further ones hold the cases of the register that are
too heavy for it (B Fig 5.10's chaotic attractor, run by the ctest claims.pde-report); a case is
looked up in all of them, and only the first one's uncited cases are warned about.

The register is the Markdown table of docs/claims.md whose header row is
| Paper | Where | Claim | Case | Check | Verdict |. For every row:

- "Where" names the figure or table (e.g. "Fig 4.1", "Table 2.1"); every location listed in
  REQUIRED below must have at least one row (the experiment chapters of the seed papers);
- "Case" is a backticked case id of the report, or "—" (then the verdict must be "not checkable");
- "Check" lists backticked check names of that case (at least one when a case is given);
- "Verdict" starts with "reproduced", "not reproduced" or "not checkable".

A verdict is what the report says: "reproduced" when every evaluation of every listed check
passed and none of them is marked "refutes"; "not reproduced" when every evaluation passed and
every listed check is marked "refutes" (its passing shows the claim does not hold). A check that
fails, or is missing, or a verdict that does not follow from the report, is an error (exit 1).
Default-suite cases that the register does not mention are listed as a warning. Bad input
(unreadable register or report, no register table) exits 2.
"""
import copy
import json
import re
import sys
from typing import Any, Dict, List, Tuple

# Every figure and table of the experiment chapters named in docs/claims.md (paper key, location).
REQUIRED = (
    [("F", "Fig 4.%d" % i) for i in range(1, 14)] + [("F", "Table 4.1")]
    + [("B", "Fig 3.%d" % i) for i in range(1, 8)] + [("B", "Table 3.1")]
    + [("B", "Fig 5.%d" % i) for i in range(1, 11)]
    + [("HLW", "Fig 1.1"), ("HLW", "Fig 1.2"), ("HLW", "Fig 2.1"), ("HLW", "Fig 2.2"),
       ("HLW", "Table 2.1"), ("HLW", "Table 2.2"), ("HLW", "Fig 2.3"), ("HLW", "Fig 3.1"),
       ("HLW", "Table 3.1")]
    + [("BS", "rigid body")]
)

VERDICTS = ("reproduced", "not reproduced", "not checkable")


class BadInput(Exception):
    pass


def split_row(line: Any) -> Any:
    """Cells of a Markdown table row; "\\|" is a literal "|" inside a cell."""
    body = line.strip()
    body = body[1:] if body.startswith("|") else body
    body = body[:-1] if body.endswith("|") and not body.endswith("\\|") else body
    return [c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", body)]


def parse_register(text: str) -> Any:
    """Rows of the register table as dicts (line number included)."""
    lines = text.splitlines()
    rows: List[Dict[str, Any]] = []
    header = None
    for no, line in enumerate(lines, 1):
        if not line.lstrip().startswith("|"):
            if header is not None and rows:
                header = None  # the table ended; a later table would need its own header
            continue
        cells = split_row(line)
        if header is None:
            if [c.lower() for c in cells] == ["paper", "where", "claim", "case", "check", "verdict"]:
                header = cells
            continue
        if all(re.fullmatch(r":?-+:?", c) for c in cells):
            continue
        if len(cells) != 6:
            raise BadInput("line %d: expected 6 cells, got %d" % (no, len(cells)))
        rows.append(dict(line=no, paper=cells[0], where=cells[1], claim=cells[2],
                         case=cells[3], checks=re.findall(r"`([^`]+)`", cells[4]),
                         case_ids=re.findall(r"`([^`]+)`", cells[3]), verdict=cells[5]))
    if not rows:
        raise BadInput("no register table (header | Paper | Where | Claim | Case | Check | Verdict |)")
    return rows


def verdict_of(text: str) -> Any:
    low = text.lower().lstrip("*_ ")
    for v in ("not reproduced", "not checkable", "reproduced"):
        if low.startswith(v):
            return v
    return None


def check_register(rows: Any, report: Dict[str, Any], extra: Any = ()) -> Any:
    """List of error strings (empty: the register agrees with the reports) and warnings."""
    errors, warnings = [], []
    cases = {c["id"]: c for c in report.get("cases", [])}
    default_ids = set(cases)
    for rep in extra:
        for c in rep.get("cases", []):
            cases.setdefault(c["id"], c)
    seen_locations = set()
    mentioned = set()
    for r in rows:
        where = "line %d (%s %s)" % (r["line"], r["paper"], r["where"])
        for loc in re.split(r"[,;]\s*", r["where"]):
            seen_locations.add((r["paper"], loc.strip()))
        v = verdict_of(r["verdict"])
        if v is None:
            errors.append("%s: verdict %r is none of %s" % (where, r["verdict"], ", ".join(VERDICTS)))
            continue
        if v == "not checkable":
            if r["case_ids"] or r["checks"]:
                errors.append("%s: a 'not checkable' claim names no case or check" % where)
            if len(r["verdict"]) < len("not checkable") + 10:
                errors.append("%s: 'not checkable' needs its reason" % where)
            continue
        if len(r["case_ids"]) != 1:
            errors.append("%s: give exactly one backticked case id" % where)
            continue
        cid = r["case_ids"][0]
        mentioned.add(cid)
        if cid not in cases:
            errors.append("%s: case '%s' is not in the default-suite report (nor in the extra "
                          "reports)" % (where, cid))
            continue
        if not r["checks"]:
            errors.append("%s: name at least one check of case '%s'" % (where, cid))
            continue
        for name in r["checks"]:
            evals = [ck for ck in cases[cid]["checks"] if ck["name"] == name]
            if not evals:
                errors.append("%s: case '%s' has no check '%s'" % (where, cid, name))
                continue
            failed = [ck for ck in evals if not ck.get("passed")]
            if failed:
                ck = failed[0]
                errors.append("%s: check '%s' of '%s' failed (%s, value %s, expected %s %s): the "
                              "verdict changed" % (where, name, cid, ck.get("method"),
                                                   ck.get("value"), ck.get("op"),
                                                   ck.get("expected")))
                continue
            refutes = any(ck.get("refutes", False) for ck in evals)
            if v == "reproduced" and refutes:
                errors.append("%s: check '%s' of '%s' refutes the claim; the register says "
                              "'reproduced'" % (where, name, cid))
            if v == "not reproduced" and not refutes:
                errors.append("%s: check '%s' of '%s' supports the claim (no \"refutes\"); the "
                              "register says 'not reproduced'" % (where, name, cid))
    for paper, loc in REQUIRED:
        if (paper, loc) not in seen_locations:
            errors.append("no register row for %s %s" % (paper, loc))
    for cid in sorted(default_ids - mentioned):
        warnings.append("default-suite case '%s' is not cited by the register" % cid)
    return errors, warnings


def run(register_text: str, report: Dict[str, Any], extra: Any = ()) -> Any:
    rows = parse_register(register_text)
    return check_register(rows, report, extra)


def negative(register_text: str, report: Dict[str, Any], extra: Any = ()) -> Any:
    """Plants one defect at a time; each must be reported. Returns the list of undetected ones."""
    rows = parse_register(register_text)
    base_errors, _ = check_register(rows, report, extra)
    if base_errors:
        return ["the unmodified register already disagrees: " + base_errors[0]]
    missed = []
    reproduced = [r for r in rows if verdict_of(r["verdict"]) == "reproduced"]
    refuted = [r for r in rows if verdict_of(r["verdict"]) == "not reproduced"]
    if not reproduced:
        return ["no 'reproduced' row to mutate"]
    target = reproduced[0]
    lines = register_text.splitlines()

    def replaced(line_no: Any, old: Any, new: Any) -> Any:
        out = list(lines)
        assert old in out[line_no - 1], (old, out[line_no - 1])
        out[line_no - 1] = out[line_no - 1].replace(old, new, 1)
        return "\n".join(out)

    mutations: List[Tuple[Any, ...]] = [
        ("case id renamed", replaced(target["line"], "`%s`" % target["case_ids"][0],
                                     "`%s-renamed`" % target["case_ids"][0]), report),
        ("check renamed", replaced(target["line"], "`%s`" % target["checks"][0],
                                   "`%s (renamed)`" % target["checks"][0]), report),
        ("verdict changed", replaced(target["line"], "reproduced", "not reproduced"), report),
        ("location dropped", "\n".join(l for i, l in enumerate(lines, 1)
                                       if not any(r["line"] == i and r["paper"] == "F" and
                                                  r["where"] == "Table 4.1" for r in rows)),
         report),
    ]
    flipped = copy.deepcopy(report)
    for c in flipped["cases"]:
        if c["id"] == target["case_ids"][0]:
            for ck in c["checks"]:
                if ck["name"] == target["checks"][0]:
                    ck["passed"] = False
                    break
    mutations.append(("a listed check fails in the report", register_text, flipped))
    if refuted:
        unrefuted = copy.deepcopy(report)
        rr = refuted[0]
        for c in unrefuted["cases"]:
            if c["id"] == rr["case_ids"][0]:
                for ck in c["checks"]:
                    ck.pop("refutes", None)
        mutations.append(("a refuting check loses its \"refutes\"", register_text, unrefuted))
    if extra:
        # a row whose case is only in an extra report: its report must be read too
        only_extra = [r for r in reproduced if r["case_ids"][0] not in
                      {c["id"] for c in report.get("cases", [])}]
        if only_extra:
            flipped_extra = copy.deepcopy(list(extra))
            ex = only_extra[0]
            for rep in flipped_extra:
                for c in rep.get("cases", []):
                    if c["id"] == ex["case_ids"][0]:
                        for ck in c["checks"]:
                            if ck["name"] == ex["checks"][0]:
                                ck["passed"] = False
            mutations.append(("a listed check of an extra report fails", register_text, report,
                              flipped_extra))
            mutations.append(("the extra report is not read", register_text, report, ()))
    for m in mutations:
        what, text, rep = m[:3]
        ext = m[3] if len(m) > 3 else extra
        try:
            errors, _ = run(text, rep, ext)
        except BadInput as e:
            errors = [str(e)]
        print("%-40s -> %s" % (what, ("detected: " + errors[0]) if errors else "NOT DETECTED"))
        if not errors:
            missed.append(what)
    return missed


def main(argv: Any) -> Any:
    neg = "--negative" in argv
    args = [a for a in argv if a != "--negative"]
    if len(args) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        with open(args[0], encoding="utf-8") as f:
            register_text = f.read()
        reports = []
        for path in args[1:]:
            with open(path, encoding="utf-8") as f:
                reports.append(json.load(f))
        report, extra = reports[0], reports[1:]
        if neg:
            missed = negative(register_text, report, extra)
            for m in missed:
                print("NOT DETECTED: " + m)
            return 1 if missed else 0
        errors, warnings = run(register_text, report, extra)
    except (OSError, ValueError, BadInput) as exc:
        print("test_claims.py: bad input: %s" % exc, file=sys.stderr)
        return 2
    for w in warnings:
        print("warning: " + w)
    for err in errors:
        print("ERROR: " + err)
    rows = parse_register(register_text)
    counts = {v: sum(1 for r in rows if verdict_of(r["verdict"]) == v) for v in VERDICTS}
    print("%d register rows: %s; %d errors" % (
        len(rows), ", ".join("%d %s" % (counts[v], v) for v in VERDICTS), len(errors)))
    return 1 if errors else 0


def test_register(register_path: str, reports: List[str]) -> None:
    """Every row of the register follows from the reports."""
    assert main([register_path] + reports) == 0


def test_negative(register_path: str, reports: List[str]) -> None:
    """Every planted defect (renamed case or check, changed verdict, ...) is detected."""
    assert main(["--negative", register_path] + reports) == 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
