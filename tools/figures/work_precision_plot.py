#!/usr/bin/python3
"""Draws the work-precision figure (docs/benchmarks.md "Work-precision") from the data written by
bench/work_precision.py.

    /usr/bin/python3 tools/figures/work_precision_plot.py DATA_JSON --out FIGURE.png

Exit status: 0; 2 bad input (one line naming the file and the key); 3 an output that cannot be
written."""

import argparse
import sys
from typing import List, Optional

from dampfig import safeio as sio
from dampfig import workprecision as wp


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("data")
    ap.add_argument("--out", required=True)
    a = ap.parse_args(argv)
    try:
        wp.draw(wp.load(a.data), a.out)
    except sio.InputProblem as e:
        print(f"work_precision_plot.py: {e}", file=sys.stderr)
        return 2
    except sio.OutputProblem as e:
        print(f"work_precision_plot.py: {e}", file=sys.stderr)
        return 3
    return 0


if __name__ == "__main__":
    sys.exit(main())
