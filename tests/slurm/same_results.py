"""Exits 0 when two sweep outputs hold the same rows in the same order (CSV and JSON),
ignoring the columns that measure time; else prints the first difference and exits 1."""
import csv
import json
import sys

TIMING = {"wall_time_s", "ms_per_step", "ms_per_step_p90", "springs_per_second",
          "real_time_factor"}


def csv_rows(base):
    with open(base + ".csv", newline="") as stream:
        rows = list(csv.reader(stream))
    keep = [i for i, name in enumerate(rows[0]) if name not in TIMING]
    return [[row[i] for i in keep] for row in rows]


def json_document(base):
    with open(base + ".json") as stream:
        document = json.load(stream)
    for row in document["rows"]:
        for name in TIMING:
            row.pop(name, None)
    return document


def main(local, merged):
    a, b = csv_rows(local), csv_rows(merged)
    if len(a) != len(b):
        print(f"CSV: {len(a) - 1} rows locally, {len(b) - 1} merged")
        return 1
    for line, (x, y) in enumerate(zip(a, b), start=1):
        if x != y:
            print(f"CSV line {line} differs:\n  local  {x}\n  merged {y}")
            return 1
    if json_document(local) != json_document(merged):
        print("JSON documents differ")
        return 1
    print(f"same results: {len(a) - 1} rows, {len(a[0])} columns compared "
          f"(timing columns ignored)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
