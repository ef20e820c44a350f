"""Report of the main job: summary table (terminal, Markdown, JSON), plots and one HTML page.

A package of one concern per module: common (reading and printing numbers), verdicts (what a
model is said to be against ARX), tables, plots, page. What run-experiments and the tests use is
re-exported here. fit_verdict and fit_page are the page of one odonata-fit run (fit_report.py).
"""
from .common import live_scores, read_predictions
from .tables import COLUMNS, markdown, table_rows, terminal_table
from .plots import dominant_rules, make_plots, plot_membership, rule_shares
from .page import page, write_report

__all__ = ["COLUMNS", "dominant_rules", "live_scores", "make_plots", "markdown", "page",
           "plot_membership", "read_predictions", "rule_shares", "table_rows", "terminal_table",
           "write_report"]
