"""dampsym's figures (docs/reports.md "Figures"): figdata (what each figure draws, without
matplotlib), styles, papers (what each paper figure shows), render (the drawing context), the
figure kinds (draw_conv, draw_series, draw_space) and cli (the command line plot.py runs)."""
