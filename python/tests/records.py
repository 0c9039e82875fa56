"""Helpers the tests share: a CSV record as the CLI writes it, and a
bit-for-bit comparison of float arrays."""

import csv
import io

import numpy as np


def read_csv_text(text):
    """The columns of a CSV record (`t,acc,vel,disp`) by name, as float arrays."""
    rows = list(csv.reader(io.StringIO(text)))
    cols = np.array([[float(x) for x in r] for r in rows[1:]]).T
    return dict(zip(rows[0], cols))


def same_bits(a, b):
    """Whether two float arrays are the same shape and the same bits."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))
