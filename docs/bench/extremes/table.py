#!/usr/bin/env python3
"""The Accuracy page's three tables of issue 37 from measure.sh's CSVs: before → after
(SwiftShader, the same code as after). Usage, from this folder:

    python3 table.py before.csv after.csv swiftshader.csv > tables.md
"""
import csv
import sys

METRICS = ("depth_p99", "id", "coverage", "normal_p99_deg")
HEAD = "depth p99 (of the radius) | wrong glyph | coverage | normal p99 (°)"


def load(path):
    with open(path, newline="") as f:
        return {(r["field"], r["view"], r["method"], r["glyph"]): r for r in csv.DictReader(f)}


def fmt(x):
    if x == 0:
        return "0"
    return "%.2g" % x if x >= 0.1 else "%.1e" % x


def cells(rows, keys):
    """One cell per metric: the worst over `keys` in each table, before → after (swiftshader)."""
    out = []
    for m in METRICS:
        worst = [max(float(t[k][m]) for k in keys) for t in rows]
        out.append("%s → %s (%s)" % tuple(fmt(w) for w in worst))
    return " | ".join(out)


def main():
    rows = [load(p) for p in sys.argv[1:4]]
    after = rows[1]
    fields = ["discs", "needles", "mixed"]
    views = ["default", "zoom6", "ortho+x"]
    print("| field | view | method | %s |" % HEAD)
    print("|---|---|---|---|---|---|---|")
    for f in fields:
        for v in views:
            for m in ("gumhold", "sigg"):
                print("| %s | %s | %s | %s |" % (f, v, m, cells(rows, [(f, v, m, "ellipsoid")])))
    print()
    print("Cylinders, capsules and superquadrics, worst of the three and of both ray casters:")
    print()
    print("| field | view | %s |" % HEAD)
    print("|---|---|---|---|---|---|")
    for f in fields:
        for v in views:
            keys = [
                (f, v, m, g)
                for m in ("gumhold", "sigg")
                for g in ("cylinder", "capsule", "superquadric")
            ]
            print("| %s | %s | %s |" % (f, v, cells(rows, keys)))
    print()
    print("grid40 at 1024×768 (the demo as `render` draws it, Gumhold's default path and Sigg's):")
    print()
    print("| view | kind | method | %s |" % HEAD)
    print("|---|---|---|---|---|---|---|")
    for v in ("default", "zoom4", "ortho"):
        for g in ("ellipsoid", "cylinder", "superquadric"):
            for m in ("gumhold", "sigg"):
                key = ("grid40", v, m, g)
                if key in after:
                    print("| %s | %s | %s | %s |" % (v, g, m, cells(rows, [key])))


if __name__ == "__main__":
    main()
