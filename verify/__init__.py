"""dampsym's independent Python side: the cross-check of a report (verify.crosscheck), the case
files it reads (verify/cases), and its tests (verify/tests, pytest).  Run from the source tree's
root as `/usr/bin/python3 -m verify.crosscheck REPORT.json`."""
