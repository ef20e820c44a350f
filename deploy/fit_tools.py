"""The offline tools as the main job calls them (deploy/run-experiments, deploy/beyond_paper.py):
odonata-sim for a preset's three excitations, odonata-fit with a JSON report."""
import json
import os
import subprocess

PHASES = ("train", "select", "validate")


def fit_json(build, args):
    """odonata-fit ARGS --json, its report parsed."""
    out = subprocess.run([os.path.join(build, "services/fit/odonata-fit"), *args, "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def simulate_phases(build, name, seed, duration, folder):
    """Offline copies of the preset's three excitations, at its own rate: training, selection
    (every choice is scored on it) and validation (never used for a choice). Returns
    {phase: path of folder/offline-PHASE.csv}."""
    files = {}
    for phase in PHASES:
        files[phase] = os.path.join(folder, f"offline-{phase}.csv")
        cmd = [os.path.join(build, "services/sim/odonata-sim"), "--preset", name, "--phase", phase,
               "--seed", str(seed), "--output", files[phase]]
        if duration > 0:
            cmd += ["--duration", str(duration)]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return files


def signal_flags(preset, ny=None, nu=None):
    """odonata-fit's --output/--input/--ny/--nu/--delay for the preset (its own order unless given)."""
    flags = ["--output", preset["output"], "--ny", str(preset["ny"] if ny is None else ny),
             "--nu", str(preset["nu"] if nu is None else nu), "--delay", str(preset["delay"])]
    for i in preset["inputs"]:
        flags += ["--input", i]
    return flags
