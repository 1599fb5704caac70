#!/usr/bin/python3
"""Unit tests of the figure helpers (tools/figures/dampfig/figdata.py): min/max decimation keeps every
extreme, the drawn convergence line has the fitted slope and passes through the window's points,
the method styles are fixed, the paper-figure parser. No matplotlib; well under a second."""
from typing import Any, Dict, Set

import json
import math
import os
import random
import unittest

from tools.figures.dampfig import figdata as fd


class Decimation(unittest.TestCase):
    def test_extremes_kept(self) -> None:
        rng = random.Random(1)
        t = [0.01 * i for i in range(100003)]
        y = [math.sin(x) + 1e-3 * rng.gauss(0, 1) for x in t]
        y[777] = 5.0   # a spike
        y[50001] = -7.0
        ot, oy = fd.decimate_minmax(t, y, 1000)
        self.assertLessEqual(len(oy), 2000)
        self.assertEqual(max(oy), 5.0)
        self.assertEqual(min(oy), -7.0)
        self.assertIn(t[777], ot)
        # every bucket's extremes survive, in time order
        per = -(-len(y) // 1000)
        for s in range(0, len(y), per):
            self.assertIn(max(y[s:s + per]), oy)
            self.assertIn(min(y[s:s + per]), oy)
        self.assertEqual(ot, sorted(ot))

    def test_nan_skipped_and_short(self) -> None:
        ot, oy = fd.decimate_minmax([0, 1, 2], [1.0, float("nan"), 3.0], 10)
        self.assertEqual((ot, oy), ([0, 2], [1.0, 3.0]))

    def test_fails_if_extremes_dropped(self) -> None:
        # the check itself can fail: plain subsampling loses the spike
        y = [0.0] * 1000
        y[501] = 1.0
        self.assertNotIn(1.0, y[::10])
        self.assertIn(1.0, fd.decimate_minmax(list(range(1000)), y, 100)[1])


class PixelColumns(unittest.TestCase):
    def test_same_extent_per_column(self) -> None:
        rng = random.Random(2)
        t = [i * 1e-3 for i in range(20001)]
        y = [math.sin(50 * x) + 0.1 * rng.gauss(0, 1) for x in t]
        y[12345] = 9.0
        ot, oy = fd.decimate_columns(t, y, 0.0, 20.0, 700)
        self.assertLessEqual(len(oy), 2 * 701 + 2)
        self.assertEqual(ot, sorted(ot))
        self.assertEqual((ot[0], ot[-1]), (t[0], t[-1]))
        # in every pixel column the kept points span what the full series spans
        cols: Dict[int, Any] = {}
        for a, b in zip(t, y):
            c = int((a - 0.0) * (700 / 20.0))  # as decimate_columns bins
            lo, hi = cols.get(c, (b, b))
            cols[c] = (min(lo, b), max(hi, b))
        kept: Dict[int, Any] = {}
        for a, b in zip(ot, oy):
            c = int((a - 0.0) * (700 / 20.0))  # as decimate_columns bins
            lo, hi = kept.get(c, (b, b))
            kept[c] = (min(lo, b), max(hi, b))
        self.assertEqual(cols, kept)
        self.assertIn(9.0, oy)

    def test_negative_control(self) -> None:
        # plain subsampling to the same size loses the spike: the check above can fail
        y = [0.0] * 20001
        y[12345] = 9.0
        self.assertNotIn(9.0, y[::14])

    def test_short_series_unchanged(self) -> None:
        self.assertEqual(fd.decimate_columns([0, 1, 2], [1.0, float("nan"), 3.0], 0, 2, 700),
                         ([0, 2], [1.0, 3.0]))


class SlopeLine(unittest.TestCase):
    def test_line_has_fitted_slope(self) -> None:
        hs = [0.1, 0.05, 0.025, 0.0125]
        errs = {h: 3.0 * h ** 2 * (1 + 0.01 * i) for i, h in enumerate(hs)}
        line = fd.slope_line(hs, errs, 2.0)
        assert line is not None
        xs, ys = line
        self.assertEqual(xs, [0.0125, 0.1])
        self.assertAlmostEqual(fd.loglog_slope(xs, ys), 2.0, places=12)
        # through the window's points in the log mean: C between the extremes of e/h^2
        c = ys[0] / xs[0] ** 2
        self.assertTrue(min(e / h ** 2 for h, e in errs.items()) <= c
                        <= max(e / h ** 2 for h, e in errs.items()))

    def test_steep_fit_between_close_steps(self) -> None:
        # a stability threshold's two runs at 0.99 h* and 1.01 h* (stress-threshold-csv1-lower):
        # the slope is about -4000 and C = e^{log C} is far beyond the doubles, so C h^slope
        # raised OverflowError and the figure was not drawn; in the log the line runs through
        # both points
        hs = [1.2941001297150938, 1.320243566679035]
        errs = {hs[0]: 8.852771727394599e+36, hs[1]: 3.1e-4}
        p = fd.loglog_slope(hs, [errs[h] for h in hs])
        logc = sum(math.log(errs[h]) - p * math.log(h) for h in hs) / 2
        with self.assertRaises(OverflowError):  # the product form's C alone
            math.exp(logc)
        line = fd.slope_line(hs, errs, p)
        assert line is not None
        for h, e in zip(*line):
            self.assertAlmostEqual(math.log(e), math.log(errs[h]), delta=1e-6)
        case = {"runs": [{"method": "csv1", "dt": h, "status": "ok",
                          "metrics": {"invariants": {"H_gamma": {"max_global_ratio_dev": e}}}}
                         for h, e in errs.items()]}
        fit = fd.metric_ladder_data(case, "invariants.H_gamma.max_global_ratio_dev")["csv1"]["fit"]
        self.assertEqual(fit["line_h"], hs)

    def test_line_beyond_the_doubles_is_left_out(self) -> None:
        errs = {1.0: 1.0, 2.0: 1.0}
        self.assertIsNone(fd.slope_line([1.0, 2.0], errs, 1e6))
        self.assertEqual(fd.fit_line(1e6, [1.0, 2.0], errs), {"slope": 1e6})
        self.assertIn("line_h", fd.fit_line(0.0, [1.0, 2.0], errs))

    def test_loglog_slope(self) -> None:
        self.assertAlmostEqual(fd.loglog_slope([1, 2, 4], [3, 24, 192]), 3.0, places=12)


class Styles(unittest.TestCase):
    def test_fixed_and_distinct(self) -> None:
        self.assertEqual(fd.method_style("csv1"), fd.method_style("csv1"))
        self.assertNotEqual(fd.method_style("csv1")[0], fd.method_style("csv2")[0])
        self.assertEqual(fd.method_style("new-method"), fd.method_style("new-method"))

    @staticmethod
    def pairs_run_together() -> Any:
        """Pairs of methods that some case of verify/cases runs together (they share figures)."""
        cases = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "cases")
        pairs: Set[Any] = set()
        for name in os.listdir(cases):
            if name.endswith(".json"):
                with open(os.path.join(cases, name)) as f:
                    ms = sorted(set(json.load(f).get("methods", [])))
                pairs.update((a, b) for i, a in enumerate(ms) for b in ms[i + 1:])
        return pairs

    def test_methods_run_together_have_distinct_colours(self) -> None:
        # time series are solid lines: colour alone must tell the runs of a panel apart (a panel
        # holds one group of at most fd.GROUP methods of a case, in the case's order)
        self.assertGreater(len(self.pairs_run_together()), 100)
        cases = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "cases")
        for name in os.listdir(cases):
            if name.endswith(".json"):
                with open(os.path.join(cases, name)) as f:
                    ms = [m for m in json.load(f).get("methods", []) if isinstance(m, str)]
                st = fd.case_styles(ms)
                for group in fd.groups(ms):
                    cols = [st[m][0] for m in group]
                    for i, a in enumerate(cols):
                        for b in cols[i + 1:]:
                            self.assertGreaterEqual(fd.lab_distance(a, b), 25, (name, group))
        self.assertEqual(len({v for v in fd.STYLES.values()}), len(fd.STYLES))

    def test_loaded_methods_get_distinct_colours_in_a_case(self) -> None:
        # methods loaded from files or plugins are not in STYLES: their hashed colour may be a
        # built-in's or another loaded method's; within one group of a case they are moved apart
        loaded = ["rk4-file", "stormer-verlet-file", "plugin-csv1", "my-method", "other", "x1",
                  "x2", "x3"]
        for methods in (["csv1", "rk4", "cimp"] + loaded, loaded, ["rk4-file", "rk4"]):
            st = fd.case_styles(methods)
            self.assertEqual(set(st), set(methods))
            for group in fd.groups(methods):
                cols = [st[m][0] for m in group]
                for i, a in enumerate(cols):
                    for b in cols[i + 1:]:
                        self.assertGreaterEqual(fd.lab_distance(a, b), 25, (methods, a, b))
            for m in methods:  # markers and line styles are fixed
                self.assertEqual(st[m][1:], fd.method_style(m)[1:])
        # the same case gives the same styles
        self.assertEqual(fd.case_styles(["csv1", "my-method"]), fd.case_styles(["csv1", "my-method"]))

    def test_negative_control(self) -> None:
        # the old palette's glifrk2 (#9467bd) and gauss3 (#756bb1), run together by the B Fig 3.3
        # cases, are 15 apart: the check above would catch them
        self.assertLess(fd.lab_distance("#9467bd", "#756bb1"), 25)
        self.assertLess(fd.lab_distance("#9467bd", "#9467be"), 1)

    def test_paper_figure(self) -> None:
        self.assertEqual(fd.paper_figure({"source": "F Figs 4.6, 4.7, F(4.4)"}), "F Figs 4.6, 4.7")
        self.assertEqual(fd.paper_figure({"source": "HLW I.2, Fig 1.2 (pendulum)"}), "HLW Fig 1.2")
        self.assertEqual(fd.paper_figure({"source": "conventions §2"}), "")


class Png(unittest.TestCase):
    """figdata.encode_png, read back by Pillow (the reader matplotlib itself uses)."""

    def decode(self, data: Any) -> Any:
        import io
        from PIL import Image
        im = Image.open(io.BytesIO(data))
        im.load()
        return im

    def test_round_trip(self) -> None:
        rng = random.Random(7)
        for channels, mode in ((3, "RGB"), (4, "RGBA")):
            for w, h in ((1, 1), (5, 3), (64, 17)):
                pixels = bytes(rng.randrange(256) for _ in range(w * h * channels))
                im = self.decode(fd.encode_png(pixels, w, h, channels))
                self.assertEqual((im.mode, im.size), (mode, (w, h)))
                self.assertEqual(im.tobytes(), pixels)

    def test_negative_control(self) -> None:
        pixels = bytes(range(48))
        data = bytearray(fd.encode_png(pixels, 4, 4, 3))
        self.assertNotEqual(self.decode(fd.encode_png(bytes(48), 4, 4, 3)).tobytes(), pixels)
        data[-20] ^= 0xFF  # inside the compressed data: the CRC (or zlib) no longer matches
        with self.assertRaises(Exception):
            self.decode(bytes(data))
        with self.assertRaises(ValueError):
            fd.encode_png(pixels, 4, 5, 3)  # 48 bytes are not 4 x 5 RGB pixels
        with self.assertRaises(ValueError):
            fd.encode_png(pixels, 12, 1, 4 - 2)


if __name__ == "__main__":
    unittest.main()
