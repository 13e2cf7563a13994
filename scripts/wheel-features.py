#!/usr/bin/env python3
"""Check that a build of the Python extension alone (what `pip wheel ./python` compiles)
turns on the same features in every dependency as `cargo test --workspace` does.

Cargo compiles a dependency again for every different feature set, and a change deep in
the graph (say `log` with `std`) reaches every crate above it: without the same features
the wheel's build in scripts/test.sh compiled burn and the rest a second time (7 minutes
of CI). python/Cargo.toml lists the features the other members and the dev-dependencies
turn on; this script says which are missing or no longer needed, package by package.

Usage: scripts/wheel-features.py        (exit status 1 when the feature sets differ)
"""
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def feature_sets(*args):
    """{package: {its feature lists}} over the units `cargo tree` shows (a package built for
    the host and for the target can appear with two lists)."""
    command = ["cargo", "tree", *args, "-f", "{p}|{f}", "--prefix", "none"]
    run = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"wheel-features: `{' '.join(command)}` failed:\n{run.stderr}")
    out = run.stdout
    sets = defaultdict(set)
    for line in out.splitlines():
        line = line.replace(" (*)", "").strip()
        if "|" in line:
            package, features = line.split("|", 1)
            sets[package].add(features)
    return sets


def main():
    workspace = feature_sets("--workspace", "-e", "normal,build,dev")
    wheel = feature_sets("-p", "yokai-python", "-e", "normal,build")
    differ = {p: f for p, f in wheel.items() if not f <= workspace.get(p, set())}
    if not differ:
        print(f"wheel-features: the extension's {len(wheel)} packages build with the "
              "workspace's features")
        return 0
    print("wheel-features: a build of the Python extension alone turns on other features than "
          "`cargo test --workspace` in these packages, so `pip wheel ./python` compiles them and "
          "everything above them again. Set them in python/Cargo.toml (the list under "
          "\"Not used by this crate's code\"):", file=sys.stderr)
    for package, features in sorted(differ.items()):
        want = sorted(workspace.get(package, {"(not in the workspace's graph)"}))
        print(f"  {package}: the extension alone {sorted(features)}, the workspace {want}",
              file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
