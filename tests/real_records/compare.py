"""Poise's diagnosis of each real record (tests/data/real/<name>/) beside its oracle: an ordinary
least-squares fit that knows the orders (oracle.py, numpy only, written independently of Poise;
SOURCE says what each record is). The records' signals are currents: Poise is run with
K_T = 1 N*m/A, so its torques in mN*m are the oracle's currents in mA.

    /usr/bin/python3 tests/real_records/compare.py [build/poise]    # the table the README shows

Used by test_real_records.py."""
import json
import os
import subprocess
import sys

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
REAL = os.path.join(SRC, "tests", "data", "real")


def records():
    return sorted(d for d in os.listdir(REAL) if os.path.isfile(os.path.join(REAL, d, "poise_args")))


def poise_args(name):
    with open(os.path.join(REAL, name, "poise_args"), encoding="utf-8") as f:
        return [line.rstrip("\n") for line in f if line.strip() and not line.startswith("#")]


def diagnose(exe, name):
    args = poise_args(name)
    r = subprocess.run([exe, "diagnose-record", *args, "--json"], cwd=os.path.join(REAL, name), capture_output=True,
                       text=True, timeout=600)
    if r.returncode != 0:
        raise RuntimeError(f"poise diagnose-record {' '.join(args)} exited {r.returncode}: {r.stderr[-2000:]}")
    return json.loads(r.stdout)


def oracle(name):
    with open(os.path.join(REAL, name, "oracle.json"), encoding="utf-8") as f:
        return json.load(f)["fit"]


def comparison(exe, name):
    """Per record: the oracle's orders (A) and Poise's (A), the Coulomb half-difference of each,
    the residual RMS of each."""
    p, o = diagnose(exe, name), oracle(name)
    poise_orders = {m["order"]: m["amplitude_mNm"]["value"] * 1e-3 for m in p.get("cogging_map", [])}
    oracle_orders = {m["order"]: m["amplitude"] for m in o["orders"]}
    coulomb = o.get("coulomb", {})
    return {
        "name": name,
        "motion": p.get("motion", {}).get("description", ""),
        "poise_orders": poise_orders,
        "oracle_orders": oracle_orders,
        "poise_coulomb": p["coulomb_mNm"]["value"] * 1e-3 if "coulomb_mNm" in p else None,
        "oracle_coulomb": coulomb.get("c1_coulomb_half_difference") if coulomb.get("identifiable") else None,
        "poise_rmse": p["rmse_after_mNm"] * 1e-3,
        "oracle_rmse": o["rms_residual_full_fit"],
        "constant_rmse": o["rms_residual_constant_only"],
    }


def table(exe):
    rows = ["| record | motion (Poise) | order: Poise / oracle amplitude, A | Coulomb, A: Poise / oracle | "
            "residual RMS, A: mean only, Poise, oracle |", "| --- | --- | --- | --- | --- |"]
    for name in records():
        c = comparison(exe, name)
        largest = max(c["oracle_orders"].values())
        cells = []
        for order, amp in sorted(c["oracle_orders"].items(), key=lambda kv: -kv[1]):
            mine = c["poise_orders"].get(order)
            mark = "" if amp >= 0.1 * largest else " (below 10%)"
            cells.append(f"{order}: {mine:.3f} / {amp:.3f}{mark}" if mine is not None else f"{order}: not found / {amp:.3f}{mark}")
        extra = sorted(set(c["poise_orders"]) - set(c["oracle_orders"]))
        if extra:
            cells.append("Poise also: " + ", ".join(f"{k} ({c['poise_orders'][k]:.3f})" for k in extra))
        coulomb = (f"{c['poise_coulomb']:.3f} / {c['oracle_coulomb']:.3f}" if c["oracle_coulomb"] is not None
                   else "one direction: not identifiable")
        rows.append(f"| `{name}` | {c['motion']} | {'; '.join(cells)} | {coulomb} | "
                    f"{c['constant_rmse']:.3f}, {c['poise_rmse']:.3f}, {c['oracle_rmse']:.3f} |")
    return "\n".join(rows)


if __name__ == "__main__":
    print(table(sys.argv[1] if len(sys.argv) > 1 else os.path.join(SRC, "build", "poise")))
