"""Fingerprints of our sets in a results file, in the one format tests/fingerprints.rs
reads: the commit the file was made at, the command that remakes the file, and per cell
the `stillpoint` command that made the set measured there with the SHA-256 of the set's
coordinates (row-major, little-endian f64). The test remakes the cheap cells through the
library's `Request`, as the command line does, and fails when the hashes differ.

    fingerprint: generate -n 16 -s 2 sha256:<64 hex digits>
"""

import hashlib
import subprocess

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


def section(made_at, remake, lines):
    """The Markdown section that ends a results file: the commit `made_at` (taken when
    the run started), the remake command and one fingerprint per cell, indented as a
    code block so that each line reads verbatim."""
    out = ["## Fingerprints", "",
           "The commit these figures were made at, the command that remakes this file, and "
           "for each cell the command that made our set with the SHA-256 of its "
           "coordinates (row-major little-endian f64). `cargo test --release -p "
           "stillpoint --test fingerprints` remakes the cheap cells and fails when what "
           "ships no longer makes these sets.", "",
           f"    commit: {made_at}", f"    remake: {remake}"]
    out += ["    " + ln for ln in lines]
    return out + [""]
