#!/usr/bin/python3
"""The figures are right: reads the plotted data back from a report directory made
with `dampsym run --figures` (series/*.json, figures/manifest.json) and compares it with
report.json — final and maximum errors, energy errors, invariant, momentum and E_n residual
maxima, temperature range, d(t) slopes, fitted orders and their drawn lines, the stability map's
boundaries against the report's rows and F's closed form. Also checks that every figure listed
exists and that report.md embeds it. Exit 0 = all agree, 1 = a disagreement (each printed).

    /usr/bin/python3 verify/figures/test_figure_data.py REPORT_DIR
"""
from typing import Any, Dict

import json
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
from tools.figures.dampfig import figdata as fd
from tools.figures.dampfig import papers

RTOL = 1e-12
problems = []
compared = 0


def close(a: Any, b: Any, rtol: Any = RTOL) -> Any:
    return a == b or abs(a - b) <= rtol * max(abs(a), abs(b))


def expect(what: Any, got: Any, want: Any, rtol: Any = RTOL) -> None:
    global compared
    compared += 1
    if got is None or want is None or not close(got, want, rtol):
        problems.append(f"{what}: plotted {got!r}, report {want!r}")


def get(d: Any, dotted: Any) -> Any:
    for k in dotted.split("."):
        if not isinstance(d, dict) or k not in d:
            return None
        d = d[k]
    return d


def check_pictures(tag: str, m: Any, s: Any) -> None:
    """The snapshots (B Fig 5.4) and the portrait (B Fig 5.10) against the run's metrics."""
    sn = s.get("snapshots")
    pe = get(m, "pde-error")
    if sn and sn.get("t") and pe and pe.get("max_abs") is not None and \
            len(sn["t"]) == pe["points"] + 1:  # every output time drawn: the metric from them
        errs = [max(abs(a - b) for a, b in zip(u, v)) for u, v in zip(sn["u"][1:], sn["pde"][1:])]
        expect(f"{tag} snapshots: max |u - u_pde|", max(errs), pe["max_abs"])
        expect(f"{tag} snapshots: final |u - u_pde|", errs[-1], pe["final_abs"])
    pl = s.get("attractor.plane")
    at = get(m, "attractor")
    if pl and pl.get("points") and at and at.get("max") is not None:
        # the portrait's points are the probe's plane: |point| over the second half is the probe
        # (each coordinate drawn to 7 digits: |point| to 1e-6 relative)
        win = [math.hypot(x, y) for t_, (x, y) in zip(pl["t"], pl["points"]) if t_ >= at["from"]]
        if pl.get("stride") == 1:
            expect(f"{tag} portrait: max |point| over the window", max(win), at["max"], 1e-6)
            expect(f"{tag} portrait: min |point| over the window", min(win), at["min"], 1e-6)
        elif win:
            expect(f"{tag} portrait: max |point| (at most the probe's max)",
                   min(max(win), at["max"]), max(win), 1e-6)


def check_run(cid: str, r: Any, s: Any) -> None:
    m = r["metrics"]
    tag = f"{cid} {r['method']} dt={r['dt']}"
    check_pictures(tag, m, s)
    for key, val in s.items():
        if not isinstance(val, dict) or "y" not in val or not val["y"]:
            continue
        y = val["y"]
        if key == "error.abs":
            expect(f"{tag} max error", max(y), get(m, "error.max_abs"))
            expect(f"{tag} final error", val["last"][1], get(m, "error.final_abs"))
        elif key == "energy.error":
            expect(f"{tag} max |H error|", max(abs(v) for v in y), get(m, "energy.max_abs_error"))
            expect(f"{tag} final |H error|", abs(val["last"][1]), get(m, "energy.final_abs_error"))
        elif key == "energy.change_res":
            if get(m, "energy.max_change_res") is not None:
                expect(f"{tag} max energy change", max(abs(v) for v in y),
                       get(m, "energy.max_change_res"))
        elif key.startswith("invariants.") and key.endswith(".step_res"):
            want = get(m, key.replace(".step_res", ".max_step_res"))
            if want is not None:
                expect(f"{tag} {key} max", max(y), want)
        elif key.startswith("invariants.") and key.endswith(".ratio_dev"):
            want = get(m, key.replace(".ratio_dev", ".max_global_ratio_dev"))
            if want is not None:
                expect(f"{tag} {key} max |.|", max(abs(v) for v in y), want)
        elif key == "conformal-symplectic.rel":
            expect(f"{tag} max E_n", max(y), get(m, "conformal-symplectic.max_rel"))
        elif key in ("momentum.linear.law_res", "momentum.angular.law_res"):
            part = key.split(".")[1]
            want = get(m, f"momentum.{part}.max_law_res")
            if want is not None:
                expect(f"{tag} {key} max", max(y), want)
        elif key == "energy-balance.residual":
            expect(f"{tag} max energy-balance residual", max(y), get(m, "energy-balance.max"))
        elif key == "temperature":
            expect(f"{tag} temperature min", min(y), get(m, "temperature.min"))
            expect(f"{tag} temperature max", max(y), get(m, "temperature.max"))
        elif key == "field-drift.d":
            d = get(m, "field-drift")
            if val["per_bucket"] == 1 and d and d.get("slope") is not None:
                expect(f"{tag} field d(t) points", len(y), d["points"])
                expect(f"{tag} field d(t) first", y[0], d["first"][1])
                expect(f"{tag} field d(t) last", val["last"][1], d["last"][1])
                a, _ = fd.linear_fit(val["t"], y)
                expect(f"{tag} field d(t) slope", a, d["slope"], 1e-9)
                expect(f"{tag} field d(t) range", max(y) - min(y), d["range"])
        elif key == "attractor.probe":
            a = get(m, "attractor")
            if a and a.get("max") is not None:
                # the drawn series covers the whole run (min/max per bucket keep the extremes):
                # its largest value is at least the window's, over the window exactly
                tt = val["t"]
                frm = a["from"]
                win = [v for t_, v in zip(tt, y) if t_ >= frm]
                if val["per_bucket"] == 1:
                    expect(f"{tag} probe max over the window", max(win), a["max"])
                    expect(f"{tag} probe min over the window", min(win), a["min"])
                elif win:
                    # decimated: every drawn point of the window is one of its samples
                    expect(f"{tag} probe max over the window (at most)",
                           min(max(win), a["max"]), max(win))
                    expect(f"{tag} probe min over the window (at least)",
                           max(min(win), a["min"]), min(win))
        elif key == "dissipation-drift.d":
            d = get(m, "dissipation-drift")
            if val["per_bucket"] == 1 and d and d.get("slope") is not None:
                expect(f"{tag} maxima", len(y), d["maxima"])
                a, _ = fd.linear_fit(val["t"], y)
                expect(f"{tag} d(t) slope", a, d["slope"], 1e-9)


def check_orders(c: Any) -> None:
    for m, d in fd.convergence_data(c).items():
        if "fit" not in d:
            continue
        f = d["fit"]
        errs = {h: e for h, e in d["points"]}
        win = sorted(f["window_dt"])
        expect(f"{c['id']} {m} order from the plotted points",
               fd.loglog_slope(win, [errs[h] for h in win]), f["slope"], 1e-9)
        expect(f"{c['id']} {m} slope of the drawn line",
               fd.loglog_slope(f["line_h"], f["line_error"]), c["method_metrics"][m]["order"]["slope"],
               1e-9)


def check_stability(c: Any, ser: Any) -> None:
    for m, d in fd.stability_data(c, ser).items():
        if "map" not in d:
            problems.append(f"{c['id']} {m}: no stability map in the series file")
            continue
        mp = d["map"]
        ng, nh = len(d["gamma"]), len(mp["h"])
        refine = (len(mp["gamma"]) - 1) // max(1, ng - 1) if ng > 1 else 1
        hs_case = mp["h"][::refine]
        for r, g in enumerate(d["gamma"]):
            row = mp["code"][r * refine][::refine]
            expect(f"{c['id']} {m} map gamma row {r}", mp["gamma"][r * refine], g)
            first_f = next((hs_case[j] for j, v in enumerate(row) if v & 1), None)
            first_pb = next((hs_case[j] for j, v in enumerate(row) if v & 2), None)
            for what, got, want in [("F boundary", first_f, d["h_F_empirical"][r]),
                                    ("power-bounded boundary", first_pb, d["h_power_unbounded"][r])]:
                global compared
                compared += 1
                if got != want:
                    problems.append(f"{c['id']} {m} gamma={g} {what}: map {got}, report {want}")
            fb = mp.get("F_formula_boundary")
            want = d["h_F_formula"][r]
            if fb and want is not None:
                # the closed form's first failing h on the fine h grid lies in the report's cell
                h_fine = fb["h"][r * refine]
                dh = hs_case[1] - hs_case[0]
                fine = (hs_case[-1] - hs_case[0]) / 2000  # the closed form's h resolution
                compared += 1
                if h_fine is None or not (want - dh - 1e-12 < h_fine <= want + fine + 1e-12):
                    problems.append(f"{c['id']} {m} gamma={g}: F closed-form boundary {h_fine} "
                                    f"not in the report's cell ({want - dh}, {want}]")
        del nh


def check_figures(report_dir: Any, report: Dict[str, Any]) -> None:
    global compared
    path = os.path.join(report_dir, "figures", "manifest.json")
    if not os.path.exists(path):
        problems.append("figures/manifest.json missing")
        return
    with open(path) as f:
        manifest = json.load(f)
    with open(os.path.join(report_dir, "report.md")) as f:
        md = f.read()
    for cid, figs in manifest["cases"].items():
        for fig in figs:
            compared += 1
            if not os.path.exists(os.path.join(report_dir, fig["file"])):
                problems.append(f"{cid}: {fig['file']} listed but missing")
            if f"]({fig['file']})" not in md:
                problems.append(f"{cid}: {fig['file']} not embedded in report.md")
    gallery = os.path.join(report_dir, "figures.md")
    text = open(gallery).read() if os.path.exists(gallery) else ""
    for c in report["cases"]:
        if ("fig" in c["id"] or "table" in c["id"]) and f"[{c['id']}](" not in text:
            problems.append(f"{c['id']}: names a paper figure or table but is not in figures.md")
    for c in report["cases"]:
        has = (len(c["dt_ladder"]) >= 2 and fd.convergence_data(c)) or any(
            "stability-sweep" in v for v in c.get("method_metrics", {}).values())
        wanted = fd.case_figure_kinds(c)  # the case's "figures" key, if any
        if wanted is not None and not wanted & {"convergence", "stability"}:
            continue
        if has and c["id"] not in manifest["cases"]:
            problems.append(f"{c['id']}: has a ladder or a sweep but no figure")


def check_claims(report: Any, manifest: Any) -> None:
    """Each case of figures.md whose paper item is a figure draws the metric of each of its
    checks (the claim's metric: figdata.missing_claim_metrics over the quantities the manifest
    records for its figures)."""
    global compared
    for c in report["cases"]:
        paper = fd.paper_figure(c)
        if not paper or not papers.is_figure(paper) or fd.case_figure_kinds(c) == set():
            continue
        figs = manifest["cases"].get(c["id"], [])
        quantities = [q for f in figs for q in f.get("quantities", [])]
        compared += 1
        for m in fd.missing_claim_metrics(c, quantities):
            problems.append(f"{c['id']} ({paper}): its check reads {m}, which no figure draws "
                            f"(drawn: {sorted(set(quantities))})")


def check_measure_series(c: Any, ser: Any) -> None:
    """The pointwise series of a measure reduce to the report's value: its maximum (min/max
    decimation keeps it) for a max measure, its last point for a final one."""
    for r, sr in zip(c["runs"], ser["runs"]):
        for name, spec in c.get("measures", {}).items():
            comp = "energy" if spec.get("quantity") == "energy-error" else \
                spec.get("component", "state")
            s = sr["series"].get(f"measure-pointwise.{comp}.{spec.get('norm', 'abs')}")
            want = fd.run_metric(r, f"measure.{name}")
            if not s or not s["y"] or want is None or spec.get("over") not in ("max", "final"):
                continue
            got = max(s["y"]) if spec["over"] == "max" else s["y"][-1]
            expect(f"{c['id']} {r['method']} h={r['dt']:g} measure.{name} from its series", got,
                   want)


def check_half_trace(c: Any, ser: Any) -> None:
    """F Fig 3.4's drawn half-trace error over h⁴ at h = 0.01 agrees with the report's fitted
    coefficient (trace-taylor.h4_coeff, Richardson at 0.01 and 0.02) to the O(h) remainder."""
    for m, d in fd.half_trace_data(c, ser).items():
        h, e = min(d["points"], key=lambda p: abs(math.log(p[0] / 0.01)))
        if d["c"]:
            expect(f"{c['id']} {m} half-trace error / h^4 at h = {h:.3g}", e / h ** 4, d["c"],
                   rtol=0.05)


def main() -> Any:
    report_dir = sys.argv[1]
    report, series = fd.load(report_dir)
    if not series:
        print(f"{report_dir}: no series files (run with --figures)", file=sys.stderr)
        return 2
    for c in report["cases"]:
        ser = series.get(c["id"])
        if ser is None:
            if fd.case_figure_kinds(c) != set():  # "figures": false keeps none
                problems.append(f"{c['id']}: no series file")
            continue
        for r, sr in zip(c["runs"], ser["runs"]):
            if (r["method"], r["dt"]) != (sr["method"], sr["dt"]):
                problems.append(f"{c['id']}: series runs out of order")
                break
            check_run(c["id"], r, sr["series"])
        check_orders(c)
        check_stability(c, ser)
        check_measure_series(c, ser)
        check_half_trace(c, ser)
    check_figures(report_dir, report)
    manifest_path = os.path.join(report_dir, "figures", "manifest.json")
    if os.path.exists(manifest_path):
        with open(manifest_path) as f:
            check_claims(report, json.load(f))
    for p in problems:
        print("DISAGREE", p)
    print(f"test_figure_data: {compared} comparisons, {len(problems)} disagreements")
    return 1 if problems or compared == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
