#!/usr/bin/python3
"""Draws the figures of a dampsym report directory: the entry point `dampsym plot` and
`dampsym run --figures` run (the package dampfig beside this file does the work; its
cli module documents the arguments and exit statuses).

    /usr/bin/python3 tools/figures/plot.py REPORT_DIR [--jobs N] [--format png|svg|pdf[,...]]"""

import os
import signal
import sys
from types import FrameType
from typing import Optional


def on_stop(sig: int, _frame: Optional[FrameType]) -> None:
    """A signal while matplotlib is being imported (a second): stop quietly, 130/143."""
    os._exit(128 + sig)


if __name__ == "__main__":
    signal.signal(signal.SIGINT, on_stop)
    signal.signal(signal.SIGTERM, on_stop)
    # the script's directory is on sys.path when run as a script: the package imports plainly
    from dampfig.cli import main
    sys.exit(main())
