"""Each experiment's headline, verdict and summary: what the report says of a model against ARX."""


from .common import DIVERGED_FIT, EQUAL_POINTS, MODE_WORDS, POOR_FIT, _finite, fmt

# --- headline and verdict -------------------------------------------------------------------

def headline_mode(s):
    """Free run where the loop does not integrate: a model of the dynamics is used to simulate, and
    free run is where a wrong structure shows. An integrator's free run drifts with any bias, so
    one-step there; a static map (ny = 0) has no free run, its one-step prediction is its output."""
    if s["integrator"] or (s["validate"].get("free_run") or {}).get("fit") is None:
        return "one_step"
    return "free_run"


def headline(s):
    """Validation FIT % in the headline mode (one unit throughout the report: higher is better)."""
    mode = headline_mode(s)
    return {"metric": f"{mode.replace('_', '-')} FIT %",
            "fuzzy": _finite((s["validate"].get(mode) or {}).get("fit")),
            "arx": _finite((s["arx"].get(mode) or {}).get("fit"))}


def lead(s):
    """The one sentence an experiment opens with: what the model is for, and fuzzy against ARX
    in FIT points."""
    mode = headline_mode(s)
    use = ("one-step prediction (the loop integrates: a long free run drifts for any model)"
           if s["integrator"] else
           "a static map (no output lags)" if mode == "one_step" else
           "simulation (free run over the validation excitation)")
    hl = s["headline"]
    scores = f"fuzzy {fmt(hl['fuzzy'])} %, ARX {fmt(hl['arx'])} %".replace("diverges %", "diverges")
    return (f"{s['output']} from {', '.join(s['inputs'])}, a model for {use}: "
            f"{s['verdict']} ({scores}).")


def _fits(s, mode):
    return (s["validate"].get(mode) or {}).get("fit"), (s["arx"].get(mode) or {}).get("fit")


def _compare(f, a, mode, rules, where=None):
    """(sentence, short) for two FITs that both stayed bounded; `where` words the mode (default
    MODE_WORDS[mode]; fit_report.py's K steps ahead has none there)."""
    d = f - a
    where = where or MODE_WORDS[mode]
    if abs(d) < EQUAL_POINTS:
        # Equal and both poor says nothing about linearity: neither structure fits.
        why = (f"neither model fits well (FIT {f:.0f} % and {a:.0f} %)" if max(f, a) < POOR_FIT
               else "one rule makes the fuzzy model linear, like ARX" if rules == 1
               else "the loop looks linear at these amplitudes")
        return f"fuzzy equals ARX {where} (within {EQUAL_POINTS:g} FIT point): {why}", "equals ARX"
    if d > 0:
        return f"fuzzy beats ARX by {d:+.1f} FIT points {where}", f"beats ARX {d:+.1f}"
    return f"fuzzy loses to ARX by {-d:.1f} FIT points {where}", f"loses {d:+.1f}"


def verdict(s):
    """One line on fuzzy against linear ARX in the headline mode: (sentence, short for the terminal)."""
    mode = headline_mode(s)
    f, a = _fits(s, mode)
    if _finite(f) is None or _finite(a) is None:
        return "no verdict: a validation score is missing", "–"
    where = MODE_WORDS[mode]
    if f < DIVERGED_FIT and a < DIVERGED_FIT:
        text = f"both diverge {where}"
        f1, a1 = _fits(s, "one_step")
        if mode != "one_step" and _finite(f1) is not None and _finite(a1) is not None:
            text += "; " + _compare(f1, a1, "one_step", s["rules"])[0]
        return text, "both diverge"
    if f < DIVERGED_FIT:
        return f"fuzzy loses to ARX: its simulation diverges {where} (ARX FIT {a:.1f} %)", "fuzzy diverges"
    if a < DIVERGED_FIT:
        return f"fuzzy beats ARX: ARX diverges {where} (fuzzy FIT {f:.1f} %)", "ARX diverges"
    return _compare(f, a, mode, s["rules"])


def _delta(s):
    """fuzzy − ARX in FIT points, headline mode; '–' where either diverged."""
    f, a = _fits(s, headline_mode(s))
    if _finite(f) is None or _finite(a) is None or min(f, a) < DIVERGED_FIT:
        return "–"
    return f"{round(f - a, 2) + 0.0:+.2f}"  # + 0.0: no "-0.00"


def _readable(r):
    """The model's readable form (odonata-fit --rules, docs/identifier.md §7.5) with its validation
    FIT beside the model's, or None when the fit report has none."""
    rd = r.get("readable")
    scores = r.get("baselines", {}).get("readable", {}).get("validate")
    if not rd or not scores:
        return None
    return {"rules": rd["rules"], "linear": rd["linear"], "text": rd["text"],
            "validate_one_step_fit": scores["one_step"]["fit"],
            "validate_free_run_fit": (scores.get("free_run") or {}).get("fit")}


# --- summary ---------------------------------------------------------------------------------

def summarise(r):
    v, b = r["validate"], r["baselines"]
    ndei = v["one_step"]["ndei"]
    pers_ndei = b["persistence"]["validate"]["one_step"]["ndei"]
    arx_fit = b["arx"]["validate"]["one_step"]["fit"]
    notes = []
    if r["rules"] == 1:
        notes.append("one rule: the model is a single local linear model (ARX-like); within the selection's "
                     "tolerance the training hold-out does not call for more rules at these amplitudes")
    if r["integrator"]:
        notes.append("integrating loop: free run drifts with any bias, one-step is the meaningful score")
    if v["one_step"]["fit"] is not None and arx_fit is not None and v["one_step"]["fit"] < arx_fit:
        notes.append(f"does not beat linear ARX one-step ({fmt(v['one_step']['fit'])} % vs {fmt(arx_fit)} %)")
    if v.get("free_run", {}).get("fit") is not None and b["arx"]["validate"].get("free_run", {}).get("fit") is not None \
            and v["free_run"]["fit"] < b["arx"]["validate"]["free_run"]["fit"]:
        notes.append("free run worse than ARX's")
    paper_mfs = r["paper"].get("mfs")
    goal_rules = paper_mfs is None or r["rules"] <= paper_mfs
    s = {
        "experiment": r["name"],
        "output": r["preset"]["output"],
        "inputs": r["preset"]["inputs"],
        "entropy_threshold": r["chosen_entropy_threshold"],
        "kappa": r["config"]["kappa"],
        "ny": r["config"]["ny"],
        "nu": r["config"]["nu"],
        "rules": r["rules"],
        "paper": r["paper"],
        "paper_threshold_run": {"entropy_threshold": r["paper_entropy_threshold_run"]["entropy_threshold"],
                                "rules": r["paper_entropy_threshold_run"]["rules"],
                                "validate_one_step_fit": r["paper_entropy_threshold_run"]["validate"]["one_step"]["fit"]},
        "train": {"one_step": r["train"]["one_step"], "free_run": r["train"].get("free_run")},
        "validate": {"one_step": v["one_step"], "free_run": v.get("free_run")},
        "validate_live": r["validate_live"],
        "averaged_output": r.get("averaged_output"),
        "arx": b["arx"]["validate"],
        "persistence": b["persistence"]["validate"],
        "integrator": r["integrator"],
        "goals": {
            "ndei_at_most_half_of_persistence": bool(ndei is not None and pers_ndei is not None and ndei <= 0.5 * pers_ndei),
            "rules_not_more_than_paper": bool(goal_rules),
            "validation_fit_at_least_90": bool(v["one_step"]["fit"] is not None and v["one_step"]["fit"] >= 90),
        },
        "notes": notes,
        "rule_text": r["rule_text"],
        "readable": _readable(r),
    }
    s["headline"] = headline(s)
    s["verdict"], s["verdict_short"] = verdict(s)
    return s
