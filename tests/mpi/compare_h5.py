#!/usr/bin/python3
"""Compares two HDF5 files dataset by dataset, byte for byte (issue 19 item 5).

Usage: compare_h5.py SINGLE SHARDED [--ignore NAME ...]
Every dataset of either file must be in both, with the same dtype, shape and bytes; a dataset
whose last path component is in --ignore (a wall time) is compared by shape and dtype only.
Exit 0 when equal, 1 with one line per difference otherwise.
"""
import sys

import h5py
import numpy as np


def datasets(f):
    out = {}
    f.visititems(lambda name, obj: out.__setitem__(name, obj) if isinstance(obj, h5py.Dataset) else None)
    return out


def main(argv):
    ignore = set()
    files = []
    it = iter(argv[1:])
    for a in it:
        if a == "--ignore":
            ignore.add(next(it))
        else:
            files.append(a)
    if len(files) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    problems = []
    with h5py.File(files[0], "r") as a, h5py.File(files[1], "r") as b:
        da, db = datasets(a), datasets(b)
        for name in sorted(set(da) ^ set(db)):
            problems.append(f"{name}: only in {files[0] if name in da else files[1]}")
        compared = 0
        for name in sorted(set(da) & set(db)):
            x, y = da[name], db[name]
            if x.dtype != y.dtype or x.shape != y.shape:
                problems.append(f"{name}: {x.dtype}{x.shape} vs {y.dtype}{y.shape}")
                continue
            if name.split("/")[-1] in ignore:
                continue
            if np.asarray(x[()]).tobytes() != np.asarray(y[()]).tobytes():
                problems.append(f"{name}: the bytes differ")
            compared += 1
    for p in problems:
        print(p)
    if not problems:
        print(f"identical: {compared} datasets byte for byte ({len(ignore)} names compared by shape only)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
