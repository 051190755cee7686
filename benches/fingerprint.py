"""Fingerprints of our sets in a results file, in the one format tests/fingerprints.rs
reads: the commit the file was made at, the command that remakes the file, and per cell
the `stillpoint` command that made the set measured there with the SHA-256 of the set's
coordinates (row-major, little-endian f64). The test remakes the cheap cells through the
library's `Request`, as the command line does, and fails when the hashes differ.

    fingerprint: generate -n 16 -s 2 sha256:<64 hex digits>
"""

import argparse
import hashlib
import json
import os
import subprocess
import sys
import tempfile

import numpy as np


def digest(x):
    """SHA-256 of the coordinates of x (n × s) as row-major little-endian f64."""
    return hashlib.sha256(np.ascontiguousarray(x, dtype="<f8").tobytes()).hexdigest()


def line(command, x):
    """One cell: `command` is the `stillpoint` subcommand and options that made x,
    without the output options (`-o`, `-q`)."""
    return f"fingerprint: {command} sha256:{digest(x)}"


def commit():
    """The commit the measured binary was built from (HEAD of the working tree)."""
    return subprocess.run(["git", "rev-parse", "HEAD"], check=True, capture_output=True,
                          text=True).stdout.strip()


def section(made_at, remake, lines, note=""):
    """The Markdown section that ends a results file: the commit `made_at` (taken when
    the run started), the remake command and one fingerprint per cell, indented as a
    code block so that each line reads verbatim."""
    out = ["## Fingerprints", "",
           "The commit these figures were made at, the command that remakes this file, and "
           "for each cell the command that made our set with the SHA-256 of its "
           "coordinates (row-major little-endian f64). `cargo test --release -p "
           "stillpoint --test fingerprints` remakes the cheap cells and fails when what "
           "ships no longer makes these sets." + (" " + note if note else ""), "",
           f"    commit: {made_at}", f"    remake: {remake}"]
    out += ["    " + ln for ln in lines]
    return out + [""]


def verify_large_n(out, max_n, binary):
    """Fingerprints for a large_n.json made before the benchmark recorded them: each
    cell's default sets (seeds 1-3) are made again and kept only where their relative
    errors on the cell's Genz instances equal the stored ones bit for bit, so the hash
    is that of the set the file measured. Rewrites large_n.json and large_n.md."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import large_n

    path = os.path.join(out, "large_n.json")
    with open(path) as fh:
        data = json.load(fh)
    kept, refused = 0, []
    above = any(c["n"] > max_n for c in data["cells"].values())
    with tempfile.TemporaryDirectory() as tmp:
        for key, cell in sorted(data["cells"].items(), key=lambda kv: (kv[1]["s"], kv[1]["n"])):
            rec = cell["methods"].get("default")
            if rec is None or cell["n"] > max_n or "sha256" in rec:
                continue
            inst, exact = large_n.instances(cell["s"], cell.get("instances", 16))
            _, _, _, hashes = large_n.run_default(binary, cell["n"], cell["s"], rec["seeds"],
                                                  tmp, 3600)
            errs = [large_n.relative_errors(np.load(os.path.join(
                tmp, f"default-s{cell['s']}-n{cell['n']}-seed{k}.npy")), inst, exact).tolist()
                for k in rec["seeds"]]
            for k in rec["seeds"]:
                os.remove(os.path.join(tmp, f"default-s{cell['s']}-n{cell['n']}-seed{k}.npy"))
            if errs == rec["errors"]:
                rec["sha256"] = hashes
                kept += 1
            else:
                refused.append(key)
            print(key, "same errors" if errs == rec["errors"] else "DIFFERENT", flush=True)
    # A later pass (a larger --max-n) adds its sentence to the note of the earlier ones.
    earlier = data.get("fingerprint_note", "")
    data["fingerprint_note"] = (earlier + " " if earlier else "") + (
        f"The fingerprints were added later (`python3 benches/fingerprint.py --large-n "
        f"{out} --max-n {max_n}`): each cell's sets were made again at commit {commit()[:7]} "
        "and kept only where their errors on the cell's instances equal the stored ones bit "
        f"for bit ({kept} cells)"
        + (f"; cells above {max_n} points" if above else "")
        + (f"{' and' if above else ';'} {', '.join(refused)}, whose sets changed,"
           if refused else "")
        + (" have none." if above or refused else "."))
    large_n.save_json(path, data)
    with open(os.path.join(out, "large_n.md"), "w") as fh:
        fh.write(large_n.report(data, data["runs"][-1]["binary_sha256"]))
    return kept, refused


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--large-n", required=True, help="a large_n.py output folder")
    ap.add_argument("--max-n", type=int, default=100000)
    ap.add_argument("--bin", default="target/release/stillpoint")
    a = ap.parse_args()
    print(verify_large_n(a.large_n, a.max_n, os.path.abspath(a.bin)))
