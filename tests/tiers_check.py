#!/usr/bin/python3
"""Every ctest test is in one tier: labelled `quick` or `long`, never both, never neither.

    tests/tiers_check.py BUILD_DIR
"""
import json
import subprocess
import sys


def main():
    build = sys.argv[1]
    out = subprocess.run(["ctest", "--show-only=json-v1"], cwd=build, capture_output=True, text=True, check=True)
    tests = json.loads(out.stdout)["tests"]
    bad = []
    for t in tests:
        labels = set()
        for p in t.get("properties", []):
            if p["name"] == "LABELS":
                labels |= set(p["value"])
        tiers = labels & {"quick", "long"}
        if len(tiers) != 1:
            bad.append(f"{t['name']}: labels {sorted(labels)}")
    print(f"{len(tests)} tests, {len(bad)} without exactly one tier")
    for line in bad:
        print("  " + line)
    return 1 if bad or not tests else 0


if __name__ == "__main__":
    sys.exit(main())
