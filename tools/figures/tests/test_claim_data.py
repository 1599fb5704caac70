"""The data each figure draws for its claim (dampfig.figdata, no matplotlib): the claim's metric
chosen from the checks, its points and slope, the ratio of two methods, the half-trace error, the
quantities a series carries, and the coverage test that every claim metric is drawn."""

import math
from typing import Any, Dict, List, Tuple

from dampfig import figdata as fd

Json = Dict[str, Any]


def ladder_case(theta: Dict[str, List[float]], final: Dict[str, List[float]]) -> Json:
    """A B Fig 3.1-like case: two methods on a ladder, the claim on measure.theta_mean_abs."""
    hs = [0.02, 0.01, 0.005, 0.0025]
    runs = [{"method": m, "dt": h, "status": "ok",
             "metrics": {"measure": {"theta_mean_abs": theta[m][i]},
                         "error": {"final_abs": final[m][i]}}}
            for m in theta for i, h in enumerate(hs)]
    checks = [{"name": "ETD below IF", "metric": "measure.theta_mean_abs", "form": "ratio",
               "method": "etd / if", "methods": ["etd", "if"], "op": "le", "expected": 0.9,
               "dt": h, "inputs": [{"dt": h, "value": theta["etd"][i] / theta["if"][i]}]}
              for i, h in enumerate(hs)]
    checks.append({"name": "ETD's advantage grows", "metric": "measure.theta_mean_abs",
                   "form": "ratio", "method": "etd / if", "methods": ["etd", "if"], "op": "gt",
                   "expected": 0.2, "inputs": [{"dt": h, "value": theta["etd"][i] / theta["if"][i]}
                                               for i, h in enumerate(hs)]})
    return {"id": "x", "runs": runs, "checks": checks, "dt_ladder": hs,
            "measures": {"theta_mean_abs": {"component": "q", "norm": "abs", "over": "mean"}}}


def first_order(c: float) -> List[float]:
    return [c * h for h in (0.02, 0.01, 0.005, 0.0025)]


def test_claim_metric_is_the_checks_not_the_final_error() -> None:
    case = ladder_case({"if": first_order(3.0), "etd": first_order(1.0)},
                       {"if": [1, 2, 3, 4], "etd": [4, 3, 2, 1]})
    assert fd.claim_ladder_metric(case) == "measure.theta_mean_abs"
    # a case whose checks read the final error only: no claim metric (the final error is drawn)
    case["checks"] = [{"name": "order", "metric": "error.final_abs"}]
    assert fd.claim_ladder_metric(case) is None
    # a metric present at one step size only is not a ladder
    case["checks"] = [{"name": "m", "metric": "measure.theta_mean_abs"}]
    for r in case["runs"][1:]:
        r["metrics"]["measure"] = {}
    assert fd.claim_ladder_metric(case) is None


def test_ladder_points_and_slope() -> None:
    case = ladder_case({"if": first_order(3.0), "etd": [2e-4 * h ** 0 for h in range(4)]},
                       {"if": [1] * 4, "etd": [1] * 4})
    d = fd.metric_ladder_data(case, "measure.theta_mean_abs")
    assert [p[0] for p in d["if"]["points"]] == [0.0025, 0.005, 0.01, 0.02]
    assert abs(d["if"]["fit"]["slope"] - 1.0) < 1e-12
    assert abs(d["etd"]["fit"]["slope"]) < 1e-12
    # a planted 1e-6 relative defect in one point moves the slope visibly
    case["runs"][0]["metrics"]["measure"]["theta_mean_abs"] *= 1 + 1e-6
    d2 = fd.metric_ladder_data(case, "measure.theta_mean_abs")
    assert abs(d2["if"]["fit"]["slope"] - 1.0) > 1e-8


def test_ratio_check_data() -> None:
    case = ladder_case({"if": first_order(3.0), "etd": [1e-3, 4e-4, 1e-4, 2e-5]},
                       {"if": [1] * 4, "etd": [1] * 4})
    r = fd.ratio_check_data(case)
    assert r is not None and r["metric"] == "measure.theta_mean_abs"
    assert [h for h, _ in r["points"]] == [0.0025, 0.005, 0.01, 0.02]
    assert math.isclose(r["points"][-1][1], 1e-3 / 0.06)
    assert len(r["bounds"]) == 4 and all(b[1] == 0.9 for b in r["bounds"])
    case["checks"] = [k for k in case["checks"] if "dt" in k]  # one h per check: no ladder ratio
    assert fd.ratio_check_data(case) is None


def test_run_metric_paths() -> None:
    run = {"metrics": {"invariants": {"e.g.dotted": {"max_step_res": 2.0}},
                       "error": {"final_abs": float("nan")}, "flag": {"ok": True}}}
    assert fd.run_metric(run, "invariants.e.g.dotted.max_step_res") == 2.0
    assert fd.run_metric(run, "error.final_abs") is None  # not finite
    assert fd.run_metric(run, "flag.ok") is None  # a verdict, not a number
    assert fd.run_metric(run, "invariants.missing.x") is None


def test_half_trace_data() -> None:
    case = {"method_metrics": {"cimp": {"trace-taylor": {"h4_coeff": 0.0588,
                                                          "h4_coeff_expected": 0.0588}},
                               "rk3": {"stability-sweep": {}}}}
    ser = {"stability_map": {"cimp": {"half_trace_error": {"omega": 1.0, "gamma": 0.4,
                                                           "h": [0.1, 0.2], "error": [0.0, 1e-4]}}}}
    d = fd.half_trace_data(case, ser)
    assert list(d) == ["cimp"] and d["cimp"]["points"] == [[0.2, 1e-4]]  # 0 cannot be drawn
    assert d["cimp"]["c"] == 0.0588 and fd.half_trace_data(case, None) == {}


def test_series_quantities_name_the_measures() -> None:
    case = {"measures": {"u_abs_max": {"component": "q", "over": "max"},
                         "u_rel_max": {"component": "q", "norm": "rel", "over": "max"},
                         "H_err": {"quantity": "energy-error", "over": "max"},
                         "H_growth": {"quantity": "energy-error", "over": "growth"}}}
    assert fd.series_quantities(case, "measure-pointwise.q.abs") == \
        ["measure-pointwise.q.abs", "measure.u_abs_max"]
    assert fd.series_quantities(case, "measure-pointwise.q.rel")[1:] == ["measure.u_rel_max"]
    assert fd.series_quantities(case, "measure-pointwise.energy.abs")[1:] == \
        ["measure.H_err", "measure.H_growth"]
    assert fd.series_quantities(case, "energy.error")[1:] == ["measure.H_err", "measure.H_growth"]
    assert fd.growth_in_time(case) and not fd.growth_in_time({"measures": {}})


def test_every_claim_metric_drawn() -> None:
    case = {"checks": [{"metric": "measure.u_rel_max"}, {"metric": "invariants.casimir.max_step_res"},
                       {"metric": "momentum.linear.max_law_res"}]}
    drawn = ["measure-pointwise.q.rel", "measure.u_rel_max", "invariants.casimir.step_res",
             "momentum.linear.law_res"]
    assert fd.missing_claim_metrics(case, drawn) == []
    # planted: the relative error not drawn, the energy invariant instead of the Casimir's
    assert fd.missing_claim_metrics(case, drawn[2:]) == ["measure.u_rel_max"]
    assert fd.missing_claim_metrics(case, ["invariants.energy.step_res", "momentum.linear.x",
                                           "measure.u_rel_max"]) == \
        ["invariants.casimir.max_step_res"]
    assert fd.metric_family("trace-taylor.h4_coeff_rel_err") == "trace-taylor"


def momentum_case(linear: Dict[str, Any]) -> Tuple[Dict[str, Any], Dict[str, Any]]:
    """A case of two runs whose series hold both momenta, the linear one reported as `linear`."""
    law = {"max_law_res": 1e-16, "scale": "sum_i |q_i| |p_i|"}
    runs = [{"method": m, "dt": 0.1, "metrics": {"momentum": {"angular": law, "linear": linear}}}
            for m in ("a", "b")]
    s = {"t": [0.0, 0.1], "y": [1e-16, 2e-16]}
    series = {"momentum.linear.law_res": s, "momentum.linear.factor": s,
              "momentum.angular.law_res": s}
    return {"runs": runs}, {"runs": [{"method": r["method"], "dt": 0.1, "series": series}
                                     for r in runs]}


def test_series_panels_leave_out_a_momentum_without_a_law() -> None:
    # a body in a central field: the report has a reason instead of the linear residuals
    case, ser = momentum_case({"reason": "no linear momentum law"})
    assert fd.lawless_momenta(case) == {"linear"}
    assert [p[0] for p in fd.series_panels(ser, case)] == ["momentum.angular.law_res"]
    # the N-body system (both laws): both drawn; without the case, every series is drawn
    both = ["momentum.linear.law_res", "momentum.linear.factor", "momentum.angular.law_res"]
    case, ser = momentum_case({"max_law_res": 1e-15, "scale": "sum_i |p_i|"})
    assert fd.lawless_momenta(case) == set()
    assert [p[0] for p in fd.series_panels(ser, case)] == both
    assert [p[0] for p in fd.series_panels(ser)] == both
    # a run without metrics (it failed) says nothing: nothing is left out
    assert fd.lawless_momenta({"runs": [{"method": "a", "metrics": {}}]}) == set()
