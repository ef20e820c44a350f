"""What every part of the report reads: the pipeline's predictions and scores, and numbers as the report prints them."""
import csv
import math
import os

import numpy as np



# The source tree: deploy/odonata_report/ is two levels below it.
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DT = 0.01  # s per sample: the pipeline runs at 100 Hz
from odonata_compare import DIVERGED_FIT  # noqa: E402  (one cut for "diverges" everywhere)
DIVERGED_NDEI = 1 - DIVERGED_FIT / 100
# Fuzzy and ARX closer than this many FIT points are called equal: below it the difference is
# within what a different seed or excitation moves.
EQUAL_POINTS = 1.0
POOR_FIT = 50.0  # % below which a model is too poor for its agreement with another to mean anything
MODE_WORDS = {"free_run": "in free run", "one_step": "in one-step prediction"}


def read_predictions(path, output=None):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    cols = {k: np.array([float(r[k]) for r in rows]) for k in rows[0].keys()} if rows else {}
    return cols


def live_scores(scores, output):
    """Accuracy of the frozen identifier's live predictions in the last (validation) run, as
    odonata-monitor's scoreboard scores them (odonata-logger export --scores, from the lossless
    log): the report computes no metric of its own."""
    o = scores["outputs"][output]
    return {"one_step": o["one_step"], "free_run": o["free_run"]}


def _finite(v):
    return v if isinstance(v, (int, float)) and math.isfinite(v) else None


def fmt(v, digits=2):
    if _finite(v) is None:
        return "–"
    if v < DIVERGED_FIT:
        return "diverges"
    return f"{v:.{digits}f}"
