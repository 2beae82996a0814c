#!/usr/bin/env python3
"""Compare two fixture folders numerically; exit 1 with a readable list of differences.

Structure (keys, list lengths, strings, booleans, null vs value) must match exactly.
Numbers must agree to REL_TOL relative (+ ABS_TOL absolute): the generator is deterministic
(seeded numpy, single-threaded numpy arithmetic, pinned wheels), so a regeneration on the
same wheels reproduces the files bit for bit; the slack only absorbs a different CPU's libm or
manifold3d choosing a different triangle order (libigl then recomputes the same t from a
co-planar triangle, differing in the last few bits). Anything larger is a real change.
"""
import json
import math
import os
import sys

REL_TOL = 1e-9
ABS_TOL = 1e-12


def walk(a, b, path, out):
    if len(out) > 50:
        return
    if isinstance(a, bool) or isinstance(b, bool) or a is None or b is None or isinstance(a, str):
        if a != b:
            out.append(f"{path}: {a!r} != {b!r}")
        return
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        if math.isnan(a) and math.isnan(b):
            return
        if not abs(a - b) <= ABS_TOL + REL_TOL * max(abs(a), abs(b)):
            out.append(f"{path}: {a!r} != {b!r} (diff {abs(a - b):.3e})")
        return
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            out.append(f"{path}: keys differ: {sorted(set(a) ^ set(b))}")
            return
        for k in a:
            if path == "" and k == "generator":
                continue
            walk(a[k], b[k], f"{path}.{k}", out)
        return
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: length {len(a)} != {len(b)}")
            return
        for i, (x, y) in enumerate(zip(a, b)):
            walk(x, y, f"{path}[{i}]", out)
        return
    out.append(f"{path}: type {type(a).__name__} != {type(b).__name__}")


def main():
    committed, fresh = sys.argv[1], sys.argv[2]
    names_c = sorted(f for f in os.listdir(committed) if f.endswith(".json"))
    names_f = sorted(f for f in os.listdir(fresh) if f.endswith(".json"))
    failed = False
    if names_c != names_f:
        print(f"fixture files differ: committed {names_c}, regenerated {names_f}")
        failed = True
    for name in sorted(set(names_c) & set(names_f)):
        with open(os.path.join(committed, name)) as fa, open(os.path.join(fresh, name)) as fb:
            out = []
            walk(json.load(fa), json.load(fb), "", out)
        if out:
            failed = True
            print(f"{name}: {len(out)}{'+' if len(out) > 50 else ''} differences, first ones:")
            for line in out[:20]:
                print("   ", line)
        else:
            print(f"{name}: identical within {REL_TOL:g} relative")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
